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
#include <meshfit/flip.h>
#include <meshfit/internal/clear_mesh.h>
#include <meshfit/internal/commit_result.h>
#include <meshfit/internal/resample_network.h>
#include <meshfit/internal/stage_support.h>
#include <meshfit/internal/subdivide.h>
#include <meshfit/internal/triangle_corners.h>
#include <meshfit/internal/unit_scale.h>
#include <meshfit/memory_limit.h>
#include <meshfit/parameters.h>
#include <meshfit/partition.h>
#include <meshfit/rbf.h>
#include <meshfit/untangle.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Dynamic_property_map.h>
#include <CGAL/Named_function_parameters.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/named_params_helper.h>

#include <algorithm>
#include <chrono>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <queue>
#include <set>
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
  /// Steps 1-4 ran more than once (an earlier start left defects).
  bool approach_retried = false;
  /// Points added on long segments (deform_fine_on_surface, step 0), which become mesh vertices.
  std::size_t network_points_added = 0;
  /// Steps of midpoint subdivision of the template before the coarse level (deform_template),
  /// each splitting every face into four: a template with fewer than twice as many vertices as
  /// the network leaves the curves no free vertex between them.
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
  os << ": where curves run close together, use a finer template (subdivide it) or sparser curves; elsewhere, "
        "give more correspondences so that the coarse level brings the template closer to the curves";
  return os.str();
}

}  // namespace meshfit

#include <meshfit/internal/deform_impl.h>

namespace meshfit {


namespace internal {
/// deform_coarse on `tm` itself. For meshes the pipeline owns (a Stage_copy, fit's copy).
template <typename TriangleMesh, typename NamedParameters>
Deformation_report deform_coarse_in_place(TriangleMesh& tm, const Curve_network& network,
                                          const std::vector<Correspondence>& pairs, const NamedParameters& np) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  const auto t0 = std::chrono::steady_clock::now();
  const Rbf_kernel kernel = choose_parameter(get_parameter(np, internal_np::rbf_kernel), Rbf_kernel::linear);
  const auto progress = get_parameter(np, internal_np::progress);

