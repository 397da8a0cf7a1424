// meshfit: stage 1, global deformation of the template onto the curve network (thesis ch. 2).
//
//   coarse  an RBF through the user's pairs moves the whole template (eq. 2.6–2.10);
//   fine    two methods (Fine_level):
//           surface (default): the curves are first embedded in the coarse-deformed surface
//           (each network vertex gets a mesh vertex at its nearest surface point, each segment
//           becomes a chain of edges by stage 2's insertion, while nothing is folded yet), then
//           the embedded vertices are moved onto the curves and the rest of the mesh follows a
//           thin-plate displacement field (Botsch & Sorkine 2008, displacement.h);
//           thesis: every network vertex is paired with its nearest template vertex (§2.1), and
//           a second RBF through those pairs puts each paired template vertex exactly on its
//           network vertex; faces the fine motion would flip (§2.3.1, exact flip counter) are
//           subdivided and the correspondences recomputed until no face flips (§2.3.2).
#ifndef MESHFIT_DEFORM_H
#define MESHFIT_DEFORM_H

#include <meshfit/correspondence.h>
#include <meshfit/curve_network.h>
#include <meshfit/displacement.h>
#include <meshfit/exceptions.h>
#include <meshfit/internal/commit_result.h>
#include <meshfit/internal/stage_support.h>
#include <meshfit/parameters.h>
#include <meshfit/partition.h>
#include <meshfit/rbf.h>
#include <meshfit/registration.h>

#include <CGAL/Named_function_parameters.h>

#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

