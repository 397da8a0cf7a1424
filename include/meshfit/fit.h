// meshfit: the whole pipeline (thesis §1.3, fig. 1.4): the template deformed onto the curves
// (stage 1, deform.h), the curves made chains of mesh edges and the regions between them labelled
// (stage 2, partition.h), the result smoothed with the curves held (stage 3, smooth.h), and a final
// verification of the result.
#ifndef MESHFIT_FIT_H
#define MESHFIT_FIT_H

#include <meshfit/check.h>
#include <meshfit/correspondence.h>
#include <meshfit/curve_network.h>
#include <meshfit/deform.h>
#include <meshfit/exceptions.h>
#include <meshfit/internal/commit_result.h>
#include <meshfit/internal/fit_impl.h>
#include <meshfit/io.h>
#include <meshfit/internal/stage_support.h>
#include <meshfit/internal/unit_scale.h>
#include <meshfit/internal/vertex_attributes.h>
#include <meshfit/parameters.h>
#include <meshfit/partition.h>
#include <meshfit/smooth.h>

#include <array>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace meshfit {

/// The final checks of fit_template_to_curves.
struct Fit_verification {
  std::size_t network_vertices = 0;          ///< vertices of the network
  std::size_t network_vertices_missing = 0;  ///< not exactly at a mesh vertex's position
  std::size_t segments = 0;                  ///< segments of the network
  std::size_t segments_not_chains = 0;       ///< not a chain of curve edges lying on the segment
  std::size_t flips_remaining = 0;           ///< faces stage 1 could not keep from flipping
  std::size_t degenerate_faces = 0;          ///< zero area (exact)
  /// Interior edges whose two faces turn more than 90 degrees apart (exact: one face is not
  /// positively oriented in the other's plane), in the result and in the template: a flipped face
  /// folds over its neighbours, so the fit must not add any.
  std::size_t folded_edges = 0;
  std::size_t template_folded_edges = 0;  ///< folded edges of the template (see folded_edges)
  bool self_intersects = false;           ///< the result intersects itself (when checked)
  bool template_self_intersects = false;  ///< so does the template (checked only when the result does)
  bool self_intersection_checked = false;  ///< the named parameter `check_self_intersections` was true
  /// Pairs of faces that intersect (PMP::self_intersections): in the template when the result
  /// intersects itself, and in the result when both do. A template that does already (CGAL's pig)
  /// must not excuse new intersections, so the counts are compared (the fit splits faces, so a
  /// pair of the template may become several: the comparison errs towards calling a result bad).
  std::size_t self_intersecting_pairs = 0;
  std::size_t template_self_intersecting_pairs = 0;  ///< see self_intersecting_pairs
  std::size_t non_finite_coordinates = 0;  ///< vertices of the result with a coordinate not finite
  /// Regions of the partition, and how many the network bounds on the result's surface when that
  /// is determined by its topology (expected_regions_known): on a connected genus-0 surface,
  /// E − V + 1 + C for a network of V vertices, E segments and C components (Euler's formula),
  /// less one for each border cycle made of curve edges only (the face of the network it bounds
  /// is not on the mesh; a border cycle with no curve edge is a hole inside a region). Not known
  /// on other surfaces, nor when a border cycle is partly on curves.
  std::size_t regions = 0;
  std::size_t expected_regions = 0;     ///< see regions
  bool expected_regions_known = false;  ///< expected_regions holds a value (see regions)

  /// More folded edges than the template has.
  bool adds_folds() const { return folded_edges > template_folded_edges; }
  /// The result intersects itself where the template does not, or in more pairs of faces.
  bool adds_self_intersections() const {
    return (self_intersects && !template_self_intersects) ||
           (template_self_intersects && self_intersecting_pairs > template_self_intersecting_pairs);
  }
  /// Faces turned over, new folds or new self-intersections: the result is tangled.
  bool tangled() const { return flips_remaining > 0 || adds_folds() || adds_self_intersections(); }