  internal::Deform_state<TriangleMesh, decltype(internal::vertex_point_map_of(tm, np))> s(
      tm, internal::vertex_point_map_of(tm, np));
  internal::check_pairs(pairs, s.vertex.size(), num_faces(tm), network);
  internal::report_progress(progress, "deform", "coarse: fitting the RBF through the user's pairs", 0, 2);
  std::vector<Point_3> centres, values;
  std::vector<Vector_3> normals;
  // An open template that faces one way (its vector area, the sum of its faces' area vectors, at
  // least a tenth of its area: a disc, a patch, not a closed bag with a pin hole) gets its
  // orientation from the pairs' layout along it (Rbf_interpolant::fit), its facing as the normal.
  Vector_3 facing(0, 0, 0);
  double area = 0;
  if (!CGAL::is_closed(tm))
    for (auto f : faces(tm)) {
      const auto h = halfedge(f, tm);
      const Point_3 a = s.to_point(source(h, tm)), b = s.to_point(target(h, tm)),
                    c = s.to_point(target(next(h, tm), tm));
      const Vector_3 n = CGAL::cross_product(b - a, c - a);
      facing = facing + n;
      area += std::sqrt(n.squared_length());
    }
  const bool open_facing = area > 0 && std::sqrt(facing.squared_length()) >= 0.1 * area;
  for (const Correspondence& c : pairs) {
    centres.push_back(s.to_point(s.vertex[c.template_vertex]));
    values.push_back(network.point(c.network_vertex));
    normals.push_back(open_facing ? facing : s.normal(c.template_vertex));
  }
  Deformation_report report;
  report.user_pairs = pairs.size();
  const Rbf_interpolant E =
      Rbf_interpolant::fit(centres, values, kernel, normals, &report.coarse_fit, 0, open_facing);
  internal::report_progress(progress, "deform", "coarse: moving the template", 1, 2);
  const std::vector<Point_3> before = s.positions();
  std::vector<Point_3> p;
  E.evaluate(before, p);
  for (const Correspondence& c : pairs) p[c.template_vertex] = network.point(c.network_vertex);
  // Orientation is judged against the affine part of E, not against the template's own
  // placement: a rotation of the template (any angle) has det R > 0 and flips nothing, a mirror
  // has det R < 0. The faces counted as flipped are those that the RBF part turns over relative
  // to the affine image of the template (exact flip counter), so the count, too, is unchanged by
  // a rigid motion or a uniform scaling of either input.
  report.coarse_affine_determinant = E.affine_determinant();
  report.orientation_reversed = !(report.coarse_affine_determinant > 0);
  std::vector<Point_3> affine_image(before.size());
  for (std::size_t i = 0; i < before.size(); ++i) affine_image[i] = E.affine_part(before[i]);
  std::size_t degenerate = 0;
  report.coarse_flipped_faces = s.flipped_faces(affine_image, p, degenerate).size();
  s.set_positions(p);
  report.coarse_seconds = internal::seconds_since(t0);
  report.vertices = num_vertices(tm);
  report.faces = num_faces(tm);
  report.mesh_vertex_of_network_vertex.assign(network.number_of_vertices(), Closest_point_assignment::unassigned);
  for (const Correspondence& c : pairs) report.mesh_vertex_of_network_vertex[c.network_vertex] = c.template_vertex;
  return report;
}
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
///     \cgalParamDefault{`meshfit::Rbf_kernel::linear` (φ(r) = r)}
///   \cgalParamNEnd
///   \cgalParamNBegin{progress}
///     \cgalParamDescription{a callback called at each step with a meshfit::Progress_step (stage `"deform"`)}
///     \cgalParamType{a callable taking `const meshfit::Progress_step&` and returning `bool` (`false` cancels) or
///       `void` (never cancels)}
///     \cgalParamDefault{none: no calls, no cancelling}
///     \cgalParamExtra{When it returns `false`, the stage throws meshfit::Algorithm_failure.}
///   \cgalParamNEnd
/// \cgalNamedParamsEnd
///
/// \throws Invalid_input for pairs out of range or an RBF that they cannot define (see
///         Rbf_interpolant::fit); Numerical_error when the solve fails.
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Deformation_report deform_coarse(TriangleMesh& tm, const Curve_network& network,
                                 const std::vector<Correspondence>& pairs,
                                 const NamedParameters& np = CGAL::parameters::default_values()) {
  return internal::run_on_copy(tm, np, [&](internal::Work_mesh& work, const auto& work_np) {
    return internal::deform_coarse_in_place(work, network, pairs, work_np);
  });
}

namespace internal {
/// deform_fine on `tm` itself: the mesh changes as the work goes (a cancel or a failure leaves it
/// partly changed). For meshes the pipeline owns (a Stage_copy, fit's copy).
template <typename TriangleMesh, typename NamedParameters>
Deformation_report deform_fine_in_place(TriangleMesh& tm, const Curve_network& network,
                                    const std::vector<Correspondence>& pairs, const NamedParameters& np) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  using GT = boost::graph_traits<TriangleMesh>;
  const auto t0 = std::chrono::steady_clock::now();
  const Rbf_kernel kernel = choose_parameter(get_parameter(np, internal_np::rbf_kernel), Rbf_kernel::linear);
  const Curve_density density =
      choose_parameter(get_parameter(np, internal_np::curve_density), Curve_density::refine);
  const std::size_t max_rounds = internal::flip_prevention_rounds(np);
  const auto progress = get_parameter(np, internal_np::progress);
  const std::size_t memory_limit = choose_parameter(get_parameter(np, internal_np::memory_limit), std::size_t(0));

  auto vpm = internal::vertex_point_map_of(tm, np);
  internal::Deform_state<TriangleMesh, decltype(vpm)> s(tm, vpm);
  internal::check_pairs(pairs, s.vertex.size(), num_faces(tm), network);
  internal::check_polylines_near(tm, vpm, network);
  if (density == Curve_density::refine) {  // every network vertex will be a centre of the fine RBF
    const double n = static_cast<double>(network.number_of_vertices() + 4);
    check_memory_estimate(2 * 8 * n * n, memory_limit, "deform",
                          "the fine RBF through all " + std::to_string(network.number_of_vertices()) +
                              " network vertices (a dense system of as many unknowns)");
  }
  Deformation_report report;
  report.fine_level = Fine_level::thesis;
  report.user_pairs = pairs.size();
  // Vertices of no face (unused) are no candidates for the closest-point pairs and do not move.
  std::vector<bool> used(s.vertex.size());
  for (std::size_t i = 0; i < s.vertex.size(); ++i) used[i] = halfedge(s.vertex[i], tm) != GT::null_halfedge();
  // Flip prevention adds vertices; beyond this many it is not converging.
  const std::size_t max_vertices = 8 * (s.vertex.size() + network.number_of_vertices());

