// meshfit internal: the helpers of deform.h's levels (the state of a deformation, the surface
// fine level's steps, the checks that refuse inputs before work). Included by deform_levels.h,
// which the library compiles once (src/deform.cpp), and by tests of these steps.
#ifndef MESHFIT_INTERNAL_DEFORM_IMPL_H
#define MESHFIT_INTERNAL_DEFORM_IMPL_H

#include <meshfit/deform.h>
#include <meshfit/correspondence.h>
#include <meshfit/curve_network.h>
#include <meshfit/displacement.h>
#include <meshfit/exceptions.h>
#include <meshfit/flip.h>
#include <meshfit/internal/border_cycles.h>
#include <meshfit/internal/clear_mesh.h>
#include <meshfit/internal/format_number.h>
#include <meshfit/internal/resample_network.h>
#include <meshfit/internal/stage_support.h>
#include <meshfit/internal/subdivide.h>
#include <meshfit/internal/triangle_corners.h>
#include <meshfit/internal/unit_scale.h>
#include <meshfit/memory_limit.h>
#include <meshfit/parameters.h>
#include <meshfit/untangle.h>
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Dynamic_property_map.h>
#include <CGAL/Named_function_parameters.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/named_params_helper.h>
#include <algorithm>
#include <chrono>
#include <deque>
#include <memory>
#include <limits>
#include <optional>
#include <queue>
#include <sstream>
#include <string>
#include <vector>

namespace meshfit {
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
  /// The vertices' neighbours, by index.
  Vertex_adjacency adjacency() const {
    Vertex_adjacency a;
    a.offsets.reserve(vertex.size() + 1);
    for (auto v : vertex) {
      for (auto h : CGAL::halfedges_around_target(halfedge(v, tm), tm)) a.neighbours.push_back(get(index, source(h, tm)));
      a.offsets.push_back(a.neighbours.size());
    }
    return a;
  }

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
  /// The faces beside an interior edge whose two faces turn more than 90 degrees apart at
  /// `positions` (exact: one face is not positively oriented in the other's plane), leaving out
  /// the edges `except` (folds already there).
  /// Interior edges (by index in edges(tm)) whose two faces' normals are 60 degrees apart or more
  /// at `positions`: the dihedral angle at the edge, between the half-planes through the faces'
  /// third corners, at most 120 degrees (CGAL::compare_dihedral_angle, exact on the points); and
  /// those beside a face of zero area, which has no normal.
  std::vector<bool> sharp_edges(const std::vector<Point_3>& positions) const {
    std::vector<bool> sharp(num_edges(tm), false);
    auto at = [&](vertex_descriptor v) -> const Point_3& { return positions[get(index, v)]; };
    std::size_t k = 0;
    for (auto e : edges(tm)) {
      const std::size_t ek = k++;
      const auto h = halfedge(e, tm), g = opposite(h, tm);
      if (is_border(h, tm) || is_border(g, tm)) continue;
      const Point_3 &a = at(source(h, tm)), &b = at(target(h, tm));
      const Point_3 &c = at(target(next(h, tm), tm)), &d = at(target(next(g, tm), tm));
      sharp[ek] = CGAL::collinear(a, b, c) || CGAL::collinear(a, b, d) ||
                  CGAL::compare_dihedral_angle(a, b, c, d, -0.5) != CGAL::LARGER;
    }
    return sharp;
  }