  /// What is wrong, one sentence each; empty when everything holds.
  std::vector<std::string> problems() const {
    std::vector<std::string> p;
    auto n = [](std::size_t k) { return std::to_string(k); };
    if (network_vertices_missing)
      p.push_back(n(network_vertices_missing) + " of " + n(network_vertices) + " network vertices are not mesh vertices");
    if (segments_not_chains)
      p.push_back(n(segments_not_chains) + " of " + n(segments) + " segments are not chains of mesh edges");
    if (flips_remaining) p.push_back(n(flips_remaining) + " faces flipped in the deformation");
    if (degenerate_faces) p.push_back(n(degenerate_faces) + " faces have zero area");
    if (adds_folds())
      p.push_back(n(folded_edges) + " folded edges (the template has " + n(template_folded_edges) + ")");
    if (self_intersects && !template_self_intersects) p.push_back("the result intersects itself (the template does not)");
    if (template_self_intersects && self_intersecting_pairs > template_self_intersecting_pairs)
      p.push_back(n(self_intersecting_pairs) + " pairs of faces intersect (the template has " +
                  n(template_self_intersecting_pairs) + ")");
    if (non_finite_coordinates) p.push_back(n(non_finite_coordinates) + " non-finite coordinates");
    if (expected_regions_known && regions != expected_regions)
      p.push_back(n(regions) + " regions where the network bounds " + n(expected_regions));
    return p;
  }
  /// No problem.
  bool passed() const { return problems().empty(); }
};

/// What fit_template_to_curves did.
struct Fit_report {
  Deformation_report deformation;  ///< stage 1
  Partition_report partition;      ///< stage 2
  Smoothing_report smoothing;      ///< stage 3 (displacements in the input's units)
  Fit_verification verification;   ///< the final checks
  double deform_seconds = 0;       ///< time of stage 1
  double partition_seconds = 0;    ///< time of stage 2
  double smooth_seconds = 0;       ///< time of stage 3, chain spacing and angle flips included
  double verify_seconds = 0;       ///< time of the verification
  double total_seconds = 0;        ///< time of the call
  std::size_t template_vertices = 0;  ///< vertices of the template
  std::size_t template_faces = 0;     ///< faces of the template
  std::size_t vertices = 0;           ///< vertices of the result
  std::size_t faces = 0;              ///< faces of the result
  double minimum_angle_deg = 0;  ///< smallest angle of the result's triangles
  /// Edges flipped after smoothing to raise the smallest angle (internal::flip_for_angles).
  std::size_t angle_flips = 0;
  /// Moves of curve chain vertices along their segments, after smoothing, that mended needles
  /// (internal::space_chain_vertices).
  std::size_t chain_vertex_moves = 0;
  /// For each network vertex, the index of its mesh vertex (order of vertices(tm)).
  std::vector<std::size_t> mesh_vertex_of_network_vertex;
};