  // Pairs kept from round to round: the user's, then those made for density and flips.
  std::vector<Correspondence> fixed = pairs;
  const std::size_t user_pairs = pairs.size();
  // Density refinement repeats while it makes progress (a loser whose nearest point is taken by
  // a nearer network vertex may need several passes), within a bound.
  std::size_t refine_passes = 0, last_losers = SIZE_MAX;
  const std::size_t max_refine_passes = 32;

  // Gives each listed network vertex a mesh vertex at its nearest point on the surface (one per
  // face and call) and pins it there; splits `centroid_faces` at their centroids. Moving such a
  // vertex onto its network vertex is a motion along the normal, which flips nothing. Returns
  // the number of new vertices.
  auto pin_at_projections = [&](const std::vector<std::size_t>& network_vertices,
                                const std::vector<typename GT::face_descriptor>& centroid_faces) {
    using Primitive = CGAL::AABB_face_graph_triangle_primitive<TriangleMesh, decltype(vpm)>;
    using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
    std::map<typename GT::face_descriptor, std::pair<std::size_t, Point_3>> at;
    if (!network_vertices.empty()) {
      Tree tree(faces(tm).first, faces(tm).second, tm, vpm);
      tree.accelerate_distance_queries();
      for (std::size_t v : network_vertices) {
        const auto hit = tree.closest_point_and_primitive(network.point(v));
        at.emplace(hit.second, std::make_pair(v, Point_3(hit.first.x(), hit.first.y(), hit.first.z())));
      }
    }
    const std::size_t before_count = s.vertex.size();
    std::vector<bool> reserved(s.vertex.size(), false);
    for (const Correspondence& c : fixed) reserved[c.template_vertex] = true;
    for (const auto& [f, vp] : at) {
      const std::size_t network_vertex = vp.first;  // (lambdas cannot capture structured bindings)
      const std::size_t t = s.insert_near(f, vp.second, reserved);
      reserved.resize(s.vertex.size(), false);
      reserved[t] = true;
      // A network vertex pinned before is re-pinned (never one of the user's pairs).
      bool users = false;
      for (std::size_t k = 0; k < fixed.size(); ++k) {
        if (fixed[k].network_vertex != network_vertex) continue;
        if (k < user_pairs) {
          users = true;
        } else {
          fixed.erase(fixed.begin() + static_cast<std::ptrdiff_t>(k));
          break;
        }
      }
      if (users) continue;
      Correspondence c;
      c.template_vertex = t;
      c.network_vertex = network_vertex;
      fixed.push_back(c);
    }
    for (auto f : centroid_faces)
      if (!at.count(f)) s.split_face(f);
    return s.vertex.size() - before_count;
  };