namespace meshfit {

/// What to do when the curves are denser than the template, so that several network vertices
/// have the same nearest template vertex and all but one lose it.
enum class Curve_density {
  /// Split the template face nearest to each losing network vertex and give it the new vertex:
  /// every network vertex becomes a mesh vertex (the curves are embedded exactly). Default.
  refine,
  /// The thesis's behaviour: the mesh keeps its size and the losers are dropped (reported).
  drop
};

/// How the fine level brings the coarse-deformed template onto the curves.
enum class Fine_level {
  /// Embed the curves in the coarse-deformed surface, then move the embedded vertices onto the
  /// curves with a thin-plate displacement of the whole mesh, and untangle what turned over with
  /// a foldover-free energy (untangle_faces) (deform_fine_on_surface). Default.
  surface,
  /// The thesis's: nearest-vertex pairs, an RBF through them, local subdivision where faces
  /// flip (deform_fine).
  thesis
};
/// "surface" or "thesis" (the command line's spelling).
inline const char* to_string(Fine_level level) { return level == Fine_level::surface ? "surface" : "thesis"; }

/// Where Fine_level::surface takes the shape of the surface between the curves from, when its
/// thin-plate field moves the embedded curves into place (deform_fine_on_surface, step 3).
enum class Fine_shape {
  /// The shape the approach (step 0) left there, whose thin-plate fields ran on the template's
  /// parametrisation (uniform Laplacian): the displacement is smooth.
  approach,
  /// The template's bending (normal_bending; of the mesh as given for deform_fine_on_surface),
  /// in the metric of the surface with the curves embedded: Laplacian editing on cotangent
  /// weights (displacement.h). A plane template stays a plane between the curves' bends. Only
  /// where step 3 is solved on the whole mesh: when it is solved in a band along the curves
  /// (displacement_held_beyond_band > 0, e.g. ico10242-bumpy-great: 5128 vertices held), the
  /// approach's shape is kept and reported.
  template_bending,
  /// Default: `template_bending`, unless the curves are sampled more densely than the template's
  /// edges (the median segment shorter than half the mean edge of the coarse surface, whose
  /// midpoint subdivisions are undone in that measure), then `approach`. Measured on
  /// bench/battery (270 rows, Hausdorff distance to the truth in % of the diagonal, approach ->
  /// template): template_bending gains ico10242-peanut-latlong 1.02 -> 0.69 and
  /// open-mesh_with_border-wave-boundary 1.38 -> 1.00 (both pass on all 5 placements now) and
  /// brings most failing rows nearer (ico2562-peanut-great 3.53 -> 1.06), but loses every row
  /// whose curves are denser than the template, where the embedding leaves thin faces whose
  /// cotangent metric the field follows (ico2562-superellipsoid-latlong-dense10 0.88 -> 2.03,
  /// dense3 0.89 -> 1.20); the choice keeps both gains and no loss (70 -> 80 rows pass).
  /// When it chose the bending and no start of step 0 is clean with it (segments not embedded,
  /// faces turned over or folded), the starts are run again with the approach's shape and the
  /// result with fewer defects is kept (the bending's on a tie): a curved template's bending
  /// turned 11 faces over on open-patch-01-wave-boundary, the approach's shape none.
  automatic
};
/// "approach", "template" or "auto" (the command line's spelling).
inline const char* to_string(Fine_shape s) {
  return s == Fine_shape::approach ? "approach" : s == Fine_shape::template_bending ? "template" : "auto";
}

/// How Fine_level::surface brought the coarse surface towards the curves before embedding them
/// (deform_fine_on_surface, step 0).
enum class Approach {
  none,              ///< not at all: the embedding starts from the coarse surface
  icp,               ///< non-rigid ICP in steps of falling stiffness (internal::approach_curves_icp)
  nearest_vertices,  ///< the thin-plate field through the nearest template vertices (internal::approach_curves)
};
/// The name of an approach as the report writes it.
inline const char* to_string(Approach a) {
  return a == Approach::icp ? "icp" : a == Approach::nearest_vertices ? "nearest_vertices" : "none";
}

/// What a deformation did.
struct Deformation_report {
  // coarse level
  std::size_t user_pairs = 0;  ///< the user's pairs
  Rbf_fit_report coarse_fit;   ///< the coarse RBF's fit
  double coarse_seconds = 0;   ///< time of the coarse level
  /// Faces the coarse motion turns over relative to the affine image of the template (exact flip
  /// counter): local inversions of the RBF, whatever the placement of the template.
  std::size_t coarse_flipped_faces = 0;
  /// det of the linear part R of the coarse interpolant (Rbf_interpolant::affine_determinant).
  double coarse_affine_determinant = 0;
  /// The affine part mirrors space (det R ≤ 0): the pairs reverse the template's orientation.
  bool orientation_reversed = false;
  std::size_t degenerate_faces_skipped = 0;  ///< zero-area faces before the fine motion: not judged
  /// Fine_level::surface: the kept result started from the template warped onto the curves as a
  /// whole (register_quadratic_warp), the starts tried when the first left defects.
  bool coarse_registered = false;
  /// Which: 1 from the warp register_quadratic_warp returned, 2 from the Coherent Point Drift's
  /// when that was another (0: the first start, from the RBF through the pairs alone).
  std::size_t registered_start = 0;
  /// That registration's figures, when it ran (iterations 0 when it did not).
  Registration_report registration;
  // fine level
  bool fine_done = false;  ///< the fine level ran
  std::size_t fine_pairs = 0;              ///< pairs of the final fine RBF (user + closest point + refined)
  std::size_t flip_rounds = 0;             ///< rounds of detection (1 when nothing flipped)
  std::size_t flips_found = 0;             ///< flipped or degenerate faces found, over all rounds
  std::size_t faces_subdivided = 0;        ///< faces split by flip prevention
  std::size_t remaining_flips = 0;         ///< after the last round: non-zero means failure
  std::size_t vertices_inserted_for_density = 0;  ///< Curve_density::refine
  std::size_t vertices_inserted_for_flips = 0;    ///< by flip prevention
  std::vector<std::size_t> dropped_network_vertices;  ///< Curve_density::drop: not represented
  Rbf_fit_report fine_fit;  ///< Fine_level::thesis
  Fine_level fine_level = Fine_level::surface;  ///< the fine level that ran (or would have)
  Fine_shape fine_shape = Fine_shape::approach;  ///< Fine_level::surface: the shape step 3 gave between the curves (never automatic; approach when its field was solved in a band along the curves, which keeps the shape beyond it)
  // Fine_level::surface
  double largest_projection_distance = 0;   ///< from a network vertex to the coarse surface
  /// Edges between two curves' vertices split so that every face has a corner free to move.
  std::size_t edges_split_between_curves = 0;
  /// Network vertices whose surface point, tracked along the curves, is not the nearest point of
  /// the whole coarse surface (internal::tracked_projections).
  std::size_t projections_off_nearest = 0;
  /// The approach whose result was kept (deform_fine_on_surface, step 0), the constraints it
  /// set (template vertices; for ICP, network vertices), and the part of its motion
  /// applied (of the last step for ICP; 0: none).
  Approach approach = Approach::none;
  std::size_t approach_constraints = 0;  ///< see `approach`
  double approach_scale = 0;  ///< the part of the approach motion applied (see approach_constraints)
  /// The nodes of the coarse space the ICP approach's steps were solved on (coarse_space: on
  /// 20 000 vertices or more); 0 when they were solved on every vertex, or for another approach.
  std::size_t approach_coarse_nodes = 0;
  /// Steps 1-4 ran more than once (an earlier start left defects).
  bool approach_retried = false;
  /// Points added on long segments (deform_fine_on_surface, step 0), which become mesh vertices.
  std::size_t network_points_added = 0;
  /// Steps of midpoint subdivision of the template before the coarse level (deform_template),
  /// each splitting every face into four: a template with fewer than twice as many vertices as
  /// the network leaves the curves no free vertex between them, and one with fewer than 40 free
  /// vertices for each region the network bounds gives the regions no shape of their own.
  std::size_t template_subdivisions = 0;
  std::size_t segments_embedded = 0;        ///< as edge chains of the coarse surface
  /// Of those (or of their pieces, when cut), where stage 2's insertion could not.
  std::size_t segments_by_shortest_path = 0;
  std::vector<std::size_t> segments_not_embedded;  ///< indices into network.segments()
  Partition_report embedding;               ///< the insertion on the coarse surface
  Displacement_report displacement;         ///< the thin-plate displacement solve
  std::size_t untangle_rounds = 0;          ///< rounds of local relaxation where faces flipped
  std::size_t untangled_vertices = 0;       ///< free vertices relaxed, over all rounds
  std::size_t remaining_folds = 0;          ///< faces beside an edge folded by the fine level, at the end
  /// Fine_level::surface: the segments (indices into network.segments()) whose edge chains are
  /// nearest, along the mesh's edges, to a face still turned over or beside a folded edge at the
  /// end (remaining_flips, remaining_folds); empty when there is none.
  std::vector<std::size_t> segments_near_defects;
  /// The input polylines (0-based, in input order) that those segments belong to: where to add
  /// correspondences (remaining_flips_message names them).
  std::vector<std::size_t> polylines_near_defects;
  std::size_t edges_flipped = 0;            ///< to repair bad faces whose corners are all held
  double fine_seconds = 0;                  ///< time of the fine level
  // result
  std::size_t vertices = 0;  ///< of the result
  std::size_t faces = 0;     ///< of the result
  /// For each network vertex, the index (in the order of vertices(tm)) of the mesh vertex placed
  /// on it, or Closest_point_assignment::unassigned when it was dropped.
  std::vector<std::size_t> mesh_vertex_of_network_vertex;
};

/// What to tell the user when the coarse level mirrors the template.
inline std::string orientation_reversal_message(double affine_determinant) {
  std::ostringstream os;
  os.precision(3);
  // The affine part maps the normalised template onto the normalised network: a determinant near
  // zero flattens space, whatever its sign.
  if (std::abs(affine_determinant) < 1e-6) {
    os << "the affine part of the coarse map is (nearly) singular, determinant " << affine_determinant
       << ": the pairs' network points are (nearly) coplanar or collinear while their template vertices are "
          "not; give pairs that span the network in all three directions";
    return os.str();
  }
  os << "the correspondences mirror the template: the affine part of the coarse map has determinant "
     << affine_determinant
     << " (a reflection, not a rotation); check that the pairs are not listed in mirrored order, or mirror the "
        "template first";
  return os.str();
}

/// What to change when Fine_level::surface leaves faces turned over or folded, and where they lie
/// (report.polylines_near_defects, 1-based in the text).
inline std::string remaining_defects_advice(const Deformation_report& r) {
  std::ostringstream os;
  if (!r.polylines_near_defects.empty())
    os << "the faces the fine level left turned over or folded lie nearest "
       << internal::name_polylines(r.polylines_near_defects) << " (in file order); ";
  os << "where curves run close together, use a finer template (subdivide it) or sparser curves; elsewhere, "
        "give more correspondences (at crossings of those curves) so that the coarse level brings the template "
        "closer to the curves";
  return os.str();
}

/// What to tell the user when faces still turn over after the fine level (report.remaining_flips
/// > 0): what was tried, and what to change, for the fine level that ran.
inline std::string remaining_flips_message(const Deformation_report& r) {
  std::ostringstream os;
  if (r.fine_level == Fine_level::thesis) {
    os << r.remaining_flips << " faces still flip after " << r.flip_rounds
       << " rounds of flip prevention (raise --max-rounds, or give more correspondences so that the coarse level "
          "brings the template closer to the curves)";
    return os.str();
  }
  os << r.remaining_flips << " faces still turn over after " << r.untangle_rounds << " rounds of untangling";
  if (r.edges_split_between_curves > 0)
    os << " (" << r.edges_split_between_curves << " edges were split between curves running side by side)";
  os << ": " << remaining_defects_advice(r);
  return os.str();
}

/// Every parameter of stage 1 with its default: the one place where the defaults are written.
/// deform_options() reads the named parameters into it; fit_template_to_curves and the command
/// line start from it.
struct Deform_options {
  Rbf_kernel rbf_kernel = Rbf_kernel::linear;            ///< named parameter `rbf_kernel`
  Curve_density curve_density = Curve_density::refine;   ///< `curve_density`
  Fine_level fine_level = Fine_level::surface;           ///< `fine_level`
  Fine_shape fine_shape = Fine_shape::automatic;         ///< `fine_shape`
  bool coarse_registration = true;                       ///< `coarse_registration` (deform_template)
  bool coarse_only = false;                              ///< `coarse_only` (deform_template)
  std::size_t flip_prevention_rounds = 10;               ///< `flip_prevention_rounds`
  std::size_t memory_limit = 0;                          ///< `memory_limit`; 0: default_memory_limit()
  /// `progress`; the default never cancels.
  Progress_callback progress = [](const Progress_step&) { return true; };
};

/// The named parameters of stage 1 in `np`, the others at their defaults (Deform_options).
/// \throws Invalid_input when `flip_prevention_rounds` is negative.
template <typename NamedParameters>
Deform_options deform_options(const NamedParameters& np) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  Deform_options o;
  o.rbf_kernel = choose_parameter(get_parameter(np, internal_np::rbf_kernel), o.rbf_kernel);
  o.curve_density = choose_parameter(get_parameter(np, internal_np::curve_density), o.curve_density);
  o.fine_level = choose_parameter(get_parameter(np, internal_np::fine_level), o.fine_level);
  o.fine_shape = choose_parameter(get_parameter(np, internal_np::fine_shape), o.fine_shape);
  o.coarse_registration = choose_parameter(get_parameter(np, internal_np::coarse_registration), o.coarse_registration);
  o.coarse_only = choose_parameter(get_parameter(np, internal_np::coarse_only), o.coarse_only);
  const auto rounds = choose_parameter(get_parameter(np, internal_np::flip_prevention_rounds), o.flip_prevention_rounds);
  static_assert(std::is_integral_v<std::decay_t<decltype(rounds)>>, "meshfit: flip_prevention_rounds must be an integer");
  o.flip_prevention_rounds = internal::non_negative_count(rounds, "deform", "flip_prevention_rounds");
  o.memory_limit = choose_parameter(get_parameter(np, internal_np::memory_limit), o.memory_limit);
  o.progress = internal::progress_callback(get_parameter(np, internal_np::progress));
  return o;
}

