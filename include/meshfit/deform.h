// meshfit: stage 1, global deformation of the template onto the curve network (thesis ch. 2).
//
//   coarse  an RBF through the user's pairs moves the whole template (eq. 2.6–2.10);
//   fine    every network vertex is paired with its nearest template vertex (§2.1), and a second
//           RBF through those pairs puts each paired template vertex exactly on its network
//           vertex; faces the fine motion would flip (§2.3.1, exact flip counter) are subdivided
//           and the correspondences recomputed until no face flips (§2.3.2).
#ifndef MESHFIT_DEFORM_H
#define MESHFIT_DEFORM_H

#include <meshfit/correspondence.h>
#include <meshfit/curve_network.h>
#include <meshfit/exceptions.h>
#include <meshfit/flip.h>
#include <meshfit/internal/stage_support.h>
#include <meshfit/internal/triangle_corners.h>
#include <meshfit/parameters.h>
#include <meshfit/rbf.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Dynamic_property_map.h>
#include <CGAL/Named_function_parameters.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/named_params_helper.h>

#include <chrono>
#include <map>
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

/// What a deformation did.
struct Deformation_report {
  // coarse level
  std::size_t user_pairs = 0;
  Rbf_fit_report coarse_fit;
  double coarse_seconds = 0;
  std::size_t coarse_flipped_faces = 0;    ///< faces the coarse motion flips (exact flip counter)
  /// More than half the faces flip at the coarse level: the pairs mirror the template.
  bool orientation_reversed = false;
  std::size_t degenerate_faces_skipped = 0;  ///< zero-area faces before the fine motion: not judged
  // fine level
  bool fine_done = false;
  std::size_t fine_pairs = 0;              ///< pairs of the final fine RBF (user + closest point + refined)
  std::size_t flip_rounds = 0;             ///< rounds of detection (1 when nothing flipped)
  std::size_t flips_found = 0;             ///< flipped or degenerate faces found, over all rounds
  std::size_t faces_subdivided = 0;        ///< faces split by flip prevention
  std::size_t remaining_flips = 0;         ///< after the last round: non-zero means failure
  std::size_t vertices_inserted_for_density = 0;  ///< Curve_density::refine
  std::size_t vertices_inserted_for_flips = 0;    ///< by flip prevention
  std::vector<std::size_t> dropped_network_vertices;  ///< Curve_density::drop: not represented
  Rbf_fit_report fine_fit;
  double fine_seconds = 0;
  // result
  std::size_t vertices = 0, faces = 0;
  /// For each network vertex, the index (in the order of vertices(tm)) of the mesh vertex placed
  /// on it, or Closest_point_assignment::unassigned when it was dropped.
  std::vector<std::size_t> mesh_vertex_of_network_vertex;
};

namespace internal {

template <typename TriangleMesh, typename VPM>
struct Deform_state {
  using GT = boost::graph_traits<TriangleMesh>;
  using vertex_descriptor = typename GT::vertex_descriptor;
  using face_descriptor = typename GT::face_descriptor;

  TriangleMesh& tm;
  VPM vpm;
  std::vector<vertex_descriptor> vertex;  // index -> descriptor, in the order of vertices(tm)
  typename boost::property_map<TriangleMesh, CGAL::dynamic_vertex_property_t<std::size_t>>::type index;

  Deform_state(TriangleMesh& m, VPM p)
      : tm(m), vpm(p), index(get(CGAL::dynamic_vertex_property_t<std::size_t>(), m)) {
    for (auto v : vertices(tm)) {
      put(index, v, vertex.size());
      vertex.push_back(v);
    }
  }

  std::vector<Point_3> positions() const {
    std::vector<Point_3> p;
    p.reserve(vertex.size());
    for (auto v : vertex) p.push_back(to_point(v));
    return p;
  }
  void set_positions(const std::vector<Point_3>& p) {
    using P = typename boost::property_traits<VPM>::value_type;
    for (std::size_t i = 0; i < vertex.size(); ++i) put(vpm, vertex[i], P(p[i].x(), p[i].y(), p[i].z()));
  }
  std::array<std::size_t, 3> corners(face_descriptor f) const { return triangle_corners(f, tm, index); }