  std::vector<Point_3> moved;
  Closest_point_assignment assignment;
  for (std::size_t round = 0;; ++round) {
    std::vector<Point_3> before = s.positions();
    used.resize(s.vertex.size(), true);  // (vertices inserted since are on faces)
    assignment = closest_point_correspondences(before, network, fixed, Loser_rule::drop, used);

    if (!assignment.losers.empty() && density == Curve_density::refine &&
        refine_passes < max_refine_passes && assignment.losers.size() < last_losers) {
      ++refine_passes;
      last_losers = assignment.losers.size();
      internal::report_progress(progress, "deform", "fine: refining where the curves are denser than the template",
                                refine_passes - 1, max_refine_passes);
      report.vertices_inserted_for_density += pin_at_projections(assignment.losers, {});
      --round;  // refinement is not a flip round
      continue;
    }

    internal::report_progress(progress, "deform", "fine: RBF through the correspondences and flip detection", round,
                              max_rounds);
    std::vector<Point_3> centres, values;
    std::vector<std::pair<std::size_t, std::size_t>> placed;  // (mesh vertex, network vertex)
    for (std::size_t v = 0; v < assignment.template_of.size(); ++v) {
      const std::size_t t = assignment.template_of[v];
      if (t == Closest_point_assignment::unassigned) continue;
      centres.push_back(before[t]);
      values.push_back(network.point(v));
      placed.emplace_back(t, v);
    }
    const Rbf_interpolant E = Rbf_interpolant::fit(centres, values, kernel, {}, &report.fine_fit, memory_limit);
    moved.clear();
    E.evaluate(before, moved);
    for (const auto& [t, v] : placed) moved[t] = network.point(v);
    for (std::size_t t = 0; t < used.size(); ++t)
      if (!used[t]) moved[t] = before[t];
    report.fine_pairs = placed.size();

    const auto flipped = s.flipped_faces(before, moved, report.degenerate_faces_skipped);
    report.flip_rounds = round + 1;
    report.flips_found += flipped.size();
    if (flipped.empty() || round + 1 >= max_rounds) {
      report.remaining_flips = flipped.size();
      break;
    }
    // Local subdivision (§2.3.2): a face flips because a paired corner is pulled across it
    // towards its network vertex. That network vertex gets a vertex of its own at its nearest
    // point on the surface (pin_at_projections), and the corner is released; the correspondences
    // are then recomputed. Flipped faces with no paired corner are split at their centroid.
    std::vector<std::size_t> pulled;
    std::vector<typename GT::face_descriptor> unpaired;
    std::vector<std::size_t> network_of(s.vertex.size(), Closest_point_assignment::unassigned);
    for (const auto& [t, v] : placed) network_of[t] = v;
    for (auto f : flipped) {
      bool any = false;
      for (std::size_t t : s.corners(f))
        if (network_of[t] != Closest_point_assignment::unassigned && moved[t] != before[t]) {
          pulled.push_back(network_of[t]);
          any = true;
        }
      if (!any) unpaired.push_back(f);
    }
    std::sort(pulled.begin(), pulled.end());
    pulled.erase(std::unique(pulled.begin(), pulled.end()), pulled.end());
    if (s.vertex.size() + pulled.size() + unpaired.size() > max_vertices)
      throw Algorithm_failure("deform", "flip prevention stopped in round " + std::to_string(round + 1) + ": " +
                                            std::to_string(flipped.size()) + " faces flip, and subdividing them would "
                                            "grow the mesh past " + std::to_string(max_vertices) +
                                            " vertices (8 × (template + network vertices)); the coarse level leaves "
                                            "the template too far from the curves (more correspondences help)");
    const std::size_t split_before = s.faces_split;
    report.vertices_inserted_for_flips += pin_at_projections(pulled, unpaired);
    report.faces_subdivided += s.faces_split - split_before;
  }

  s.set_positions(moved);
  report.fine_done = true;
  // With Curve_density::refine these are the network vertices refinement could not serve.
  report.dropped_network_vertices = assignment.losers;
  report.mesh_vertex_of_network_vertex = assignment.template_of;
  report.fine_seconds = internal::seconds_since(t0);
  report.vertices = num_vertices(tm);
  report.faces = num_faces(tm);
  return report;
}
}  // namespace internal

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
///     \cgalParamDefault{`meshfit::Rbf_kernel::linear` (φ(r) = r)}
///   \cgalParamNEnd
///   \cgalParamNBegin{curve_density}
///     \cgalParamDescription{what becomes of a network vertex whose nearest template vertex is taken by another}
///     \cgalParamType{meshfit::Curve_density}
///     \cgalParamDefault{`meshfit::Curve_density::refine` (it gets a vertex of its own)}
///   \cgalParamNEnd
///   \cgalParamNBegin{flip_prevention_rounds}
///     \cgalParamDescription{the most rounds of flip prevention (detection, local subdivision, a new fit)}
///     \cgalParamType{an integer type}
///     \cgalParamDefault{`10`}
///     \cgalParamExtra{A negative value throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{memory_limit}
///     \cgalParamDescription{the most bytes the dense RBF system of the fine level (Fine_level::thesis) may take;
///       a larger system is refused with meshfit::Algorithm_failure before it is allocated}
///     \cgalParamType{`std::size_t`}
///     \cgalParamDefault{`0`, which means meshfit::default_memory_limit() (an eighth of the physical memory)}
///   \cgalParamNEnd
///   \cgalParamNBegin{progress}
///     \cgalParamDescription{a callback called at each step with a meshfit::Progress_step (stage `"deform"`)}
///     \cgalParamType{a callable taking `const meshfit::Progress_step&` and returning `bool` (`false` cancels) or
///       `void` (never cancels)}
///     \cgalParamDefault{none: no calls, no cancelling}
///     \cgalParamExtra{When it returns `false`, the stage throws meshfit::Algorithm_failure.}
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
  return internal::run_on_copy(tm, np, [&](internal::Work_mesh& work, const auto& work_np) {
    return internal::deform_fine_in_place(work, network, pairs, work_np);
  });
}