/// The named parameters from which deform_options() gives `o` back: a Deform_options passed to
/// the public functions, `deform_template(tm, network, pairs, deform_parameters(o))`, or chained
/// with more (`deform_parameters(o).number_of_iterations(50)` for fit_template_to_curves).
inline auto deform_parameters(const Deform_options& o) {
  return parameters::rbf_kernel(o.rbf_kernel)
      .curve_density(o.curve_density)
      .fine_level(o.fine_level)
      .fine_shape(o.fine_shape)
      .coarse_registration(o.coarse_registration)
      .coarse_only(o.coarse_only)
      .flip_prevention_rounds(o.flip_prevention_rounds)
      .memory_limit(o.memory_limit)
      .progress(o.progress);
}

namespace internal {
// The levels on meshfit's own mesh, compiled once in the library (src/deform.cpp; their code is
// in internal/deform_levels.h). They change `tm` as the work goes: a cancel or a failure leaves
// it partly changed. The public functions below run them on a copy of the caller's mesh.
Deformation_report deform_coarse_in_place(Work_mesh& tm, const Curve_network& network,
                                          const std::vector<Correspondence>& pairs, const Deform_options& options);
Deformation_report deform_fine_in_place(Work_mesh& tm, const Curve_network& network,
                                        const std::vector<Correspondence>& pairs, const Deform_options& options);
Deformation_report deform_fine_on_surface_in_place(Work_mesh& tm, const Curve_network& network,
                                                   const std::vector<Correspondence>& pairs,
                                                   const Deform_options& options);
Deformation_report deform_template_in_place(Work_mesh& tm, const Curve_network& network,
                                            const std::vector<Correspondence>& pairs, const Deform_options& options);
}  // namespace internal