  /// The faces that moving the vertices from `before` to `after` flips or collapses (exact flip
  /// counter). A face of zero area before the motion has no plane to flip in, and subdividing it
  /// would not change that: it is counted in `degenerate`, not judged.
  std::vector<face_descriptor> flipped_faces(const std::vector<Point_3>& before, const std::vector<Point_3>& after,
                                             std::size_t& degenerate) const {
    std::vector<face_descriptor> flipped;
    degenerate = 0;
    for (auto f : faces(tm)) {
      const auto c = corners(f);
      const Triangle_points b{before[c[0]], before[c[1]], before[c[2]]};
      if (orientation_in_plane(b, b[0], b[1], b[2]) == CGAL::ZERO) {
        ++degenerate;
        continue;
      }
      if (flip_counter(b, {after[c[0]], after[c[1]], after[c[2]]}).state() != Flip_state::kept) flipped.push_back(f);
    }
    return flipped;
  }
  using Point = typename boost::property_traits<VPM>::value_type;
  std::size_t faces_split = 0;  ///< by the split functions below

  std::size_t add_index(vertex_descriptor v) {
    put(index, v, vertex.size());
    vertex.push_back(v);
    return vertex.size() - 1;
  }
  /// Splits `f` at `p` (which must lie inside it); returns the new vertex's index.
  std::size_t split_face_at(face_descriptor f, const Point_3& p) {
    const auto h = CGAL::Euler::add_center_vertex(halfedge(f, tm), tm);
    put(vpm, target(h, tm), Point(p.x(), p.y(), p.z()));
    ++faces_split;
    return add_index(target(h, tm));
  }
  /// Splits `f` at its centroid; returns the new vertex's index.
  std::size_t split_face(face_descriptor f) {
    const auto c = corners(f);
    const Point_3 p[3] = {to_point(vertex[c[0]]), to_point(vertex[c[1]]), to_point(vertex[c[2]])};
    return split_face_at(f, Point_3((p[0].x() + p[1].x() + p[2].x()) / 3, (p[0].y() + p[1].y() + p[2].y()) / 3,
                                    (p[0].z() + p[1].z() + p[2].z()) / 3));
  }
  /// Splits the edge of halfedge `h` at `p` and the one or two faces beside it into two each.
  std::size_t split_edge_at(typename GT::halfedge_descriptor h, const Point_3& p) {
    const auto hnew = CGAL::Euler::split_edge(h, tm);  // source(h) -> new vertex -> target(h)
    const vertex_descriptor x = target(hnew, tm);
    put(vpm, x, Point(p.x(), p.y(), p.z()));
    if (!is_border(hnew, tm)) {
      CGAL::Euler::split_face(hnew, next(h, tm), tm);
      ++faces_split;
    }
    const auto o = opposite(h, tm);
    if (!is_border(o, tm)) {
      CGAL::Euler::split_face(o, next(opposite(hnew, tm), tm), tm);
      ++faces_split;
    }
    return add_index(x);
  }
  /// A vertex at (or near) `p`, a point of face `f`: a new vertex inside the face or on one of its
  /// edges, or, when `p` is near a corner, that corner if it is not `reserved` (else a new vertex
  /// at the centroid of `f`). Returns its index.
  std::size_t insert_near(face_descriptor f, const Point_3& p, const std::vector<bool>& reserved) {
    const auto c = corners(f);
    const Point_3 t[3] = {to_point(vertex[c[0]]), to_point(vertex[c[1]]), to_point(vertex[c[2]])};
    // Barycentric coordinates of p (a placement choice, not a geometric decision: whatever is
    // made here is checked by the flip detection). Splitting near an edge or a corner would
    // make slivers: near an edge the edge is split instead, near a corner the face's centroid.
    const Vector_3 n = CGAL::cross_product(t[1] - t[0], t[2] - t[0]);
    const double area2 = n.squared_length();
    double l[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
    if (area2 > 0)
      for (int k = 0; k < 3; ++k)
        l[k] = CGAL::cross_product(t[(k + 1) % 3] - p, t[(k + 2) % 3] - p) * n / area2;
    constexpr double margin = 0.15;
    int small = 0, which = 0;
    for (int k = 0; k < 3; ++k)
      if (l[k] < margin) { ++small; which = k; }
    if (small == 0) return split_face_at(f, p);
    if (small == 1) {
      // The edge opposite corner `which`: split it at p's position along it, kept off its ends.
      const std::size_t a = c[(which + 1) % 3];
      const Point_3 &pa = t[(which + 1) % 3], &pb = t[(which + 2) % 3];
      auto h = halfedge(f, tm);
      while (get(index, source(h, tm)) != a) h = next(h, tm);
      const double len2 = CGAL::squared_distance(pa, pb);
      double u = len2 > 0 ? ((p - pa) * (pb - pa)) / len2 : 0.5;
      u = std::min(1 - margin, std::max(margin, u));
      return split_edge_at(h, pa + u * (pb - pa));
    }
    // Near a corner: that corner is already (almost) at p; use it unless it is taken.
    int corner = 0;
    for (int k = 1; k < 3; ++k)
      if (l[k] > l[corner]) corner = k;
    if (c[corner] >= reserved.size() || !reserved[c[corner]]) return c[corner];
    return split_face(f);
  }
  Point_3 to_point(vertex_descriptor v) const { return point_of<TriangleMesh>(vpm, v); }
  Vector_3 normal(std::size_t i) const {
    const auto n = CGAL::Polygon_mesh_processing::compute_vertex_normal(vertex[i], tm,
                                                                        CGAL::parameters::vertex_point_map(vpm));
    return Vector_3(n.x(), n.y(), n.z());
  }
};

inline void check_pairs(const std::vector<Correspondence>& pairs, std::size_t template_vertices,
                        std::size_t template_faces, const Curve_network& network) {
  if (template_faces == 0) throw Invalid_input("deform: the template has no face");
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Correspondence& c = pairs[i];
    if (c.template_vertex >= template_vertices || c.network_vertex >= network.number_of_vertices())
      throw Invalid_input(c.where, "pair " + std::to_string(i) + " (" + std::to_string(c.template_vertex) +
                                       ", " + std::to_string(c.network_vertex) + ") is out of range: " +
                                       std::to_string(template_vertices) + " template vertices, " +
                                       std::to_string(network.number_of_vertices()) + " network vertices");
  }
}

}  // namespace internal