namespace internal {
/// deform_fine_on_surface on `tm` itself: the mesh changes as the work goes (a cancel or a failure leaves it
/// partly changed). For meshes the pipeline owns (a Stage_copy, fit's copy).
template <typename TriangleMesh, typename NamedParameters>
Deformation_report deform_fine_on_surface_in_place(TriangleMesh& tm, const Curve_network& network,
                                    const std::vector<Correspondence>& pairs, const NamedParameters& np) {
  auto vpm = internal::vertex_point_map_of(tm, np);
  internal::check_pairs(pairs, num_vertices(tm), num_faces(tm), network);
  const double h = internal::mean_edge_length(tm, vpm);
  std::vector<Segment_3> border;
  for (auto e : edges(tm))
    if (is_border(e, tm)) border.emplace_back(get(vpm, source(e, tm)), get(vpm, target(e, tm)));
  // Segments with both ends near the border (nearer to it than half an edge more than to the
  // surface, as in step 1) are not cut: a curve along the border becomes the border arc (step 2),
  // whatever the length of its segments.
  std::vector<bool> whole(network.number_of_segments(), false);
  if (!border.empty()) {
    using Primitive = CGAL::AABB_face_graph_triangle_primitive<TriangleMesh, decltype(vpm)>;
    using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
    std::unique_ptr<Tree> tree;
    std::vector<int> near(network.number_of_vertices(), -1);  // unknown, no, yes
    auto near_border = [&](std::size_t v) {
      if (near[v] < 0) {
        if (!tree) {
          tree = std::make_unique<Tree>(faces(tm).first, faces(tm).second, tm, vpm);
          tree->accelerate_distance_queries();
        }
        const Point_3& p = network.point(v);
        const double reach = std::sqrt(tree->squared_distance(p)) + 0.5 * h;
        near[v] = 0;
        for (const Segment_3& b : border)
          if (CGAL::squared_distance(b, p) <= reach * reach) {
            near[v] = 1;
            break;
          }
      }
      return near[v] == 1;
    };
    for (std::size_t k = 0; k < whole.size(); ++k) {
      const auto& sk = network.segments()[k];
      whole[k] = CGAL::squared_distance(network.point(sk[0]), network.point(sk[1])) > 4 * h * h && near_border(sk[0]) &&
                 near_border(sk[1]);
    }
  }
  const internal::Resampled_network cut = internal::resample_long_segments(network, h, whole);
  std::vector<Correspondence> cut_pairs = pairs;
  for (Correspondence& c : cut_pairs) c.network_vertex = cut.vertex_of[c.network_vertex];
  // Steps 1-4 on the cut network; the report in terms of the user's network.
  auto run = [&] {
    if (cut.added == 0) return internal::fine_on_surface(tm, network, pairs, np);
    Deformation_report r = internal::fine_on_surface(tm, cut.network, cut_pairs, np);
    r.network_points_added = cut.added;
    std::vector<std::size_t> mesh_of(network.number_of_vertices());
    for (std::size_t v = 0; v < mesh_of.size(); ++v) mesh_of[v] = r.mesh_vertex_of_network_vertex[cut.vertex_of[v]];
    r.mesh_vertex_of_network_vertex = std::move(mesh_of);
    std::vector<std::size_t> missing;
    for (std::size_t k : r.segments_not_embedded) missing.push_back(cut.segment_of[k]);
    std::sort(missing.begin(), missing.end());
    missing.erase(std::unique(missing.begin(), missing.end()), missing.end());
    r.segments_not_embedded = std::move(missing);
    r.segments_embedded = network.number_of_segments() - r.segments_not_embedded.size();
    return r;
  };
  // The mesh as points (through the point map, which may live outside the mesh) and triangles,
  // to go back to. Rebuilt in place, vertices and faces in their order (assigning a Surface_mesh
  // would leave the caller's property maps dangling); values of the caller's other properties on
  // the mesh are not carried over.
  struct Snapshot {
    std::vector<Point_3> points;
    std::vector<std::array<std::size_t, 3>> triangles;
  };
  auto points = [&] {
    std::vector<Point_3> out;
    for (auto v : vertices(tm)) {
      const auto p = get(vpm, v);
      out.emplace_back(p.x(), p.y(), p.z());
    }
    return out;
  };
  auto snapshot = [&] {
    Snapshot shot{points(), {}};
    auto index = get(CGAL::dynamic_vertex_property_t<std::size_t>(), tm);
    std::size_t i = 0;
    for (auto v : vertices(tm)) put(index, v, i++);
    for (auto f : faces(tm)) shot.triangles.push_back(internal::triangle_corners(f, tm, index));
    return shot;
  };
  auto restore = [&](const Snapshot& shot) {
    internal::clear_mesh(tm);
    using P = typename boost::property_traits<decltype(vpm)>::value_type;
    std::vector<typename boost::graph_traits<TriangleMesh>::vertex_descriptor> vertex;
    for (const Point_3& p : shot.points) {
      vertex.push_back(add_vertex(tm));
      put(vpm, vertex.back(), P(p.x(), p.y(), p.z()));
    }
    for (const auto& t : shot.triangles)
      if (CGAL::Euler::add_face(std::array{vertex[t[0]], vertex[t[1]], vertex[t[2]]}, tm) ==
          boost::graph_traits<TriangleMesh>::null_face())
        throw Numerical_error("deform: the mesh could not be rebuilt to run the fine level again");
  };
  auto defects = [](const Deformation_report& r) {
    return r.segments_not_embedded.size() + r.remaining_flips + r.remaining_folds;
  };
  // Three starts, tried in turn until one leaves no defect: the coarse surface brought towards the
  // curves by non-rigid ICP (internal::approach_curves_icp), by the thin-plate field through the
  // nearest template vertices (internal::approach_curves), and as it is. Each approach is made
  // from the coarse surface; when none is clean, the start with the fewest defects is kept (the
  // earlier on a tie), unless the last one fails with a reason.
  // A polyline far from the coarse surface is refused before any approach pulls the surface to it.
  internal::check_polylines_near(tm, vpm, network);
  const Snapshot coarse = snapshot();
  std::optional<Deformation_report> best;
  std::optional<Snapshot> best_mesh;
  std::size_t tried = 0;
  for (int start = 0; start < 3; ++start) {
    if (tried > 0) restore(coarse);
    internal::Approach_result approach;
    // Curves more than twice as dense as the template: no approach will give them room (step 2
    // refuses such inputs), and ICP would only move the template around.
    if (start == 0 && cut.network.number_of_vertices() <= 2 * num_vertices(tm))
      approach = internal::approach_curves_icp(tm, vpm, cut.network, cut_pairs);
    if (start == 1) approach = internal::approach_curves(tm, vpm, cut.network, cut_pairs);
    if (start < 2 && approach.scale == 0) continue;  // the approach made no motion: the same start as the last
    std::optional<Deformation_report> r;
    try {
      r = run();
    } catch (const Cancelled&) {
      throw;  // the caller's cancel, not a failure of this start
    } catch (const Algorithm_failure&) {
      // The last start's reason (from the coarse surface as it is) is said rather than a result
      // with defects kept.
      if (start == 2) throw;
    }
    ++tried;
    if (!r) continue;
    r->approach_constraints = approach.constraints;
    r->approach_scale = approach.scale;
    r->approach = start == 0 ? Approach::icp : start == 1 ? Approach::nearest_vertices : Approach::none;
    r->approach_retried = tried > 1;
    if (!best || defects(*r) < defects(*best)) {
      best = r;
      best_mesh.reset();
      if (defects(*r) == 0) return *best;
      best_mesh = snapshot();
    }
  }
  if (best_mesh) restore(*best_mesh);
  return *best;
}
}  // namespace internal