/// Coarse level: moves every vertex of `tm` with the RBF interpolant through the user's `pairs`
/// (template vertex position → network vertex). Vertex i is the i-th of vertices(tm).
/// The orientation is the sign of the RBF's affine part; on an open template that faces one way
/// (a disc, a patch) it is the pairs' layout along the template that decides it, not how their
/// heights across it correlate (Rbf_interpolant::fit with `orientation_from_layout`).
/// The work is done on a copy of `tm` and written into it when complete, as by deform_template.
/// \tparam TriangleMesh a model of `MutableFaceGraph` (tested: CGAL::Surface_mesh, CGAL::Polyhedron_3) whose
///         points have double Cartesian coordinates (any Cartesian kernel over double, e.g. Epick,
///         Simple_cartesian<double>; an exact kernel is refused at compile time)
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param tm the template, moved in place
/// \param network the curve network
/// \param pairs the user's pairs: template vertex i (the i-th of `vertices(tm)`) → network vertex
/// \param np an optional sequence of named parameters among the ones listed below
/// \return the coarse figures (coarse_fit, coarse_flipped_faces, orientation_reversed, …);
///         `mesh_vertex_of_network_vertex` holds the user's pairs only
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `ReadWritePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///       meshfit::Point_3 as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for `CGAL::vertex_point_t` must be
///       available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{rbf_kernel}
///     \cgalParamDescription{the basis function φ of the coarse interpolant (rbf.h)}
///     \cgalParamType{meshfit::Rbf_kernel}
///     \cgalParamDefault{\default_rbf_kernel (φ(r) = r)}
///   \cgalParamNEnd
///   \cgalParamNBegin{progress}
///     \cgalParamDescription{a callback called at each step with a meshfit::Progress_step (stage `"deform"`)}
///     \cgalParamType{a callable taking `const meshfit::Progress_step&` and returning `bool` (`false` cancels) or
///       `void` (never cancels)}
///     \cgalParamDefault{none: no calls, no cancelling}
///     \cgalParamExtra{When it returns `false`, the stage throws meshfit::Algorithm_failure.}
///   \cgalParamNEnd
///   \cgalParamNBegin{geom_traits}
///     \cgalParamDescription{the geometric traits of `tm`'s points: checked at compile time to be a Cartesian kernel over `double`; the computation does not call it}
///     \cgalParamType{a Cartesian kernel over `double` (`FT` = `double`): `CGAL::Epick`, `CGAL::Simple_cartesian<double>`;
///       anything else (an exact kernel such as Epeck) is refused at compile time by a static assertion}
///     \cgalParamDefault{the kernel of the point type of the `vertex_point_map` (meshfit::Kernel, Epick, for meshfit::Point_3)}
///     \cgalParamExtra{The stage computes on a copy of the coordinates in meshfit::Kernel (exact predicates on the same
///       doubles), so the results do not depend on this parameter.}
///   \cgalParamNEnd
///   \cgalParamNBegin{number_of_threads}
///     \cgalParamDescription{the most threads (OpenMP's and OpenBLAS's, threads.h) the call uses; the counts are put back
///       as they were when it returns or throws (meshfit::Scoped_number_of_threads)}
///     \cgalParamType{an integer type, at least 1}
///     \cgalParamDefault{unchanged: every core, or what `OMP_NUM_THREADS`, `OPENBLAS_NUM_THREADS` or
///       meshfit::set_number_of_threads() set}
///     \cgalParamExtra{A value below 1 throws meshfit::Invalid_input before any work.}
///   \cgalParamNEnd
/// \cgalNamedParamsEnd
///
/// \throws Invalid_input for pairs out of range or an RBF that they cannot define (see
///         Rbf_interpolant::fit); Numerical_error when the solve fails.
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Deformation_report deform_coarse(TriangleMesh& tm, const Curve_network& network,
                                 const std::vector<Correspondence>& pairs,
                                 const NamedParameters& np = CGAL::parameters::default_values()) {
  const Deform_options options = deform_options(np);
  const Scoped_number_of_threads threads(internal::threads_of(np, "deform"));
  return internal::run_on_copy(tm, np, [&](internal::Work_mesh& work, const auto&) {
    return internal::deform_coarse_in_place(work, network, pairs, options);
  });
}


/// Fine level, on a template already roughly in place (deform_coarse): pairs every network vertex
/// with its nearest template vertex (user `pairs` are kept), fits an RBF through all pairs and
/// moves the template so that each paired vertex lies exactly on its network vertex. When the
/// motion would flip faces (exact flip counter, judged against the positions before this call),
/// the network vertices pulling them get mesh vertices of their own at their nearest points on the
/// surface (local subdivision), and everything is redone, for at most `flip_prevention_rounds`
/// rounds (default 10); `report.remaining_flips` tells whether that was enough. With
/// Curve_density::refine (default) network vertices that lost their nearest template vertex get a
/// vertex the same way; with Curve_density::drop they are dropped (reported), and only flip
/// prevention adds vertices. New vertices come after the existing ones. Vertices of no face play
/// no part (no pair, no motion).
/// The work is done on a copy of `tm` (internal/commit_result.h): an exception (a cancel from the
/// `progress` callback, Algorithm_failure, …) leaves `tm`, its property maps and their values as
/// they were; on success the result is written into `tm` in place, as fit_template_to_curves does
/// (a CGAL::Surface_mesh keeps its property maps with their values on the template's vertices, a
/// CGAL::Polyhedron_3 its vertex handles; vertices added follow the template's).
/// \tparam TriangleMesh a model of `MutableFaceGraph` (tested: CGAL::Surface_mesh, CGAL::Polyhedron_3) whose
///         points have double Cartesian coordinates (any Cartesian kernel over double, e.g. Epick,
///         Simple_cartesian<double>; an exact kernel is refused at compile time)
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param tm the template, moved in place
/// \param network the curve network
/// \param pairs the user's pairs: template vertex i (the i-th of `vertices(tm)`) → network vertex
/// \param np an optional sequence of named parameters among the ones listed below
/// \return the fine figures (fine_fit, flip_rounds, faces_subdivided, remaining_flips, …)
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `ReadWritePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///       meshfit::Point_3 as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for `CGAL::vertex_point_t` must be
///       available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{rbf_kernel}
///     \cgalParamDescription{the basis function φ of the fine interpolant (rbf.h)}
///     \cgalParamType{meshfit::Rbf_kernel}
///     \cgalParamDefault{\default_rbf_kernel (φ(r) = r)}
///   \cgalParamNEnd
///   \cgalParamNBegin{curve_density}
///     \cgalParamDescription{what becomes of a network vertex whose nearest template vertex is taken by another}
///     \cgalParamType{meshfit::Curve_density}
///     \cgalParamDefault{\default_curve_density (it gets a vertex of its own)}
///   \cgalParamNEnd
///   \cgalParamNBegin{flip_prevention_rounds}
///     \cgalParamDescription{the most rounds of flip prevention (detection, local subdivision, a new fit)}
///     \cgalParamType{an integer type}
///     \cgalParamDefault{\default_flip_prevention_rounds}
///     \cgalParamExtra{A negative value throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{memory_limit}
///     \cgalParamDescription{the most bytes a dense RBF system (the coarse level's, through the pairs, and the thesis fine level's) may take;
///       a larger system is refused with meshfit::Algorithm_failure before it is allocated}
///     \cgalParamType{`std::size_t`}
///     \cgalParamDefault{\default_memory_limit, which means meshfit::default_memory_limit() (an eighth of the physical memory, at most 2 GiB)}
///   \cgalParamNEnd
///   \cgalParamNBegin{progress}
///     \cgalParamDescription{a callback called at each step with a meshfit::Progress_step (stage `"deform"`)}
///     \cgalParamType{a callable taking `const meshfit::Progress_step&` and returning `bool` (`false` cancels) or
///       `void` (never cancels)}
///     \cgalParamDefault{none: no calls, no cancelling}
///     \cgalParamExtra{When it returns `false`, the stage throws meshfit::Algorithm_failure.}
///   \cgalParamNEnd
///   \cgalParamNBegin{geom_traits}
///     \cgalParamDescription{the geometric traits of `tm`'s points: checked at compile time to be a Cartesian kernel over `double`; the computation does not call it}
///     \cgalParamType{a Cartesian kernel over `double` (`FT` = `double`): `CGAL::Epick`, `CGAL::Simple_cartesian<double>`;
///       anything else (an exact kernel such as Epeck) is refused at compile time by a static assertion}
///     \cgalParamDefault{the kernel of the point type of the `vertex_point_map` (meshfit::Kernel, Epick, for meshfit::Point_3)}
///     \cgalParamExtra{The stage computes on a copy of the coordinates in meshfit::Kernel (exact predicates on the same
///       doubles), so the results do not depend on this parameter.}
///   \cgalParamNEnd
///   \cgalParamNBegin{number_of_threads}
///     \cgalParamDescription{the most threads (OpenMP's and OpenBLAS's, threads.h) the call uses; the counts are put back
///       as they were when it returns or throws (meshfit::Scoped_number_of_threads)}
///     \cgalParamType{an integer type, at least 1}
///     \cgalParamDefault{unchanged: every core, or what `OMP_NUM_THREADS`, `OPENBLAS_NUM_THREADS` or
///       meshfit::set_number_of_threads() set}
///     \cgalParamExtra{A value below 1 throws meshfit::Invalid_input before any work.}
///   \cgalParamNEnd
/// \cgalNamedParamsEnd
///
/// \throws Invalid_input for pairs out of range or that define no interpolant, or a negative
///         `flip_prevention_rounds`.
/// \throws Numerical_error when a solve fails.
/// \throws Algorithm_failure before any work when a polyline lies entirely far from the template
///         (internal::check_polylines_near); when the dense RBF would exceed `memory_limit`; when
///         flip prevention would grow the mesh past 8 × (template + network vertices).
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Deformation_report deform_fine(TriangleMesh& tm, const Curve_network& network,
                               const std::vector<Correspondence>& pairs,
                               const NamedParameters& np = CGAL::parameters::default_values()) {
  const Deform_options options = deform_options(np);
  const Scoped_number_of_threads threads(internal::threads_of(np, "deform"));
  return internal::run_on_copy(tm, np, [&](internal::Work_mesh& work, const auto&) {
    return internal::deform_fine_in_place(work, network, pairs, options);
  });
}