/// Coarse level: moves every vertex of `tm` with the RBF interpolant through the user's `pairs`
/// (template vertex position → network vertex). Vertex i is the i-th of vertices(tm).
/// Named parameters: `vertex_point_map`, `rbf_kernel`, `progress`.
/// \throws Invalid_input for pairs out of range or an RBF that they cannot define (see
///         Rbf_interpolant::fit); Numerical_error when the solve fails.
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Deformation_report deform_coarse(TriangleMesh& tm, const Curve_network& network,
                                 const std::vector<Correspondence>& pairs,
                                 const NamedParameters& np = CGAL::parameters::default_values()) {
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
  for (const Correspondence& c : pairs) {
    centres.push_back(s.to_point(s.vertex[c.template_vertex]));
    values.push_back(network.point(c.network_vertex));
    normals.push_back(s.normal(c.template_vertex));
  }
  Deformation_report report;
  report.user_pairs = pairs.size();
  const Rbf_interpolant E = Rbf_interpolant::fit(centres, values, kernel, normals, &report.coarse_fit);
  internal::report_progress(progress, "deform", "coarse: moving the template", 1, 2);
  const std::vector<Point_3> before = s.positions();
  std::vector<Point_3> p;
  E.evaluate(before, p);
  for (const Correspondence& c : pairs) p[c.template_vertex] = network.point(c.network_vertex);
  // A mirror image (an affine part with negative determinant) flips every face: report it as an
  // orientation reversal rather than as many flips.
  std::size_t degenerate = 0;
  report.coarse_flipped_faces = s.flipped_faces(before, p, degenerate).size();
  const std::size_t judged = num_faces(tm) - degenerate;
  report.orientation_reversed = judged > 0 && 2 * report.coarse_flipped_faces > judged;
  s.set_positions(p);
  report.coarse_seconds = internal::seconds_since(t0);
  report.vertices = num_vertices(tm);
  report.faces = num_faces(tm);
  report.mesh_vertex_of_network_vertex.assign(network.number_of_vertices(), Closest_point_assignment::unassigned);
  for (const Correspondence& c : pairs) report.mesh_vertex_of_network_vertex[c.network_vertex] = c.template_vertex;
  return report;
}