/// Fine level, Fine_level::surface, on a template already roughly in place (deform_coarse):
///   0. a segment longer than twice the template's mean edge is cut into pieces of about one edge
///      (points on the segment), unless both its ends lie near the border (as in step 1): a
///      long straight segment's ends project onto a curved surface far from where its middle
///      does, and the pieces follow the surface; the report speaks of the network's own
///      vertices and segments (`network_points_added` counts the points). Then the surface is
///      brought towards the curves: by non-rigid ICP (internal::approach_curves_icp: up to six
///      least-squares steps of falling stiffness, each asking that the point of the surface
///      tracked for every network vertex move onto it against the thin-plate energy of the
///      motion, each untangled, halved while it leaves a face turned over or a new fold, and
///      the last that cannot be made ending the approach);
///   1. every network vertex gets a mesh vertex at (or near) its point on the surface, tracked
///      along the curves from the user's pairs (internal::tracked_projections); the vertices of
///      curves running along the border go onto the border (a curve runs along it when its
///      nearest border points trace at least half its length), the other vertices stay off it;
///      a face or an edge is split, or a template vertex already there reused; the user's pairs
///      keep their template vertices;
///   2. every segment becomes a chain of mesh edges on this surface, where nothing is folded:
///      the border arc for a segment along the border, stage 2's insertion (partition_mesh on
///      the network as projected) for the others, and the shortest edge path crossing no chain
///      where that insertion refuses;
///   3. the network vertices are moved onto their points, the inner vertices of each chain onto
///      the segment, and every other vertex by the thin-plate displacement field through those
///      motions (interpolate_displacements); when that leaves faces turned over or folded, the
///      motion is made again in four equal parts, with step 4a's untangling after each;
///   4. faces that turn over against the coarse surface's normals, or fold with a neighbour,
///      are repaired: the free vertices around them are relaxed towards their neighbours' mean
///      (up to 3 rings, for at most `flip_prevention_rounds` rounds, default 10, the best state
///      kept), and an edge of a bad face whose corners are all held is flipped when both new
///      faces are good. `report.remaining_flips` and `report.remaining_folds` are what is left.
/// Vertices are added only in step 1 (at most one per network vertex and added point), after the
/// existing ones. When steps 1-4 after the ICP approach leave defects (segments not embedded,
/// faces turned over or folded), they run again from the coarse surface after the older approach
/// (internal::approach_curves: the thin-plate field through the motions of the curves' surface
/// points given to template vertices three edges apart, unless even an eighth of it turns a face
/// over or folds an edge), and then without approach; the result with the fewest defects is kept
/// (`approach`, `approach_retried`; the earlier on a tie).
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
///     \cgalParamDefault{`10`}
///     \cgalParamExtra{A negative value throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{progress}
///     \cgalParamDescription{a callback called at each step with a meshfit::Progress_step (stage `"deform"`)}
///     \cgalParamType{a callable taking `const meshfit::Progress_step&` and returning `bool` (`false` cancels) or
///       `void` (never cancels)}
///     \cgalParamDefault{none: no calls, no cancelling}
///     \cgalParamExtra{When it returns `false`, the stage throws meshfit::Algorithm_failure. The embedding's insertion (step 2) reports its steps as this stage's.}
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
  return internal::run_on_copy(tm, np, [&](internal::Work_mesh& work, const auto& work_np) {
    return internal::deform_fine_on_surface_in_place(work, network, pairs, work_np);
  });
}