  std::vector<face_descriptor> folded_faces(const std::vector<Point_3>& positions,
                                            std::vector<bool>* folded_edges = nullptr,
                                            const std::vector<bool>* except = nullptr) const {
    std::vector<face_descriptor> out;
    if (folded_edges) folded_edges->assign(num_edges(tm), false);
    std::size_t k = 0;
    for (auto e : edges(tm)) {
      const std::size_t ek = k++;
      const auto h = halfedge(e, tm), g = opposite(h, tm);
      if (is_border(h, tm) || is_border(g, tm)) continue;
      if (except && ek < except->size() && (*except)[ek]) continue;
      if (!edge_folds(tm, h, [&](vertex_descriptor v) { return positions[get(index, v)]; })) continue;
      if (folded_edges) (*folded_edges)[ek] = true;
      out.push_back(face(h, tm));
      out.push_back(face(g, tm));
    }
    return out;
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
  /// inside the face, `margin` away from its edges). "Near" is a barycentric coordinate below
  /// `margin`; `centroid_when_reserved` puts the new vertex at the centroid instead. Returns its
  /// index.
  /// With `off_border`, a border edge is not split nor a border vertex used: the face is split
  /// with p's barycentric coordinates kept at least `margin` (a curve vertex inside the surface).
  std::size_t insert_near(face_descriptor f, const Point_3& p, const std::vector<bool>& reserved,
                          double margin = 0.15, bool centroid_when_reserved = true, bool off_border = false) {
    const auto c = corners(f);
    const Point_3 t[3] = {to_point(vertex[c[0]]), to_point(vertex[c[1]]), to_point(vertex[c[2]])};
    // Barycentric coordinates of p (a placement choice, not a geometric decision: whatever is
    // made here is checked afterwards). Splitting near an edge or a corner would make slivers:
    // near an edge the edge is split instead, near a corner the corner is used.
    const Vector_3 n = CGAL::cross_product(t[1] - t[0], t[2] - t[0]);
    const double area2 = n.squared_length();
    double l[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
    if (area2 > 0)
      for (int k = 0; k < 3; ++k)
        l[k] = CGAL::cross_product(t[(k + 1) % 3] - p, t[(k + 2) % 3] - p) * n / area2;
    int small = 0, which = 0;
    for (int k = 0; k < 3; ++k)
      if (l[k] < margin) { ++small; which = k; }
    if (small == 0) return split_face_at(f, p);
    auto clamped_in_face = [&] {
      double sum = 0;
      for (double& x : l) sum += (x = std::max(x, margin));
      return split_face_at(f, Point_3((l[0] * t[0].x() + l[1] * t[1].x() + l[2] * t[2].x()) / sum,
                                      (l[0] * t[0].y() + l[1] * t[1].y() + l[2] * t[2].y()) / sum,
                                      (l[0] * t[0].z() + l[1] * t[1].z() + l[2] * t[2].z()) / sum));
    };
    if (small == 1) {
      // The edge opposite corner `which`: split it at p's position along it, kept off its ends.
      const std::size_t a = c[(which + 1) % 3];
      const Point_3 &pa = t[(which + 1) % 3], &pb = t[(which + 2) % 3];
      auto h = halfedge(f, tm);
      while (get(index, source(h, tm)) != a) h = next(h, tm);
      if (off_border && is_border(opposite(h, tm), tm)) return clamped_in_face();
      const double len2 = CGAL::squared_distance(pa, pb);
      double u = len2 > 0 ? ((p - pa) * (pb - pa)) / len2 : 0.5;
      u = std::min(1 - margin, std::max(margin, u));
      return split_edge_at(h, pa + u * (pb - pa));
    }
    // Near a corner: that corner is already (almost) at p; use it unless it is taken.
    int corner = 0;
    for (int k = 1; k < 3; ++k)
      if (l[k] > l[corner]) corner = k;
    const bool usable = !(off_border && is_border(vertex[c[corner]], tm));
    if (usable && (c[corner] >= reserved.size() || !reserved[c[corner]])) return c[corner];
    if (centroid_when_reserved && usable) return split_face(f);
    return clamped_in_face();
  }
  Point_3 to_point(vertex_descriptor v) const { return point_of<TriangleMesh>(vpm, v); }
  Vector_3 normal(std::size_t i) const {
    const auto n = CGAL::Polygon_mesh_processing::compute_vertex_normal(vertex[i], tm,
                                                                        CGAL::parameters::vertex_point_map(vpm));
    return Vector_3(n.x(), n.y(), n.z());
  }
};

/// The diagonal of the bounding box of the mesh's points that lie on a face (a vertex on no face,
/// unused, sets no scale: see checked_template_box).
template <typename TriangleMesh, typename VPM>
double bbox_diagonal(const TriangleMesh& tm, const VPM& vpm) {
  Bbox_3 box;
  for (auto v : vertices(tm))
    if (halfedge(v, tm) != boost::graph_traits<TriangleMesh>::null_halfedge()) box += get(vpm, v).bbox();
  return meshfit::bbox_diagonal(box);
}

/// The mean length of the mesh's edges (0 when it has none): the scale of the template against
/// which the fine level cuts long segments and refuses oversampled curves.
template <typename TriangleMesh, typename VPM>
double mean_edge_length(const TriangleMesh& tm, const VPM& vpm) {
  double length = 0;
  for (auto e : edges(tm))
    length += std::sqrt(CGAL::squared_distance(point_of<TriangleMesh>(vpm, source(e, tm)),
                                               point_of<TriangleMesh>(vpm, target(e, tm))));
  return num_edges(tm) > 0 ? length / static_cast<double>(num_edges(tm)) : 0;
}

/// \throws Algorithm_failure naming the polylines all of whose points are far from the surface
///         (`distance(v)`, the distance of network vertex v from it, more than a tenth of
///         `size`, the template's bounding-box diagonal): no fine level can bring them onto it,
///         and the thesis level would subdivide without end trying; or naming the first point
///         farther than `size` itself, a piece of a polyline that leaves the surface (the rest of
///         its polyline may lie on it): the fine level would pull the surface out to it and
///         untangle what that folds, for minutes.
template <typename Distance>
void refuse_far_polylines(const Curve_network& network, const Distance& distance, double size) {
  std::vector<std::size_t> lines;
  for (std::size_t k = 0; k < network.polylines().size(); ++k) {
    const auto& pl = network.polylines()[k];
    if (std::all_of(pl.begin(), pl.end(), [&](std::size_t v) { return distance(v) > 0.1 * size; })) lines.push_back(k);
  }
  if (!lines.empty()) {
    const char* them = lines.size() == 1 ? "it" : "them";
    throw Algorithm_failure("deform", name_polylines(lines) + " (in file order) lie" + (lines.size() == 1 ? "s" : "") +
                                          " far from the template after the coarse level (every point farther than "
                                          "a tenth of its size): give a correspondence on " + them + ", or remove " +
                                          them,
                            {{"far_polylines", static_cast<double>(lines.size())},
                             {"first_far_polyline", static_cast<double>(lines.front() + 1)}});
  }
  for (std::size_t k = 0; k < network.polylines().size(); ++k) {
    const auto& pl = network.polylines()[k];
    for (std::size_t i = 0; i < pl.size(); ++i) {
      const double d = distance(pl[i]);
      if (!(d > size)) continue;
      throw Algorithm_failure("deform", name_polylines({k}) + " (in file order), point " + std::to_string(i + 1) +
                                            ", lies " + format_number(d / size) +
                                            " times the template's size away from it after the coarse level: "
                                            "curves must run on the surface; check that point, or remove it",
                              {{"polyline", static_cast<double>(k + 1)},
                               {"point", static_cast<double>(i + 1)},
                               {"distance_over_template_size", d / size}});
    }
  }
}

/// The AABB tree of a mesh's faces, for closest points on its surface.
template <typename TriangleMesh, typename VPM>
using Face_tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_face_graph_triangle_primitive<TriangleMesh, VPM>>>;

/// The face tree of `tm` at its points now, ready for distance queries (1.3 million faces: 0.7 s).
template <typename TriangleMesh, typename VPM>
void build_face_tree(const TriangleMesh& tm, const VPM& vpm, Face_tree<TriangleMesh, VPM>& tree) {
  tree.rebuild(faces(tm).first, faces(tm).second, tm, vpm);
  tree.accelerate_distance_queries();
}

/// refuse_far_polylines with the distances to the faces of `tm` (`tree`, built at its points now)
/// and its bounding-box diagonal.
template <typename TriangleMesh, typename VPM>
void check_polylines_near(const TriangleMesh& tm, const VPM& vpm, const Face_tree<TriangleMesh, VPM>& tree,
                          const Curve_network& network) {
  refuse_far_polylines(
      network, [&](std::size_t v) { return std::sqrt(tree.squared_distance(network.point(v))); }, bbox_diagonal(tm, vpm));
}

/// check_polylines_near with a face tree of its own.
template <typename TriangleMesh, typename VPM>
void check_polylines_near(const TriangleMesh& tm, const VPM& vpm, const Curve_network& network) {
  Face_tree<TriangleMesh, VPM> tree;
  build_face_tree(tm, vpm, tree);
  check_polylines_near(tm, vpm, tree, network);
}

/// tracked_projections' state: each network vertex's surface point and face once known, and the
/// queue of vertices whose neighbours are still to be found.
template <typename TriangleMesh, typename VPM, typename Tree>
class Projection_tracker {
  using GT = boost::graph_traits<TriangleMesh>;
  using face_descriptor = typename GT::face_descriptor;

 public:
  Projection_tracker(const TriangleMesh& tm, const VPM& vpm, const Tree& tree, const Curve_network& network)
      : tm(tm), vpm(vpm), tree(tree), network(network), q(network.number_of_vertices()),
        face_of(network.number_of_vertices(), GT::null_face()), known(network.number_of_vertices(), false),
        seen(get(CGAL::dynamic_face_property_t<std::size_t>(), tm)),
        face_budget(std::max<std::size_t>(num_faces(tm) / 4, 2000)) {
    for (auto f : faces(tm)) put(seen, f, SIZE_MAX);
  }

  std::vector<Point_3> run(const std::vector<Correspondence>& pairs, std::size_t& global_jumps) {
    seed(pairs);
    global_jumps = 0;
    while (!queue.empty()) {
      const std::size_t v = queue.front();
      queue.pop_front();
      for (std::size_t k : network.incident_segments(v)) {
        const auto& sg = network.segments()[k];
        const std::size_t w = sg[0] == v ? sg[1] : sg[0];
        if (known[w]) continue;
        if (!place_near(v, w)) ++global_jumps;
        queue.push_back(w);
      }
    }
    return q;
  }

 private:
  Kernel::Triangle_3 triangle(face_descriptor f) const {
    const auto h = halfedge(f, tm);
    return Kernel::Triangle_3(point_of<TriangleMesh>(vpm, source(h, tm)), point_of<TriangleMesh>(vpm, target(h, tm)),
                              point_of<TriangleMesh>(vpm, target(next(h, tm), tm)));
  }

  // The starts: the user's pairs (their template vertices), then, in each component of the
  // network with no pair, its vertex nearest to the surface.
  void seed(const std::vector<Correspondence>& pairs) {
    for (const Correspondence& c : pairs) {
      if (known[c.network_vertex]) continue;
      auto v = *std::next(vertices(tm).first, static_cast<std::ptrdiff_t>(c.template_vertex));
      for (auto h : CGAL::halfedges_around_target(halfedge(v, tm), tm))
        if (!is_border(h, tm)) face_of[c.network_vertex] = face(h, tm);
      q[c.network_vertex] = point_of<TriangleMesh>(vpm, v);
      known[c.network_vertex] = true;
      queue.push_back(c.network_vertex);
    }
    std::vector<bool> component_seeded(network.number_of_components(), false);
    for (std::size_t v : queue) component_seeded[network.component(v)] = true;
    std::vector<std::size_t> seed_of(network.number_of_components(), SIZE_MAX);
    std::vector<double> seed_distance(network.number_of_components(), std::numeric_limits<double>::infinity());
    for (std::size_t v = 0; v < network.number_of_vertices(); ++v) {
      const std::size_t c = network.component(v);
      if (component_seeded[c]) continue;
      const double d = CGAL::squared_distance(tree.closest_point(network.point(v)), network.point(v));
      if (d < seed_distance[c]) seed_distance[c] = d, seed_of[c] = v;
    }
    for (std::size_t c = 0; c < seed_of.size(); ++c) {
      if (seed_of[c] == SIZE_MAX) continue;
      const auto hit = tree.closest_point_and_primitive(network.point(seed_of[c]));
      q[seed_of[c]] = Point_3(hit.first.x(), hit.first.y(), hit.first.z());
      face_of[seed_of[c]] = hit.second;
      known[seed_of[c]] = true;
      queue.push_back(seed_of[c]);
    }
  }

  // Places w, a neighbour of the placed v, at the nearest point of the faces within reach of v's
  // point. The faces within reach are searched nearest to w first, and the search ends at the
  // nearest face of the whole surface when it is within reach (the usual case): that face is
  // then the answer, found after a path's worth of faces rather than the whole disc. False when
  // the search did not come to that face.
  bool place_near(std::size_t v, std::size_t w) {
    const Point_3& p = network.point(w);
    const double reach = 2 * std::sqrt(CGAL::squared_distance(network.point(v), p)) +
                         std::sqrt(CGAL::squared_distance(network.point(v), q[v]));
    ++search;
    const auto nearest = tree.closest_point_and_primitive(p);
    const double nearest_d = CGAL::squared_distance(nearest.first, p);
    double best = std::numeric_limits<double>::infinity();
    face_descriptor best_face = GT::null_face();
    bool reached_nearest = false;
    using Entry = std::pair<double, face_descriptor>;
    auto later = [](const Entry& a, const Entry& b) { return a.first > b.first; };
    std::priority_queue<Entry, std::vector<Entry>, decltype(later)> heap(later);
    heap.emplace(CGAL::squared_distance(triangle(face_of[v]), p), face_of[v]);
    put(seen, face_of[v], search);
    std::size_t visited = 0;
    while (!heap.empty() && visited < face_budget) {
      const auto [d, f] = heap.top();
      heap.pop();
      ++visited;
      if (d < best) best = d, best_face = f;
      if (f == nearest.second || d <= nearest_d) {
        reached_nearest = true;
        break;
      }
      for (auto h : CGAL::halfedges_around_face(halfedge(f, tm), tm)) {
        const auto g = opposite(h, tm);
        if (is_border(g, tm) || get(seen, face(g, tm)) == search) continue;
        put(seen, face(g, tm), search);
        const auto tg = triangle(face(g, tm));
        if (CGAL::squared_distance(tg, q[v]) <= reach * reach) heap.emplace(CGAL::squared_distance(tg, p), face(g, tm));
      }
    }
    q[w] = Kernel().construct_projected_point_3_object()(triangle(best_face), p);
    face_of[w] = best_face;
    known[w] = true;
    return reached_nearest;
  }

  const TriangleMesh& tm;
  const VPM& vpm;
  const Tree& tree;
  const Curve_network& network;
  std::vector<Point_3> q;  // by network vertex: its surface point, once known
  std::vector<face_descriptor> face_of;
  std::vector<bool> known;
  std::deque<std::size_t> queue;
  decltype(get(CGAL::dynamic_face_property_t<std::size_t>(), std::declval<const TriangleMesh&>())) seen;
  std::size_t search = 0;  // the search that marked a face in `seen`
  const std::size_t face_budget;
};

/// The surface point of each network vertex, tracked along the curves: from the user's pairs
/// (their template vertices), each neighbour along a segment takes the nearest point of the
/// faces within reach of its predecessor's point (a face walk out to twice the segment's length
/// plus the predecessor's distance to the surface), not the nearest point of the whole surface,
/// which on thin parts (a trunk beside a body, two sides of an ear) can lie on another part. A
/// component of the network with no pair starts from its vertex nearest to the surface. Returns
/// the points; `global_jumps` counts the vertices whose search within reach did not come to the
/// nearest face of the whole surface.
template <typename TriangleMesh, typename VPM, typename Tree>
std::vector<Point_3> tracked_projections(const TriangleMesh& tm, const VPM& vpm, const Tree& tree,
                                         const Curve_network& network, const std::vector<Correspondence>& pairs,
                                         std::size_t& global_jumps) {
  return Projection_tracker<TriangleMesh, VPM, Tree>(tm, vpm, tree, network).run(pairs, global_jumps);
}

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

/// The nearest point to q on segments a_k b_k, k < count (`ends(k)` gives the pair of points):
/// the segment `k`, the point's parameter `u` from a_k, its squared distance `d2` and the
/// segment's `length`. Used on a mesh's border edges.
struct Nearest_on_segments {
  std::size_t k = 0;
  double u = 0, d2 = std::numeric_limits<double>::infinity(), length = 0;
};
template <typename Ends>
Nearest_on_segments nearest_on_segments(std::size_t count, const Ends& ends, const Point_3& q) {
  Nearest_on_segments best;
  for (std::size_t k = 0; k < count; ++k) {
    const auto [a, b] = ends(k);
    const Vector_3 ab = b - a;
    const double len2 = ab.squared_length();
    const double u = len2 > 0 ? std::min(1.0, std::max(0.0, ((q - a) * ab) / len2)) : 0.0;
    const double d2 = CGAL::squared_distance(q, a + u * ab);
    if (d2 < best.d2) best = {k, u, d2, std::sqrt(len2)};
  }
  return best;
}

/// The network vertices of the curves that run along a mesh's border, given for each network
/// vertex whether it is near the border (`near`) and its nearest border point (`shadow`): a curve
/// (network.curves()) runs along the border when its shadow there (the path of the shadows of its
/// consecutive near vertices) is at least half as long as the curve; its near vertices and its ends
/// are along the border. A curve that only ends there, or leaves the surface across the border (its
/// points beyond are near the border too, but their shadows bunch up), is not.
inline std::vector<bool> vertices_along_border(const Curve_network& network, const std::vector<bool>& near,
                                               const std::vector<Point_3>& shadow) {
  std::vector<bool> along(network.number_of_vertices(), false);
  for (const auto& curve : network.curves()) {
    const auto& cv = curve.vertices;
    double length = 0, shadow_length = 0;
    for (std::size_t i = 0; i + 1 < cv.size(); ++i) {
      length += std::sqrt(CGAL::squared_distance(network.point(cv[i]), network.point(cv[i + 1])));
      if (near[cv[i]] && near[cv[i + 1]]) shadow_length += std::sqrt(CGAL::squared_distance(shadow[cv[i]], shadow[cv[i + 1]]));
    }
    if (length > 0 && 2 * shadow_length >= length)
      for (std::size_t v : cv) along[v] = along[v] || near[v] || v == cv.front() || v == cv.back();
  }
  return along;
}

/// What approach_curves did.
struct Approach_result {
  std::size_t constraints = 0;  ///< template vertices given a displacement
  double scale = 0;             ///< the part of the displacement applied (0: none)
  std::size_t coarse_nodes = 0;  ///< the coarse space's nodes the steps were solved on (0: every vertex)
};

/// Brings the coarse-deformed surface towards the curves before they are embedded, along the
/// surface rather than through space: every network vertex's surface point (tracked along the
/// curves) should move onto the vertex; that motion is given to the template vertex nearest the
/// surface point, for vertices at least three edges apart (the user's pairs first, then in
/// network order), and the thin-plate displacement field through them (interpolate_displacements)
/// moves the rest. The tangential part of each motion is what the embedding then does not have
/// to make. Halved (up to three times) while the motion would turn a face over or fold an edge;
/// not applied when it still would.
template <typename TriangleMesh, typename VPM>
Approach_result approach_curves(TriangleMesh& tm, const VPM& vpm, const Curve_network& network,
                                const std::vector<Correspondence>& pairs) {
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<TriangleMesh, VPM>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  Deform_state<TriangleMesh, VPM> s(tm, vpm);
  const std::size_t n = s.vertex.size();
  const std::vector<Point_3> before = s.positions();
  const Vertex_adjacency adjacency = s.adjacency();
  std::vector<bool> constrained(n, false), blocked(n, false);
  std::vector<Vector_3> given(n, Vector_3(0, 0, 0));
  Approach_result result;
  auto take = [&](std::size_t i, const Vector_3& d) {
    if (blocked[i]) return;
    constrained[i] = true;
    given[i] = d;
    ++result.constraints;
    std::vector<std::size_t> ring{i};
    blocked[i] = true;
    for (int grow = 0; grow < 2; ++grow) {
      std::vector<std::size_t> next;
      for (std::size_t u : ring)
        for (std::size_t k = adjacency.offsets[u]; k < adjacency.offsets[u + 1]; ++k)
          if (!blocked[adjacency.neighbours[k]]) blocked[adjacency.neighbours[k]] = true, next.push_back(adjacency.neighbours[k]);
      ring.swap(next);
    }
  };
  for (const Correspondence& c : pairs) take(c.template_vertex, network.point(c.network_vertex) - before[c.template_vertex]);
  {
    Tree tree(faces(tm).first, faces(tm).second, tm, vpm);
    tree.accelerate_distance_queries();
    std::size_t off = 0;
    const std::vector<Point_3> surface_point = tracked_projections(tm, vpm, tree, network, pairs, off);
    for (std::size_t v = 0; v < network.number_of_vertices(); ++v) {
      const auto f = tree.closest_point_and_primitive(surface_point[v]).second;
      std::size_t best = 0;
      double best_d2 = std::numeric_limits<double>::infinity();
      for (std::size_t c : s.corners(f)) {
        const double d2 = CGAL::squared_distance(before[c], surface_point[v]);
        if (d2 < best_d2) best_d2 = d2, best = c;
      }
      take(best, network.point(v) - surface_point[v]);
    }
  }
  const std::vector<Vector_3> d = interpolate_displacements(adjacency, constrained, given, 2);
  std::vector<bool> folded_before;
  s.folded_faces(before, &folded_before);
  std::vector<Point_3> after(n);
  for (double scale = 1; scale > 0.1; scale /= 2) {
    for (std::size_t i = 0; i < n; ++i) after[i] = before[i] + scale * d[i];
    std::size_t degenerate = 0;
    if (!s.flipped_faces(before, after, degenerate).empty() || !s.folded_faces(after, nullptr, &folded_before).empty())
      continue;
    s.set_positions(after);
    result.scale = scale;
    break;
  }
  return result;
}

/// The state of approach_curves_icp: the mesh's faces by index and the edges its fold test leaves
/// out, and the three parts of a step (constraints, bad faces, untangling).
template <typename TriangleMesh, typename VPM>
class Icp_approach {
 public:
  Icp_approach(TriangleMesh& tm, const VPM& vpm)
      : tm(tm), vpm(vpm), s(tm, vpm), n(s.vertex.size()), adjacency(s.adjacency()),
        face_index(get(CGAL::dynamic_face_property_t<std::size_t>(), tm)) {
    for (auto f : faces(tm)) {
      put(face_index, f, corners.size());
      corners.push_back(s.corners(f));
    }
    for (const auto& cycle : border_cycles(tm)) {
      for (auto g : cycle) {
        border_edges.push_back({get(s.index, source(g, tm)), get(s.index, target(g, tm))});
        border_loop.push_back(loops);
      }
      ++loops;
    }
    // Edges exempt from the fold test: folded or sharp on the coarse surface.
    const std::vector<Point_3> p = s.positions();
    s.folded_faces(p, &exempt);
    const std::vector<bool> sharp = s.sharp_edges(p);
    for (std::size_t k = 0; k < exempt.size(); ++k) exempt[k] = exempt[k] || sharp[k];
  }

  // `tree`: the face tree at the mesh's points now, or nullptr. `tree_after`, when given, receives
  // the face tree the last step built when no motion followed it (it is then at the points after
  // the approach); it is left empty otherwise.
  Approach_result run(const Curve_network& network, const std::vector<Correspondence>& pairs,
                      const Face_tree<TriangleMesh, VPM>* tree,
                      std::optional<Face_tree<TriangleMesh, VPM>>* tree_after = nullptr) {
    const double h = mean_edge_length(tm, vpm);
    Approach_result result;
    double stiffness = 10;
    for (int step = 0; step < 6; ++step, stiffness /= 4) {
      const std::vector<Point_3> before = s.positions();
      std::vector<Point_3> surface_point;
      std::vector<Soft_displacement> constraints =
          surface_constraints(network, pairs, before, step == 0 ? tree : nullptr, surface_point);
      if (step == 0) {
        along_border = along_border_at(network, before, surface_point);
        free_slope_across_border_in_network(network, before);
      }
      attach_to_border(network, before, constraints);
      result.constraints = constraints.size();
      // Done when every network vertex is within a quarter of an edge of its surface point: what is
      // left is finer than the mesh (the 81 920-face scale case is there after one step; five more
      // cost 12 s and moved nothing that mattered).
      double largest_gap = 0;
      for (const Soft_displacement& c : constraints) largest_gap = std::max(largest_gap, c.target.squared_length());
      if (largest_gap < 0.0625 * h * h) {
        if (tree_after && own_tree) *tree_after = std::move(own_tree);
        break;
      }
      // A large mesh's steps are sought in a coarse space (built at the first step's positions).
      if (n >= coarse_from_vertices && coarse.nodes == 0) {
        std::vector<Vector_3> face_normal, vertex_normal;
        normals(before, face_normal, vertex_normal);
        coarse = coarse_space(adjacency, before, vertex_normal, coarse_rings);
      }
      const double scale =
          take_step(before, fit_displacements(adjacency, constraints, stiffness, coarse.nodes > 0 ? &coarse : nullptr));
      if (scale == 0) break;
      result.scale = scale;
      result.coarse_nodes = coarse.nodes;
    }
    return result;
  }

 private:
  using Fold = std::array<std::size_t, 2>;  // the two faces beside a folded edge

  // From this many vertices on, the steps are sought in a coarse space of aggregates of
  // `coarse_rings` rings (coarse_space: about 1/16 of the vertices). On the bench/scale cases
  // (one step each) the approach took 1.0 / 5.7 / 22.4 s on every vertex and takes 0.3 / 1.5 /
  // 7.1 s so (81 920 / 327 680 / 1 310 720 faces); the fit ends 0.505 / 0.507 / 0.525 % from the
  // truth instead of 0.461 / 0.460 / 0.476 %, every case verified. Below, the whole mesh's solve
  // costs little.
  static constexpr std::size_t coarse_from_vertices = 20000;
  static constexpr std::size_t coarse_rings = 2;

  // Every network vertex's surface point (tracked along the curves: tracked_projections), asked
  // to move onto the vertex: a constraint on the point of its face, by barycentric weights.
  // `tree`: the face tree at `before`, or nullptr (one is built, in own_tree).
  std::vector<Soft_displacement> surface_constraints(const Curve_network& network, const std::vector<Correspondence>& pairs,
                                                     const std::vector<Point_3>& before,
                                                     const Face_tree<TriangleMesh, VPM>* given,
                                                     std::vector<Point_3>& surface_point) {
    std::vector<Soft_displacement> constraints;
    own_tree.reset();
    if (!given) build_face_tree(tm, vpm, own_tree.emplace());
    const Face_tree<TriangleMesh, VPM>& tree = given ? *given : *own_tree;
    std::size_t off_nearest = 0;
    surface_point = tracked_projections(tm, vpm, tree, network, pairs, off_nearest);
    for (std::size_t v = 0; v < network.number_of_vertices(); ++v) {
      const auto& c = corners[get(face_index, tree.closest_point_and_primitive(surface_point[v]).second)];
      // The surface point's barycentric coordinates in its face (a weight, not a decision).
      const Vector_3 e0 = before[c[1]] - before[c[0]], e1 = before[c[2]] - before[c[0]],
                     e2 = surface_point[v] - before[c[0]];
      const double d00 = e0 * e0, d01 = e0 * e1, d11 = e1 * e1, d20 = e2 * e0, d21 = e2 * e1;
      const double den = d00 * d11 - d01 * d01;
      double b1 = den > 0 ? (d11 * d20 - d01 * d21) / den : 0, b2 = den > 0 ? (d00 * d21 - d01 * d20) / den : 0;
      b1 = std::clamp(b1, 0.0, 1.0);
      b2 = std::clamp(b2, 0.0, 1.0 - b1);
      constraints.push_back({c, {1 - b1 - b2, b1, b2}, network.point(v) - surface_point[v], 1});
    }
    return constraints;
  }

  // The nearest point to q on the border at positions p (border_edges[k] at parameter u).
  Nearest_on_segments nearest_border_point(const std::vector<Point_3>& p, const Point_3& q) const {
    return nearest_on_segments(
        border_edges.size(), [&](std::size_t k) { return std::pair(p[border_edges[k][0]], p[border_edges[k][1]]); }, q);
  }

  // The network vertices of curves that run along the border, as step 1 of the fine level judges
  // them (Surface_fine_level::place_border_vertices): a vertex is near the border when it is
  // nearer to it than half a border edge more than to its surface point (vertices_along_border).
  std::vector<bool> along_border_at(const Curve_network& network, const std::vector<Point_3>& p,
                                    const std::vector<Point_3>& surface_point) const {
    const std::size_t nv = network.number_of_vertices();
    if (border_edges.empty()) return std::vector<bool>(nv, false);
    std::vector<bool> near(nv, false);
    std::vector<Point_3> shadow(nv);
    for (std::size_t v = 0; v < nv; ++v) {
      const Nearest_on_segments b = nearest_border_point(p, network.point(v));
      near[v] = std::sqrt(b.d2) <= std::sqrt(CGAL::squared_distance(network.point(v), surface_point[v])) + 0.5 * b.length;
      const Point_3 &a = p[border_edges[b.k][0]], &c = p[border_edges[b.k][1]];
      shadow[v] = a + b.u * (c - a);
    }
    return vertices_along_border(network, near, shadow);
  }

  // The vertices along the border (along_border) ask that their nearest border point, rather than
  // their surface point, move onto them: nothing else keeps the border from running past a curve
  // that bounds the surface (open-plane-wave-boundary: the corners flared out beyond the network's
  // and became two regions more).
  void attach_to_border(const Curve_network& network, const std::vector<Point_3>& p,
                        std::vector<Soft_displacement>& constraints) const {
    for (std::size_t v = 0; v < along_border.size(); ++v) {
      if (!along_border[v]) continue;
      const Nearest_on_segments b = nearest_border_point(p, network.point(v));
      const auto& e = border_edges[b.k];
      const Point_3 on = p[e[0]] + b.u * (p[e[1]] - p[e[0]]);
      constraints[v] = {{e[0], e[1], e[0]}, {1 - b.u, b.u, 0}, network.point(v) - on, 1};
    }
  }

  // The border loops that curves of the network run along (along_border) are given the thin-plate
  // energy's rows along the border (Vertex_adjacency::border_edge): the network gives the surface's
  // shape across them, which a row across the border would hold flat (open-plane-saddle-boundary
  // ended 1.04 % of the diagonal from the truth so, 0.48 % now). Other loops keep their whole
  // one-sided rows, which hold a free border's slope: along them alone, the rims of CGAL's pig's
  // holes let 25 faces turn over (real-pig).
  void free_slope_across_border_in_network(const Curve_network& network, const std::vector<Point_3>& p) {
    std::vector<bool> in_network(loops, false);
    bool any = false;
    for (std::size_t v = 0; v < along_border.size(); ++v)
      if (along_border[v]) any = in_network[border_loop[nearest_border_point(p, network.point(v)).k]] = true;
    if (!any) return;
    adjacency.border_edge.assign(adjacency.neighbours.size(), false);
    auto flag = [&](std::size_t a, std::size_t b) {
      for (std::size_t m = adjacency.offsets[a]; m < adjacency.offsets[a + 1]; ++m)
        if (adjacency.neighbours[m] == b) adjacency.border_edge[m] = true;
    };
    for (std::size_t k = 0; k < border_edges.size(); ++k)
      if (in_network[border_loop[k]]) flag(border_edges[k][0], border_edges[k][1]), flag(border_edges[k][1], border_edges[k][0]);
  }

  // The faces turned over against their normals before the step, then those beside a folded edge;
  // `folds` gets the folded edges.
  std::vector<std::size_t> bad_faces(const std::vector<Point_3>& p, const std::vector<Vector_3>& face_normal,
                                     std::vector<Fold>& folds) const {
    std::vector<std::size_t> bad;
    for (std::size_t k = 0; k < corners.size(); ++k) {
      const auto& c = corners[k];
      if (CGAL::orientation(p[c[0]], p[c[1]], p[c[2]], p[c[0]] + face_normal[k]) != CGAL::POSITIVE) bad.push_back(k);
    }
    const auto folded = s.folded_faces(p, nullptr, &exempt);
    folds.clear();
    for (std::size_t j = 0; j + 1 < folded.size(); j += 2)
      folds.push_back({get(face_index, folded[j]), get(face_index, folded[j + 1])});
    for (auto f : folded) bad.push_back(get(face_index, f));
    return bad;
  }

  // The faces' normals at p (not normalised) and each vertex's sum of its faces' normals.
  void normals(const std::vector<Point_3>& p, std::vector<Vector_3>& face_normal, std::vector<Vector_3>& vertex_normal) const {
    face_normal.clear();
    vertex_normal.assign(n, Vector_3(0, 0, 0));
    for (const auto& c : corners) {
      face_normal.push_back(CGAL::cross_product(p[c[1]] - p[c[0]], p[c[2]] - p[c[0]]));
      for (std::size_t k : c) vertex_normal[k] = vertex_normal[k] + face_normal.back();
    }
  }

  // The motion `d` from `before`, halved while it leaves bad faces that untangle cannot mend, and
  // applied; the scale it was applied at, or 0 when it could not be.
  double take_step(const std::vector<Point_3>& before, const std::vector<Vector_3>& d) {
    // Faces judged against their normals before the step; vertices move in their tangent planes.
    std::vector<Vector_3> face_normal, vertex_normal;
    normals(before, face_normal, vertex_normal);
    // A face of no area has no normal to judge it by (untangle_faces refuses it): the approach
    // ends. (The example translated by 1e15, whose x coordinates are multiples of 1/8, has such.)
    if (std::any_of(face_normal.begin(), face_normal.end(), [](const Vector_3& v) { return v == CGAL::NULL_VECTOR; }))
      return 0;
    for (double scale = 1; scale > 0.2; scale /= 2) {
      std::vector<Point_3> after(n);
      for (std::size_t i = 0; i < n; ++i) after[i] = before[i] + scale * d[i];
      std::vector<Fold> folds;
      std::vector<std::size_t> bad = bad_faces(after, face_normal, folds);
      for (std::size_t rings : {2, 6}) {
        if (bad.empty()) break;
        untangle(after, bad, folds, rings, face_normal, vertex_normal);
      }
      if (!bad.empty()) continue;
      s.set_positions(after);
      return scale;
    }
    return 0;
  }

  // Untangles the free vertices up to `rings` edges from the bad faces (the border stays); keeps
  // the result when it leaves fewer bad faces.
  void untangle(std::vector<Point_3>& after, std::vector<std::size_t>& bad, std::vector<Fold>& folds, std::size_t rings,
                const std::vector<Vector_3>& face_normal, const std::vector<Vector_3>& vertex_normal) const {
    std::vector<bool> free(n, false);
    std::vector<std::size_t> ring;
    for (std::size_t k : bad)
      for (std::size_t c : corners[k])
        if (!free[c]) free[c] = true, ring.push_back(c);
    for (std::size_t grow = 0; grow < rings; ++grow) {
      std::vector<std::size_t> next;
      for (std::size_t i : ring)
        for (std::size_t k = adjacency.offsets[i]; k < adjacency.offsets[i + 1]; ++k)
          if (!free[adjacency.neighbours[k]]) free[adjacency.neighbours[k]] = true, next.push_back(adjacency.neighbours[k]);
      ring.swap(next);
    }
    for (std::size_t i = 0; i < n; ++i)
      if (free[i] && is_border(s.vertex[i], tm)) free[i] = false;
    // A face beside a folded edge is judged against the other face's normal as well: the fold
    // turns it over against that normal, which the untangling then sees (real-dino: a fold
    // between two faces of 1/20 000 of the mean area stopped the first step; with this, two
    // steps are made instead of none, and every segment is embedded).
    std::vector<std::array<std::size_t, 3>> judged = corners;
    std::vector<Vector_3> judged_normal = face_normal;
    for (const auto& [f, g] : folds) {
      judged.push_back(corners[f]), judged_normal.push_back(face_normal[g]);
      judged.push_back(corners[g]), judged_normal.push_back(face_normal[f]);
    }
    std::vector<Point_3> trial = untangle_faces(after, judged, judged_normal, free, vertex_normal, 1.0);
    std::vector<Fold> trial_folds;
    std::vector<std::size_t> now = bad_faces(trial, face_normal, trial_folds);
    if (now.size() < bad.size()) after.swap(trial), bad.swap(now), folds.swap(trial_folds);
  }

  TriangleMesh& tm;
  VPM vpm;
  Deform_state<TriangleMesh, VPM> s;
  std::size_t n;
  Vertex_adjacency adjacency;
  std::vector<std::array<std::size_t, 3>> corners;  // by face index
  typename boost::property_map<TriangleMesh, CGAL::dynamic_face_property_t<std::size_t>>::type face_index;
  std::vector<bool> exempt;  // by edge
  Coarse_space coarse;       // empty below coarse_from_vertices, and until the first step
  std::vector<std::array<std::size_t, 2>> border_edges;  // by vertex index, loop after loop
  std::vector<std::size_t> border_loop;                  // each border edge's loop
  std::size_t loops = 0;
  std::vector<bool> along_border;  // by network vertex, judged at the first step (vertices_along_border)
  std::optional<Face_tree<TriangleMesh, VPM>> own_tree;  // built by the last surface_constraints without a tree
};

/// Non-rigid ICP: brings the coarse surface towards the curves in up to six steps of falling
/// stiffness (10, then a quarter of the last), before the curves are embedded in it. Each step
/// takes every network vertex's surface point (tracked along the curves: tracked_projections; for
/// the vertices of curves that run along the border, judged at the first step as step 1 of the
/// fine level judges them, the nearest border point) and asks, in the least-squares sense, that the point of its face move onto the vertex, against
/// `stiffness` times the thin-plate energy of the motion (fit_displacements). Where the step
/// turns a face over against its own normal before the step (an exact orientation with the
/// normal's end as fourth point) or folds an edge that was neither folded nor sharp (faces more
/// than 60 degrees apart: a smooth motion may tip such an edge over), the free vertices around
/// those faces (2, then 6 rings; the border stays) are untangled (untangle_faces). A step that
/// still leaves such a face is halved, twice; the first step that cannot be made ends the
/// approach, as does every network vertex lying within a quarter of the mean edge of its surface
/// point (before any step: no approach). On a mesh of 20 000 vertices or more the steps are sought
/// in a coarse space (coarse_space, fit_displacements). The stiffness and the data are free of
/// units (uniform Laplacian, barycentric weights; the coarse space's weights are ratios of
/// distances): the motion does not depend on where the inputs are placed. `tree`, when given, is
/// the face tree of `tm` at its points at the call (build_face_tree), used for the first step.
/// `tree_after`, when given, receives the face tree at the points after the approach when the
/// approach built one there (its last step measured the gap and moved nothing); else it is left
/// empty.
template <typename TriangleMesh, typename VPM>
Approach_result approach_curves_icp(TriangleMesh& tm, const VPM& vpm, const Curve_network& network,
                                    const std::vector<Correspondence>& pairs,
                                    const Face_tree<TriangleMesh, VPM>* tree = nullptr,
                                    std::optional<Face_tree<TriangleMesh, VPM>>* tree_after = nullptr) {
  return Icp_approach<TriangleMesh, VPM>(tm, vpm).run(network, pairs, tree, tree_after);
}

/// deform_fine_on_surface on the network as it is (its long segments not cut); compiled once in
/// src/surface_fine_level.cpp. With `split_for_paths`, a segment whose ends the other chains wall
/// off is given a path through the edges that join two chain vertices, split for it (a fallback:
/// deform_fine_on_surface_impl asks for it only when every start left such a segment). `tree`:
/// the face tree of `tm` at its points now, when the caller has one (step 1 builds one otherwise).
/// `template_bending`: normal_bending of the template, by vertex index (the mesh's first
/// vertices; those it inserts come after), in the mesh's frame: the shape that step 3 gives the
/// surface between the curves. Without it, step 3 keeps the shape the mesh has when it starts.
using Work_face_tree = Face_tree<Work_mesh, boost::property_map<Work_mesh, CGAL::vertex_point_t>::type>;
Deformation_report fine_on_surface(Work_mesh& tm, const Curve_network& network, const std::vector<Correspondence>& pairs,
                                   const Deform_options& options, bool split_for_paths = false,
                                   std::optional<Work_face_tree> tree = std::nullopt,
                                   const std::vector<double>* template_bending = nullptr);

/// The largest template that deform_template's subdivision makes.
constexpr std::size_t max_subdivided_faces = 2000000;

/// The fewest template vertices that deform_template leaves to the surface fine level: twice the
/// network's vertices (room beside every chain), and 40 free vertices (beyond the network's) for
/// every region the network bounds on a sphere (its independent cycles plus one), so that the shape
/// between the curves is more than a face or two. Measured on bench/battery's
/// ico162-bumpy-latlong (162 template vertices, 117 network vertices, 24 regions), Hausdorff
/// distance to the truth in % of the diagonal after 1, 2 and 3 midpoint subdivisions (22, 102 and
/// 422 free vertices per region): 1.50, 0.77 and 1.18. Not more than 40: the 1 014-face
/// open-mesh_with_border (48 per region) passes as it is, and subdivided once leaves a face
/// turned over against the truth on its wave.
inline double wanted_template_vertices(const Curve_network& network) {
  const auto n = static_cast<double>(network.number_of_vertices());
  return std::max(2 * n, n + 40 * static_cast<double>(network.number_of_independent_cycles() + 1));
}

/// The median length of the network's segments (the upper one of an even count); 0 without segments.
inline double median_segment_length(const Curve_network& network) {
  std::vector<double> lengths;
  for (const auto& sk : network.segments())
    lengths.push_back(std::sqrt(CGAL::squared_distance(network.point(sk[0]), network.point(sk[1]))));
  if (lengths.empty()) return 0;
  std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
  return lengths[lengths.size() / 2];
}

/// Fine_shape::automatic (deform.h) resolved on the mesh the surface fine level starts from:
/// Fine_shape::approach when the curves are sampled more densely than the template's edges (the
/// median segment shorter than half the mean edge of `tm` times 2^`subdivisions`, the midpoint
/// subdivisions made before the coarse level: the template's own edge at the curves' scale),
/// Fine_shape::template_bending otherwise. Other values are returned as they are. A ratio of
/// lengths: unchanged by where the inputs are placed.
template <typename TriangleMesh, typename VPM>
Fine_shape resolved_fine_shape(Fine_shape shape, const TriangleMesh& tm, const VPM& vpm, const Curve_network& network,
                               std::size_t subdivisions = 0) {
  if (shape != Fine_shape::automatic) return shape;
  const double edge = std::ldexp(mean_edge_length(tm, vpm), static_cast<int>(subdivisions));
  return 2 * median_segment_length(network) < edge ? Fine_shape::approach : Fine_shape::template_bending;
}

/// Curves sampled far more densely than the (subdivided, coarsely placed) template's edges would
/// put rows of network vertices a fraction of an edge apart into its faces: needles that fold,
/// found only after a long run. Refused when the median segment is shorter than an eighth of the
/// mean edge (lengths in the curves' frame, after the coarse level).
template <typename TriangleMesh, typename VPM>
void refuse_oversampled_curves(const TriangleMesh& tm, const VPM& vpm, const Curve_network& network,
                               std::size_t subdivisions) {
  const double edge = mean_edge_length(tm, vpm);
  const double median = median_segment_length(network);
  if (!(median > 0 && median * 8 < edge)) return;
  std::ostringstream os;
  os.precision(3);
  os << "the curves are sampled " << edge / median << " times more densely than the template's edges";
  if (subdivisions > 0) os << " after " << subdivisions << " midpoint subdivision" << (subdivisions > 1 ? "s" : "");
  os << " (median segment " << median << ", mean edge " << edge
     << "): every network vertex becomes a mesh vertex, and rows of them inside single faces fold; sample the "
        "curves more sparsely (a point or two per template edge is enough), or give a finer template";
  throw Algorithm_failure("deform", os.str(),
                          {{"median_segment_length", median}, {"mean_edge_length", edge},
                           {"template_subdivisions", static_cast<double>(subdivisions)}});
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_DEFORM_IMPL_H