/// Fine level, on a template already roughly in place (deform_coarse): pairs every network vertex
/// with its nearest template vertex (user `pairs` are kept), fits an RBF through all pairs and
/// moves the template so that each paired vertex lies exactly on its network vertex. When the
/// motion would flip faces (exact flip counter, judged against the positions before this call),
/// the network vertices pulling them get mesh vertices of their own at their nearest points on the
/// surface (local subdivision), and everything is redone, for at most `number_of_iterations`
/// rounds (default 10); `report.remaining_flips` tells whether that was enough. With
/// Curve_density::refine (default) network vertices that lost their nearest template vertex get a
/// vertex the same way; with Curve_density::drop they are dropped (reported), and only flip
/// prevention adds vertices. New vertices come after the existing ones. Named parameters:
/// `vertex_point_map`, `rbf_kernel`, `curve_density`, `number_of_iterations`, `progress`.
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Deformation_report deform_fine(TriangleMesh& tm, const Curve_network& network,
                               const std::vector<Correspondence>& pairs,
                               const NamedParameters& np = CGAL::parameters::default_values()) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  using GT = boost::graph_traits<TriangleMesh>;
  const auto t0 = std::chrono::steady_clock::now();
  const Rbf_kernel kernel = choose_parameter(get_parameter(np, internal_np::rbf_kernel), Rbf_kernel::linear);
  const Curve_density density =
      choose_parameter(get_parameter(np, internal_np::curve_density), Curve_density::refine);
  const std::size_t max_rounds =
      static_cast<std::size_t>(choose_parameter(get_parameter(np, CGAL::internal_np::number_of_iterations), 10));
  const auto progress = get_parameter(np, internal_np::progress);

  auto vpm = internal::vertex_point_map_of(tm, np);
  internal::Deform_state<TriangleMesh, decltype(vpm)> s(tm, vpm);
  internal::check_pairs(pairs, s.vertex.size(), num_faces(tm), network);
  Deformation_report report;
  report.user_pairs = pairs.size();

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
    assignment = closest_point_correspondences(before, network, fixed);

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
    const Rbf_interpolant E = Rbf_interpolant::fit(centres, values, kernel, {}, &report.fine_fit);
    moved.clear();
    E.evaluate(before, moved);
    for (const auto& [t, v] : placed) moved[t] = network.point(v);
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

/// Both levels: deform_coarse then deform_fine (unless the named parameter `coarse_only` is true).
/// The report holds the figures of both. When the coarse level reverses the orientation (pairs
/// that mirror the template), the fine level is not run: the report says so and the caller
/// decides (the command line fails with exit status 3).
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Deformation_report deform_template(TriangleMesh& tm, const Curve_network& network,
                                   const std::vector<Correspondence>& pairs,
                                   const NamedParameters& np = CGAL::parameters::default_values()) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  Deformation_report coarse = deform_coarse(tm, network, pairs, np);
  if (coarse.orientation_reversed || choose_parameter(get_parameter(np, internal_np::coarse_only), false))
    return coarse;
  Deformation_report fine = deform_fine(tm, network, pairs, np);
  fine.coarse_fit = coarse.coarse_fit;
  fine.coarse_seconds = coarse.coarse_seconds;
  fine.coarse_flipped_faces = coarse.coarse_flipped_faces;
  fine.orientation_reversed = coarse.orientation_reversed;
  return fine;
}

}  // namespace meshfit

#endif  // MESHFIT_DEFORM_H