namespace internal {
/// deform_template on the inputs as they are.
template <typename TriangleMesh, typename NamedParameters>
Deformation_report deform_template_unscaled(TriangleMesh& tm, const Curve_network& network,
                                            const std::vector<Correspondence>& pairs, const NamedParameters& np) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  const bool coarse_only = choose_parameter(get_parameter(np, internal_np::coarse_only), false);
  const Fine_level level = choose_parameter(get_parameter(np, internal_np::fine_level), Fine_level::surface);
  const Curve_density density = choose_parameter(get_parameter(np, internal_np::curve_density), Curve_density::refine);
  // The surface fine level gives every network vertex a mesh vertex and needs free vertices
  // between the curves: a template with fewer than twice the network's vertices is subdivided
  // (before the coarse level, so that the new vertices follow the RBF rather than the chords),
  // at most three times and to at most max_subdivided_faces faces.
  std::size_t subdivisions = 0;
  const bool surface_refined = level == Fine_level::surface && density == Curve_density::refine && !coarse_only;
  if (surface_refined) {
    // Before the subdivision, whose new vertices would make an out-of-range template index valid.
    check_pairs(pairs, num_vertices(tm), num_faces(tm), network);
    while (subdivisions < 3 && num_vertices(tm) < 2 * network.number_of_vertices() &&
           4 * num_faces(tm) <= max_subdivided_faces) {
      subdivide_at_midpoints(tm, vertex_point_map_of(tm, np));
      ++subdivisions;
    }
  }
  Deformation_report coarse = deform_coarse_in_place(tm, network, pairs, np);
  coarse.template_subdivisions = subdivisions;
  if (coarse.orientation_reversed || coarse_only) return coarse;
  if (surface_refined) refuse_oversampled_curves(tm, vertex_point_map_of(tm, np), network, subdivisions);
  Deformation_report fine = level == Fine_level::surface ? deform_fine_on_surface_in_place(tm, network, pairs, np)
                                                         : deform_fine_in_place(tm, network, pairs, np);
  fine.coarse_fit = coarse.coarse_fit;
  fine.coarse_seconds = coarse.coarse_seconds;
  fine.coarse_flipped_faces = coarse.coarse_flipped_faces;
  fine.orientation_reversed = coarse.orientation_reversed;
  fine.coarse_affine_determinant = coarse.coarse_affine_determinant;
  fine.template_subdivisions = subdivisions;
  return fine;
}
}  // namespace internal