/// Fits `tm` (the template) to `network` through the user's `pairs` (template vertex index →
/// network vertex) and partitions it by the curves:
///   1. deform_template (coarse RBF through the pairs, then the fine level: by default the curves
///      embedded in the coarse surface, moved into place by a thin-plate displacement and
///      untangled; with `fine_level(Fine_level::thesis)` the thesis's fine RBF through
///      closest-point pairs and flip prevention; thesis ch. 2);
///   2. partition_mesh (every segment a chain of mesh edges, regions labelled; ch. 3);
///   3. smooth_fitted_mesh with the curve edges and their vertices held (ch. 4); then the inner
///      vertices of bunched chains slid apart along their segments (internal::space_chain_vertices)
///      and edges flipped for the smallest angle where the surface is nearly flat
///      (internal::flip_for_angles);
///   4. verification (Fit_verification): network vertices are mesh vertices, segments are edge
///      chains, no flipped (folded) or degenerate face, no self-intersection the template did not
///      have (PMP::does_self_intersect; when both intersect themselves, no more intersecting face
///      pairs than the template's, PMP::self_intersections), finite coordinates.
/// The work is done on a copy: `tm` is changed only when every stage and the verification
/// completed, so an exception (including a cancel from the `progress` callback, Algorithm_failure,
/// Invalid_input for a non-finite attribute value) leaves `tm`, its property maps and their values
/// as they were. Vertex i of the result is template vertex i (moved); vertices added by the stages
/// follow. A failed verification does not throw: the report says what is wrong and the caller
/// decides.
///
/// What the caller's mesh keeps (the result is written into `tm` in place, see
/// internal/commit_result.h):
///   - CGAL::Surface_mesh: every property map added to `tm` (of any type) stays, with its values
///     on the template's vertices (template vertex i keeps its index, so its descriptor and its
///     values stay valid). An edge of the result joining the same two template vertices as an edge
///     of the template is that edge (same index, values kept, halfedges in the same directions);
///     a face of the result with the same three template vertices in the same order is that face.
///     Every other element (the added vertices, and edges and faces the stages made) gets each
///     map's default value. Removed (garbage) elements of the template stay removed; the added
///     vertices are appended after every index. Template edges and faces the result no longer has
///     are reused for its new ones (their values reset to the defaults).
///   - other meshes (CGAL::Polyhedron_3, …): the template's vertex descriptors (handles) stay
///     valid and are result vertices 0 … n−1, so vertex property maps keyed by them (a
///     boost::associative_property_map over a std::map/unordered_map, CGAL's dynamic vertex
///     property maps of the mesh) keep their values; every face, edge and halfedge is removed and
///     made anew, so their old descriptors are invalid and maps keyed by them are stale. (With
///     CGAL::Polyhedron_items_with_id_3, the added vertices' and the new faces' and halfedges' ids
///     are not set: call CGAL::set_halfedgeds_items_id(tm) after.)
/// Vertex attributes carried to the added vertices (CGAL's IO named parameters; each a read-write
/// property map on the vertices of `tm`, read on the template's vertices after the stages and
/// written on the added vertices only, after `tm` holds the result, so a map keyed by descriptors
/// gets the descriptors of the result's vertices):
///   `vertex_texture_map` (values with x(), y() and a two-coordinate constructor: Point_2,
///   Vector_2), `vertex_color_map` (CGAL::IO::Color, all four channels), `vertex_normal_map`
///   (values with x(), y(), z() and a three-coordinate constructor: Vector_3).
///   The template's vertices keep their values; each added vertex gets the discrete harmonic
///   extension of the template's values over the result's edges (the mean of its neighbours', as
///   displacement.h at order 1 with the template's vertices fixed), so it lies in the convex hull
///   of its neighbours' values. Normals are extended likewise and normalised (they stay consistent
///   with the template's normals, which keep the caller's values even where the surface moved;
///   call PMP::compute_vertex_normals after for geometric ones); where the extension cancels out,
///   the result's geometric normal is taken (the sum of the vertex's triangles' normals weighted by
///   their areas).
/// \tparam TriangleMesh a model of `MutableFaceGraph` (tested: CGAL::Surface_mesh, CGAL::Polyhedron_3) whose
///         points have double Cartesian coordinates (any Cartesian kernel over double, e.g. Epick,
///         Simple_cartesian<double>; an exact kernel is refused at compile time)
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param tm the template; the result is written into it (in place, as above) when every stage
///        and the verification completed
/// \param input_network the curve network
/// \param pairs the user's pairs: template vertex i (the i-th of `vertices(tm)`) → network vertex
/// \param np an optional sequence of named parameters among the ones listed below
/// \return the reports of the stages and of the verification, the times and the result's figures
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
///   \cgalParamNBegin{edge_is_constrained_map}
///     \cgalParamDescription{output: set to `true` exactly on the curve edges of the result}
///     \cgalParamType{a class model of `WritablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%edge_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: the curve edges are not written}
///   \cgalParamNEnd
///   \cgalParamNBegin{face_patch_map}
///     \cgalParamDescription{output: the region of each face of the result, numbered from 0}
///     \cgalParamType{a class model of `WritablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%face_descriptor` as key type and an integer type as
///       value type}
///     \cgalParamDefault{none: the regions are not written}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_texture_map}
///     \cgalParamDescription{texture coordinates, carried to the added vertices (above)}
///     \cgalParamType{a class model of `ReadWritePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and a value type with
///       x(), y() and a two-coordinate constructor (Point_2, Vector_2)}
///     \cgalParamDefault{none: no texture coordinates are carried}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_normal_map}
///     \cgalParamDescription{vertex normals, carried to the added vertices and normalised (above)}
///     \cgalParamType{a class model of `ReadWritePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and a value type with
///       x(), y(), z() and a three-coordinate constructor (Vector_3)}
///     \cgalParamDefault{none: no normals are carried}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_color_map}
///     \cgalParamDescription{vertex colours, carried to the added vertices (above)}
///     \cgalParamType{a class model of `ReadWritePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and `CGAL::IO::Color` as value type}
///     \cgalParamDefault{none: no colours are carried}
///   \cgalParamNEnd
///   \cgalParamNBegin{fine_level}
///     \cgalParamDescription{stage 1's fine level}
///     \cgalParamType{meshfit::Fine_level}
///     \cgalParamDefault{\default_fine_level}
///   \cgalParamNEnd
///   \cgalParamNBegin{coarse_registration}
///     \cgalParamDescription{when `Fine_level::surface` leaves defects (segments not embedded, faces turned over or
///       folded), run the levels again from the template warped onto the curves as a whole
///       (register_quadratic_warp, registration.h) and keep the result with fewer defects}
///     \cgalParamType{`bool`}
///     \cgalParamDefault{\default_coarse_registration}
///   \cgalParamNEnd
///   \cgalParamNBegin{fine_shape}
///     \cgalParamDescription{where `Fine_level::surface` takes the shape between the curves from}
///     \cgalParamType{meshfit::Fine_shape}
///     \cgalParamDefault{\default_fine_shape}
///   \cgalParamNEnd
///   \cgalParamNBegin{rbf_kernel}
///     \cgalParamDescription{the basis function φ of stage 1's interpolants (rbf.h)}
///     \cgalParamType{meshfit::Rbf_kernel}
///     \cgalParamDefault{\default_rbf_kernel (φ(r) = r)}
///   \cgalParamNEnd
///   \cgalParamNBegin{curve_density}
///     \cgalParamDescription{what becomes of a network vertex whose nearest template vertex is taken by another}
///     \cgalParamType{meshfit::Curve_density}
///     \cgalParamDefault{\default_curve_density (it gets a vertex of its own)}
///   \cgalParamNEnd
///   \cgalParamNBegin{flip_prevention_rounds}
///     \cgalParamDescription{the most rounds of stage 1's flip prevention (`Fine_level::thesis`) or untangling (`Fine_level::surface`)}
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
///   \cgalParamNBegin{number_of_iterations}
///     \cgalParamDescription{stage 3's iterations, split as smooth_fitted_mesh splits them: one fifth (rounded down)
///       modified mean curvature, the rest modified Laplacian}
///     \cgalParamType{an integer type}
///     \cgalParamDefault{\default_smoothing_iterations}
///     \cgalParamExtra{A negative value throws meshfit::Invalid_input; `0` skips the smoothing.}
///   \cgalParamNEnd
///   \cgalParamNBegin{mean_curvature_iterations}
///     \cgalParamDescription{the iterations of stage 3's first phase, overriding the split}
///     \cgalParamType{an integer type}
///     \cgalParamDefault{`number_of_iterations / 5` (integer division): \default_mean_curvature_iterations}
///   \cgalParamNEnd
///   \cgalParamNBegin{laplacian_iterations}
///     \cgalParamDescription{the iterations of stage 3's second phase, overriding the split}
///     \cgalParamType{an integer type}
///     \cgalParamDefault{`number_of_iterations - number_of_iterations / 5`: \default_laplacian_iterations}
///   \cgalParamNEnd
///   \cgalParamNBegin{smoothing_tolerance}
///     \cgalParamDescription{stage 3 ends a phase after an iteration that moves no vertex farther than this times the
///       mean edge length (smooth_fitted_mesh)}
///     \cgalParamType{`double`, not negative}
///     \cgalParamDefault{\default_smoothing_tolerance}
///     \cgalParamExtra{Zero makes every iteration; a negative or non-finite value throws meshfit::Invalid_input
///       before any work.}
///   \cgalParamNEnd
///   \cgalParamNBegin{step_size}
///     \cgalParamDescription{stage 3's step λ (smooth_fitted_mesh)}
///     \cgalParamType{`double` in (0, 1]}
///     \cgalParamDefault{\default_flow_step}
///     \cgalParamExtra{A value outside (0, 1] throws meshfit::Invalid_input when stage 3 starts (`tm` is
///       unchanged).}
///   \cgalParamNEnd
///   \cgalParamNBegin{check_self_intersections}
///     \cgalParamDescription{whether the verification looks for self-intersections of the result (the most expensive
///       check)}
///     \cgalParamType{`bool`}
///     \cgalParamDefault{\default_fit_check_self_intersections}
///   \cgalParamNEnd
///   \cgalParamNBegin{progress}
///     \cgalParamDescription{a callback called at each step with a meshfit::Progress_step (stage `"fit"`)}
///     \cgalParamType{a callable taking `const meshfit::Progress_step&` and returning `bool` (`false` cancels) or
///       `void` (never cancels)}
///     \cgalParamDefault{none: no calls, no cancelling}
///     \cgalParamExtra{Every stage calls it with its own stage name (`"deform"`, `"partition"`, `"smooth"`), the
///       verification with `"fit"`. When it returns `false`, fit_template_to_curves throws
///       meshfit::Algorithm_failure and `tm` is unchanged.}
///   \cgalParamNEnd
///   \cgalParamNBegin{geom_traits}
///     \cgalParamDescription{the geometric traits of `tm`'s points: checked at compile time to be a Cartesian kernel over `double`; the stages and the verification compute on meshfit's copy of the points in meshfit::Kernel}
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
/// \throws Invalid_input for pairs out of range or that define no interpolant, a template
///         coordinate outside the supported range, a negative count among the named
///         parameters (before any work), or a template vertex's attribute (texture coordinate,
///         normal, colour) that is not finite.
/// \throws Algorithm_failure when the pairs mirror the template, when some network vertex could
///         not be given a mesh vertex (Curve_density::drop), or when cancelled.
/// \throws Numerical_error when a solve of stage 1 fails.
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Fit_report fit_template_to_curves(TriangleMesh& tm, const Curve_network& input_network,
                                  const std::vector<Correspondence>& pairs,
                                  const NamedParameters& np = CGAL::parameters::default_values()) {
  const auto t0 = std::chrono::steady_clock::now();
  const internal::Fit_options options = internal::fit_options(np);
  const Scoped_number_of_threads threads(internal::threads_of(np, "fit"));
  const auto vpm = internal::vertex_point_map_of(tm, np);

  Fit_report report;
  report.template_vertices = num_vertices(tm);
  report.template_faces = num_faces(tm);

  // The copy the stages work on (through Mesh_data, which keeps the order of vertices and faces;
  // CGAL::copy_face_graph does not).
  // The stages run on the template and the network each scaled by a power of two of their own to
  // a unit-sized box (exact; see coordinate_range.h and deform_template_in_place): the result,
  // in the network's frame, is scaled back by `unit`.
  const double template_unit = internal::unit_scale(internal::checked_template_box(tm, vpm));
  const double unit = internal::unit_scale(input_network.bbox());
  const Curve_network scaled_network = unit == 1 ? Curve_network() : internal::scaled(input_network, unit);
  const Curve_network& network = unit == 1 ? input_network : scaled_network;
  // (A Work_mesh, built from template_data, whatever TriangleMesh is: the caller's points may be of
  // any Cartesian kernel over double.)
  Mesh_data template_data = to_mesh_data(tm, CGAL::parameters::vertex_point_map(vpm));
  for (Point_3& p : template_data.points) p = internal::scaled(p, template_unit);

  // Stages 1-3 and the verification, compiled once (src/fit.cpp); `result` is in the network's frame.
  internal::Work_mesh work;
  Mesh_data result;
  internal::fit_work(template_data, network, pairs, options, unit, report, work, result);

  // The added vertices' attributes, computed before `tm` changes (a solve that throws leaves it
  // as it was); see internal/vertex_attributes.h.
  auto attributes = internal::carried_attributes(np);
  attributes.extend(tm, result);

  const internal::Committed_elements<TriangleMesh> committed = internal::commit_work(work, result, tm, vpm);
  internal::put_patches_and_curves(result, tm, committed.vertex_of, committed.face_of, np);
  attributes.write(committed.vertex_of);
  report.total_seconds = internal::seconds_since(t0);
  return report;
}

}  // namespace meshfit

#endif  // MESHFIT_FIT_H