/// Fine level, Fine_level::surface, on a template already roughly in place (deform_coarse):
///   0. a segment longer than twice the template's mean edge is cut into pieces of about one edge
///      (points on the segment), unless both its ends lie near the border (as in step 1): a
///      long straight segment's ends project onto a curved surface far from where its middle
///      does, and the pieces follow the surface; the report speaks of the network's own
///      vertices and segments (`network_points_added` counts the points). Then the surface is
///      brought towards the curves: by non-rigid ICP (internal::approach_curves_icp: up to six
///      least-squares steps of falling stiffness, each asking that the point of the surface
///      tracked for every network vertex move onto it against the thin-plate energy of the
///      motion (the vertices of curves along the border, judged as in step 1 at the first step:
///      their nearest border point), each untangled, halved while it leaves a face turned over or a new fold, and
///      the last that cannot be made ending the approach; on 20 000 vertices or more, each
///      step is solved in a coarse space of about a sixteenth of the vertices, coarse_space);
///   1. every network vertex gets a mesh vertex at (or near) its point on the surface, tracked
///      along the curves from the user's pairs (internal::tracked_projections); the vertices of
///      curves running along the border go onto the border (a curve runs along it when its
///      nearest border points trace at least half its length), the other vertices stay off it;
///      a face or an edge is split, or a template vertex already there reused; the user's pairs
///      keep their template vertices;
///   2. every segment becomes a chain of mesh edges on this surface, where nothing is folded:
///      the border arc for a segment along the border, stage 2's insertion (partition_mesh on
///      the network as projected) for the others, and the shortest edge path crossing no chain
///      where that insertion refuses; an interior edge joining two chain vertices is then split at
///      its midpoint, so that every face keeps a free corner;
///   3. the network vertices are moved onto their points, the inner vertices of each chain onto
///      the segment, and every other vertex by the thin-plate displacement field through those
///      motions (interpolate_displacements), solved in a band along the curves with the vertices
///      beyond it held (each held vertex reaches the larger of 4 rings and 10 times its motion
///      over the mean edge; the whole mesh when the band would hold at least half the free
///      vertices; `report.displacement.held_beyond_band`); when that leaves faces turned over or folded, the
///      motion is made again in four equal parts, with step 4a's untangling after each;
///   4. faces that turn over against the coarse surface's normals, or fold with a neighbour,
///      are repaired: the free vertices around them are relaxed towards their neighbours' mean
///      (up to 3 rings, for at most `flip_prevention_rounds` rounds, default 10, the best state
///      kept), and an edge of a bad face whose corners are all held is flipped when both new
///      faces are good; last, each free corner of a face still turned over is put where its faces
///      are good, if a point between its neighbours' mean and its ring does so, edges out of it
///      being flipped to lower its degree where none does. `report.remaining_flips` and
///      `report.remaining_folds` are what is left.
/// Vertices are added in step 1 (at most one per network vertex and added point) and by the
/// splits of step 2, after the existing ones. When steps 1-4 after the ICP approach leave
/// defects (segments not embedded, faces turned over or folded), they run again from the coarse
/// surface after the older approach (internal::approach_curves: the thin-plate field through the
/// motions of the curves' surface points given to template vertices three edges apart, unless
/// even an eighth of it turns a face over or folds an edge), and then without approach; the result with the fewest defects is kept
/// (`approach`, `approach_retried`; the earlier on a tie). When one of them left a segment with no
/// path in step 2 (its ends walled off by faces whose corners are all on chains, as at a crossing
/// on CGAL's pig), the three run once more with the edges joining two chain vertices split before
/// such a path is sought again.
/// The work is done on a copy of `tm` (internal/commit_result.h): an exception (a cancel from the
/// `progress` callback, Algorithm_failure, …) leaves `tm`, its property maps and their values as
/// they were; on success the result is written into `tm` in place, as fit_template_to_curves does
/// (a CGAL::Surface_mesh keeps its property maps with their values on the template's vertices, a
/// CGAL::Polyhedron_3 its vertex handles; vertices added follow the template's).
/// \tparam TriangleMesh a model of `MutableFaceGraph` (tested: CGAL::Surface_mesh, CGAL::Polyhedron_3) whose
///         points have double Cartesian coordinates (any Cartesian kernel over double, e.g. Epick,
///         Simple_cartesian<double>; an exact kernel is refused at compile time)
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param tm the template, moved in place
/// \param network the curve network
/// \param pairs the user's pairs: template vertex i (the i-th of `vertices(tm)`) → network vertex
/// \param np an optional sequence of named parameters among the ones listed below
/// \return the fine figures (segments_embedded, embedding, displacement, untangle_rounds,
///         remaining_flips, remaining_folds, …)
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `ReadWritePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///       meshfit::Point_3 as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for `CGAL::vertex_point_t` must be
///       available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{flip_prevention_rounds}
///     \cgalParamDescription{the most rounds of untangling (step 4)}
///     \cgalParamType{an integer type}
///     \cgalParamDefault{\default_flip_prevention_rounds}
///     \cgalParamExtra{A negative value throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{progress}
///     \cgalParamDescription{a callback called at each step with a meshfit::Progress_step (stage `"deform"`)}
///     \cgalParamType{a callable taking `const meshfit::Progress_step&` and returning `bool` (`false` cancels) or
///       `void` (never cancels)}
///     \cgalParamDefault{none: no calls, no cancelling}
///     \cgalParamExtra{When it returns `false`, the stage throws meshfit::Algorithm_failure. The embedding's insertion (step 2) reports its steps as this stage's.}
///   \cgalParamNEnd
///   \cgalParamNBegin{geom_traits}
///     \cgalParamDescription{the geometric traits of `tm`'s points: checked at compile time to be a Cartesian kernel over `double`; the computation does not call it}
///     \cgalParamType{a Cartesian kernel over `double` (`FT` = `double`): `CGAL::Epick`, `CGAL::Simple_cartesian<double>`;
///       anything else (an exact kernel such as Epeck) is refused at compile time by a static assertion}
///     \cgalParamDefault{the kernel of the point type of the `vertex_point_map` (meshfit::Kernel, Epick, for meshfit::Point_3)}
///     \cgalParamExtra{The stage computes on a copy of the coordinates in meshfit::Kernel (exact predicates on the same
///       doubles), so the results do not depend on this parameter.}
///   \cgalParamNEnd
///   \cgalParamNBegin{number_of_threads}
///     \cgalParamDescription{the most threads (OpenMP's and OpenBLAS's, threads.h) the call uses; the counts are put back
///       as they were when it returns or throws (meshfit::Scoped_number_of_threads)}
///     \cgalParamType{an integer type, at least 1}
///     \cgalParamDefault{unchanged: every core, or what `OMP_NUM_THREADS`, `OPENBLAS_NUM_THREADS` or
///       meshfit::set_number_of_threads() set}
///     \cgalParamExtra{A value below 1 throws meshfit::Invalid_input before any work.}
///   \cgalParamNEnd
/// \cgalNamedParamsEnd
///
/// \throws Invalid_input for pairs out of range, or two pairs that give one network vertex two
///         template vertices (or the reverse), or a negative `flip_prevention_rounds`.
/// \throws Numerical_error when the displacement solve fails.
/// \throws Algorithm_failure, naming the polylines (1-based, in file order), before any work
///         when: the network is not planar and the template has genus 0; a polyline lies entirely
///         far from the coarse-deformed template (farther than a tenth of its size); segments of
///         two polylines cross on the surface without a shared vertex (their projections cross
///         and the segments pass within 1 % of their length of each other); two network vertices
///         cannot be told apart on the surface (curves denser than the template).
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Deformation_report deform_fine_on_surface(TriangleMesh& tm, const Curve_network& network,
                                          const std::vector<Correspondence>& pairs,
                                          const NamedParameters& np = CGAL::parameters::default_values()) {
  const Deform_options options = deform_options(np);
  const Scoped_number_of_threads threads(internal::threads_of(np, "deform"));
  return internal::run_on_copy(tm, np, [&](internal::Work_mesh& work, const auto&) {
    return internal::deform_fine_on_surface_in_place(work, network, pairs, options);
  });
}


/// Both levels: deform_coarse then the fine level (unless the named parameter `coarse_only` is
/// true): deform_fine_on_surface, or deform_fine with `fine_level(Fine_level::thesis)`.
/// With the surface fine level and Curve_density::refine (the defaults), a template with fewer
/// than twice as many vertices as the network, or fewer than the network's vertices plus 40 for
/// every region it bounds (independent cycles + 1), is first subdivided at its edges' midpoints (every
/// face into four; at most three times, to at most 2e6 faces; `template_subdivisions`): the
/// template's vertices keep their indices, the new ones come after them.
/// When the surface fine level leaves defects (segments not embedded, faces turned over, folds),
/// both levels run once more from the (subdivided) template warped onto the curves as a whole
/// (register_quadratic_warp, registration.h; unless `coarse_registration(false)`), and once more
/// from the Coherent Point Drift's warp when the warp used was a closest-point fit's and defects
/// remain; a later result is kept when it has fewer defects than the one kept so far, compared in
/// that order (`coarse_registered`, `registered_start`, `registration`); a warp that turns space
/// over, or a start the fine level refuses, leaves the result kept so far.
/// The report holds the figures of both. When the coarse level reverses the orientation (pairs
/// that mirror the template), the fine level is not run: the report says so and the caller
/// decides (the command line fails with exit status 3).
/// The levels run on the template and the network each scaled by a power of two to a unit-sized
/// box (exact; see coordinate_range.h), so the result depends neither on the unit of the
/// coordinates nor on the template's size against the curves'.
/// The work is done on a copy of `tm` (internal/commit_result.h): an exception (a cancel from the
/// `progress` callback, Algorithm_failure, …) leaves `tm`, its property maps and their values as
/// they were; on success the result is written into `tm` in place, as fit_template_to_curves does
/// (a CGAL::Surface_mesh keeps its property maps with their values on the template's vertices, a
/// CGAL::Polyhedron_3 its vertex handles; vertices added follow the template's).
/// \tparam TriangleMesh a model of `MutableFaceGraph` (tested: CGAL::Surface_mesh, CGAL::Polyhedron_3) whose
///         points have double Cartesian coordinates (any Cartesian kernel over double, e.g. Epick,
///         Simple_cartesian<double>; an exact kernel is refused at compile time)
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param tm the template, moved in place
/// \param network the curve network
/// \param pairs the user's pairs: template vertex i (the i-th of `vertices(tm)`) → network vertex
/// \param np an optional sequence of named parameters among the ones listed below
/// \return the figures of both levels (those of the coarse level only when the fine level did
///         not run)
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `ReadWritePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///       meshfit::Point_3 as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for `CGAL::vertex_point_t` must be
///       available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{coarse_only}
///     \cgalParamDescription{stop after the coarse level}
///     \cgalParamType{`bool`}
///     \cgalParamDefault{\default_coarse_only}
///   \cgalParamNEnd
///   \cgalParamNBegin{fine_level}
///     \cgalParamDescription{the method of the fine level}
///     \cgalParamType{meshfit::Fine_level}
///     \cgalParamDefault{\default_fine_level (deform_fine_on_surface; `Fine_level::thesis`: deform_fine)}
///   \cgalParamNEnd
///   \cgalParamNBegin{coarse_registration}
///     \cgalParamDescription{when `Fine_level::surface` leaves defects (segments not embedded, faces turned over or
///       folded), run the levels again from the template warped onto the curves as a whole
///       (register_quadratic_warp, registration.h) and keep the result with fewer defects}
///     \cgalParamType{`bool`}
///     \cgalParamDefault{\default_coarse_registration}
///   \cgalParamNEnd
///   \cgalParamNBegin{fine_shape}
///     \cgalParamDescription{where `Fine_level::surface` takes the shape between the curves from (deform_template, deform_fine_on_surface)}
///     \cgalParamType{meshfit::Fine_shape}
///     \cgalParamDefault{\default_fine_shape}
///   \cgalParamNEnd
///   \cgalParamNBegin{rbf_kernel}
///     \cgalParamDescription{the basis function φ of the interpolants (the coarse one, and the fine one of `Fine_level::thesis`) (rbf.h)}
///     \cgalParamType{meshfit::Rbf_kernel}
///     \cgalParamDefault{\default_rbf_kernel (φ(r) = r)}
///   \cgalParamNEnd
///   \cgalParamNBegin{curve_density}
///     \cgalParamDescription{what becomes of a network vertex whose nearest template vertex is taken by another}
///     \cgalParamType{meshfit::Curve_density}
///     \cgalParamDefault{\default_curve_density (it gets a vertex of its own)}
///   \cgalParamNEnd
///   \cgalParamNBegin{flip_prevention_rounds}
///     \cgalParamDescription{the most rounds of flip prevention (`Fine_level::thesis`) or of untangling (`Fine_level::surface`)}
///     \cgalParamType{an integer type}
///     \cgalParamDefault{\default_flip_prevention_rounds}
///     \cgalParamExtra{A negative value throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{memory_limit}
///     \cgalParamDescription{the most bytes a dense RBF system (the coarse level's, through the pairs, and the thesis fine level's) may take;
///       a larger system is refused with meshfit::Algorithm_failure before it is allocated}
///     \cgalParamType{`std::size_t`}
///     \cgalParamDefault{\default_memory_limit, which means meshfit::default_memory_limit() (an eighth of the physical memory, at most 2 GiB)}
///     \cgalParamExtra{Read by the fine level `Fine_level::thesis` only.}
///   \cgalParamNEnd
///   \cgalParamNBegin{progress}
///     \cgalParamDescription{a callback called at each step with a meshfit::Progress_step (stage `"deform"`)}
///     \cgalParamType{a callable taking `const meshfit::Progress_step&` and returning `bool` (`false` cancels) or
///       `void` (never cancels)}
///     \cgalParamDefault{none: no calls, no cancelling}
///     \cgalParamExtra{When it returns `false`, the stage throws meshfit::Algorithm_failure.}
///   \cgalParamNEnd
///   \cgalParamNBegin{geom_traits}
///     \cgalParamDescription{the geometric traits of `tm`'s points: checked at compile time to be a Cartesian kernel over `double`; the computation does not call it}
///     \cgalParamType{a Cartesian kernel over `double` (`FT` = `double`): `CGAL::Epick`, `CGAL::Simple_cartesian<double>`;
///       anything else (an exact kernel such as Epeck) is refused at compile time by a static assertion}
///     \cgalParamDefault{the kernel of the point type of the `vertex_point_map` (meshfit::Kernel, Epick, for meshfit::Point_3)}
///     \cgalParamExtra{The stage computes on a copy of the coordinates in meshfit::Kernel (exact predicates on the same
///       doubles), so the results do not depend on this parameter.}
///   \cgalParamNEnd
///   \cgalParamNBegin{number_of_threads}
///     \cgalParamDescription{the most threads (OpenMP's and OpenBLAS's, threads.h) the call uses; the counts are put back
///       as they were when it returns or throws (meshfit::Scoped_number_of_threads)}
///     \cgalParamType{an integer type, at least 1}
///     \cgalParamDefault{unchanged: every core, or what `OMP_NUM_THREADS`, `OPENBLAS_NUM_THREADS` or
///       meshfit::set_number_of_threads() set}
///     \cgalParamExtra{A value below 1 throws meshfit::Invalid_input before any work.}
///   \cgalParamNEnd
/// \cgalNamedParamsEnd
///
/// \throws Invalid_input when a template coordinate is outside the supported range, and as
///         deform_coarse, deform_fine and deform_fine_on_surface.
/// \throws Numerical_error, Algorithm_failure as the levels that run.
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Deformation_report deform_template(TriangleMesh& tm, const Curve_network& network,
                                   const std::vector<Correspondence>& pairs,
                                   const NamedParameters& np = CGAL::parameters::default_values()) {
  const Deform_options options = deform_options(np);
  const Scoped_number_of_threads threads(internal::threads_of(np, "deform"));
  return internal::run_on_copy(tm, np, [&](internal::Work_mesh& work, const auto&) {
    return internal::deform_template_in_place(work, network, pairs, options);
  });
}
}  // namespace meshfit

#endif  // MESHFIT_DEFORM_H