namespace internal {
/// deform_template on `tm` itself: the mesh changes as the work goes (a cancel or a failure leaves it
/// partly changed). For meshes the pipeline owns (a Stage_copy, fit's copy).
template <typename TriangleMesh, typename NamedParameters>
Deformation_report deform_template_in_place(TriangleMesh& tm, const Curve_network& network,
                                    const std::vector<Correspondence>& pairs, const NamedParameters& np) {
  // The template and the network are each scaled to a unit-sized box, by powers of two of their
  // own: the coarse level maps the one onto the other whatever their relative size (a template
  // in millimetres, curves in metres), and everything after it works in the network's frame.
  const auto vpm = internal::vertex_point_map_of(tm, np);
  const double st = internal::unit_scale(internal::checked_template_box(tm, vpm));
  const double sn = internal::unit_scale(network.bbox());
  if (st == 1 && sn == 1) return internal::deform_template_unscaled(tm, network, pairs, np);
  const Curve_network unit_network = sn == 1 ? network : internal::scaled(network, sn);
  internal::scale_points(tm, vpm, st);
  Deformation_report r;
  try {
    r = internal::deform_template_unscaled(tm, unit_network, pairs, np);
  } catch (...) {
    internal::scale_points(tm, vpm, 1 / st);
    throw;
  }
  internal::scale_points(tm, vpm, 1 / sn);
  r.largest_projection_distance /= sn;
  return r;
}
}  // namespace internal

/// Both levels: deform_coarse then the fine level (unless the named parameter `coarse_only` is
/// true): deform_fine_on_surface, or deform_fine with `fine_level(Fine_level::thesis)`.
/// With the surface fine level and Curve_density::refine (the defaults), a template with fewer
/// than twice as many vertices as the network is first subdivided at its edges' midpoints (every
/// face into four; at most three times, to at most 2e6 faces; `template_subdivisions`): the
/// template's vertices keep their indices, the new ones come after them.
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
///     \cgalParamDefault{`false`}
///   \cgalParamNEnd
///   \cgalParamNBegin{fine_level}
///     \cgalParamDescription{the method of the fine level}
///     \cgalParamType{meshfit::Fine_level}
///     \cgalParamDefault{`meshfit::Fine_level::surface` (deform_fine_on_surface; `Fine_level::thesis`: deform_fine)}
///   \cgalParamNEnd
///   \cgalParamNBegin{rbf_kernel}
///     \cgalParamDescription{the basis function φ of the interpolants (the coarse one, and the fine one of `Fine_level::thesis`) (rbf.h)}
///     \cgalParamType{meshfit::Rbf_kernel}
///     \cgalParamDefault{`meshfit::Rbf_kernel::linear` (φ(r) = r)}
///   \cgalParamNEnd
///   \cgalParamNBegin{curve_density}
///     \cgalParamDescription{what becomes of a network vertex whose nearest template vertex is taken by another}
///     \cgalParamType{meshfit::Curve_density}
///     \cgalParamDefault{`meshfit::Curve_density::refine` (it gets a vertex of its own)}
///   \cgalParamNEnd
///   \cgalParamNBegin{flip_prevention_rounds}
///     \cgalParamDescription{the most rounds of flip prevention (`Fine_level::thesis`) or of untangling (`Fine_level::surface`)}
///     \cgalParamType{an integer type}
///     \cgalParamDefault{`10`}
///     \cgalParamExtra{A negative value throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{memory_limit}
///     \cgalParamDescription{the most bytes the dense RBF system of the fine level (Fine_level::thesis) may take;
///       a larger system is refused with meshfit::Algorithm_failure before it is allocated}
///     \cgalParamType{`std::size_t`}
///     \cgalParamDefault{`0`, which means meshfit::default_memory_limit() (an eighth of the physical memory)}
///     \cgalParamExtra{Read by the fine level `Fine_level::thesis` only.}
///   \cgalParamNEnd
///   \cgalParamNBegin{progress}
///     \cgalParamDescription{a callback called at each step with a meshfit::Progress_step (stage `"deform"`)}
///     \cgalParamType{a callable taking `const meshfit::Progress_step&` and returning `bool` (`false` cancels) or
///       `void` (never cancels)}
///     \cgalParamDefault{none: no calls, no cancelling}
///     \cgalParamExtra{When it returns `false`, the stage throws meshfit::Algorithm_failure.}
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
  return internal::run_on_copy(tm, np, [&](internal::Work_mesh& work, const auto& work_np) {
    return internal::deform_template_in_place(work, network, pairs, work_np);
  });
}


}  // namespace meshfit

#endif  // MESHFIT_DEFORM_H
