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
#include <meshfit/internal/angle_flips.h>
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
#include <meshfit/partition.h>
#include <meshfit/surface_walk.h>
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
      if (!internal::edge_folds(tm, h, [&](vertex_descriptor v) { return positions[get(index, v)]; })) continue;
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

/// "polyline 3" or "polylines 1, 4, 7" (1-based, in file order), at most ten named.
inline std::string name_polylines(const std::vector<std::size_t>& polylines) {
  std::ostringstream os;
  os << (polylines.size() == 1 ? "polyline " : "polylines ");
  for (std::size_t k = 0; k < polylines.size() && k < 10; ++k) os << (k ? ", " : "") << polylines[k] + 1;
  if (polylines.size() > 10) os << " and " << polylines.size() - 10 << " more";
  return os.str();
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
                                          them);
  }
  for (std::size_t k = 0; k < network.polylines().size(); ++k) {
    const auto& pl = network.polylines()[k];
    for (std::size_t i = 0; i < pl.size(); ++i) {
      const double d = distance(pl[i]);
      if (!(d > size)) continue;
      throw Algorithm_failure("deform", name_polylines({k}) + " (in file order), point " + std::to_string(i + 1) +
                                            ", lies " + format_number(d / size) +
                                            " times the template's size away from it after the coarse level: "
                                            "curves must run on the surface; check that point, or remove it");
    }
  }
}

/// refuse_far_polylines with the distances to the faces of `tm` and its bounding-box diagonal.
template <typename TriangleMesh, typename VPM>
void check_polylines_near(const TriangleMesh& tm, const VPM& vpm, const Curve_network& network) {
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<TriangleMesh, VPM>;
  CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>> tree(faces(tm).first, faces(tm).second, tm, vpm);
  tree.accelerate_distance_queries();
  refuse_far_polylines(
      network, [&](std::size_t v) { return std::sqrt(tree.squared_distance(network.point(v))); }, bbox_diagonal(tm, vpm));
}

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
  using GT = boost::graph_traits<TriangleMesh>;
  using face_descriptor = typename GT::face_descriptor;
  const std::size_t nv = network.number_of_vertices();
  std::vector<Point_3> q(nv);
  std::vector<face_descriptor> face_of(nv, GT::null_face());
  std::vector<bool> known(nv, false);
  std::deque<std::size_t> queue;
  auto triangle = [&](face_descriptor f) {
    const auto h = halfedge(f, tm);
    return Kernel::Triangle_3(point_of<TriangleMesh>(vpm, source(h, tm)), point_of<TriangleMesh>(vpm, target(h, tm)),
                              point_of<TriangleMesh>(vpm, target(next(h, tm), tm)));
  };
  for (const Correspondence& c : pairs) {
    if (known[c.network_vertex]) continue;
    auto v = *std::next(vertices(tm).first, static_cast<std::ptrdiff_t>(c.template_vertex));
    for (auto h : CGAL::halfedges_around_target(halfedge(v, tm), tm))
      if (!is_border(h, tm)) face_of[c.network_vertex] = face(h, tm);
    q[c.network_vertex] = point_of<TriangleMesh>(vpm, v);
    known[c.network_vertex] = true;
    queue.push_back(c.network_vertex);
  }
  global_jumps = 0;
  std::vector<bool> component_seeded(network.number_of_components(), false);
  for (std::size_t v : queue) component_seeded[network.component(v)] = true;
  std::vector<std::size_t> seed_of(network.number_of_components(), SIZE_MAX);
  std::vector<double> seed_distance(network.number_of_components(), std::numeric_limits<double>::infinity());
  for (std::size_t v = 0; v < nv; ++v) {
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
  auto seen = get(CGAL::dynamic_face_property_t<std::size_t>(), tm);
  for (auto f : faces(tm)) put(seen, f, SIZE_MAX);
  std::size_t search = 0;
  const std::size_t face_budget = std::max<std::size_t>(num_faces(tm) / 4, 2000);
  while (!queue.empty()) {
    const std::size_t v = queue.front();
    queue.pop_front();
    for (std::size_t k : network.incident_segments(v)) {
      const auto& sg = network.segments()[k];
      const std::size_t w = sg[0] == v ? sg[1] : sg[0];
      if (known[w]) continue;
      const Point_3& p = network.point(w);
      const double reach = 2 * std::sqrt(CGAL::squared_distance(network.point(v), p)) +
                           std::sqrt(CGAL::squared_distance(network.point(v), q[v]));
      ++search;
      // The faces within reach are searched nearest to p first, and the search ends at the nearest
      // face of the whole surface when it is within reach (the usual case): that face is then the
      // answer, found after a path's worth of faces rather than the whole disc.
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
      if (!reached_nearest) ++global_jumps;
      queue.push_back(w);
    }
  }
  return q;
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

/// What approach_curves did.
struct Approach_result {
  std::size_t constraints = 0;  ///< template vertices given a displacement
  double scale = 0;             ///< the part of the displacement applied (0: none)
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

/// Non-rigid ICP: brings the coarse surface towards the curves in up to six steps of falling
/// stiffness (10, then a quarter of the last), before the curves are embedded in it. Each step
/// takes every network vertex's surface point (tracked along the curves: tracked_projections)
/// and asks, in the least-squares sense, that the point of its face move onto the vertex, against
/// `stiffness` times the thin-plate energy of the motion (fit_displacements). Where the step
/// turns a face over against its own normal before the step (an exact orientation with the
/// normal's end as fourth point) or folds an edge that was neither folded nor sharp (faces more
/// than 60 degrees apart: a smooth motion may tip such an edge over), the free vertices around
/// those faces (2, then 6 rings; the border stays) are untangled (untangle_faces). A step that
/// still leaves such a face is halved, twice; the first step that cannot be made ends the
/// approach, as does every network vertex lying within a quarter of the mean edge of its surface
/// point (before any step: no approach). The stiffness and the data are free of units (uniform Laplacian, barycentric
/// weights): the motion does not depend on where the inputs are placed.
template <typename TriangleMesh, typename VPM>
Approach_result approach_curves_icp(TriangleMesh& tm, const VPM& vpm, const Curve_network& network,
                                    const std::vector<Correspondence>& pairs) {
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<TriangleMesh, VPM>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  Deform_state<TriangleMesh, VPM> s(tm, vpm);
  const std::size_t n = s.vertex.size();
  const Vertex_adjacency adjacency = s.adjacency();
  std::vector<std::array<std::size_t, 3>> corners;
  auto face_index = get(CGAL::dynamic_face_property_t<std::size_t>(), tm);
  for (auto f : faces(tm)) {
    put(face_index, f, corners.size());
    corners.push_back(s.corners(f));
  }
  // Edges exempt from the fold test: folded or sharp on the coarse surface.
  std::vector<bool> exempt;
  s.folded_faces(s.positions(), &exempt);
  {
    const std::vector<Point_3> p = s.positions();
    auto normal = [&](auto h) {
      const auto& c = corners[get(face_index, face(h, tm))];
      return CGAL::cross_product(p[c[1]] - p[c[0]], p[c[2]] - p[c[0]]);
    };
    std::size_t k = 0;
    for (auto e : edges(tm)) {
      const std::size_t ek = k++;
      const auto h = halfedge(e, tm), g = opposite(h, tm);
      if (is_border(h, tm) || is_border(g, tm)) continue;
      const Vector_3 a = normal(h), b = normal(g);
      if (!(a * b > 0.5 * std::sqrt(a.squared_length() * b.squared_length()))) exempt[ek] = true;
    }
  }
  const double h = mean_edge_length(tm, vpm);
  Approach_result result;
  double stiffness = 10;
  for (int step = 0; step < 6; ++step, stiffness /= 4) {
    const std::vector<Point_3> before = s.positions();
    std::vector<Soft_displacement> constraints;
    {
      Tree tree(faces(tm).first, faces(tm).second, tm, vpm);
      tree.accelerate_distance_queries();
      std::size_t off_nearest = 0;
      const std::vector<Point_3> surface_point = tracked_projections(tm, vpm, tree, network, pairs, off_nearest);
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
    }
    result.constraints = constraints.size();
    // Done when every network vertex is within a quarter of an edge of its surface point: what is
    // left is finer than the mesh (the 81 920-face scale case is there after one step; five more
    // cost 12 s and moved nothing that mattered).
    double largest_gap = 0;
    for (const Soft_displacement& c : constraints) largest_gap = std::max(largest_gap, c.target.squared_length());
    if (largest_gap < 0.0625 * h * h) break;
    const std::vector<Vector_3> d = fit_displacements(adjacency, constraints, stiffness);
    // Faces judged against their normals before the step; vertices move in their tangent planes.
    std::vector<Vector_3> face_normal, vertex_normal(n, Vector_3(0, 0, 0));
    for (const auto& c : corners) {
      face_normal.push_back(CGAL::cross_product(before[c[1]] - before[c[0]], before[c[2]] - before[c[0]]));
      for (std::size_t k : c) vertex_normal[k] = vertex_normal[k] + face_normal.back();
    }
    // A face of no area has no normal to judge it by (untangle_faces refuses it): the approach
    // ends. (The example translated by 1e15, whose x coordinates are multiples of 1/8, has such.)
    if (std::any_of(face_normal.begin(), face_normal.end(), [](const Vector_3& v) { return v == CGAL::NULL_VECTOR; }))
      break;
    // The faces turned over, then those beside a folded edge; `folds` gets the folded edges as the
    // pairs of faces (f, g) beside them.
    using Fold = std::array<std::size_t, 2>;
    auto bad_faces = [&](const std::vector<Point_3>& p, std::vector<Fold>& folds) {
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
    };
    bool moved = false;
    for (double scale = 1; scale > 0.2 && !moved; scale /= 2) {
      std::vector<Point_3> after(n);
      for (std::size_t i = 0; i < n; ++i) after[i] = before[i] + scale * d[i];
      std::vector<Fold> folds;
      std::vector<std::size_t> bad = bad_faces(after, folds);
      for (std::size_t rings : {2, 6}) {
        if (bad.empty()) break;
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
        std::vector<std::size_t> now = bad_faces(trial, trial_folds);
        if (now.size() < bad.size()) after.swap(trial), bad.swap(now), folds.swap(trial_folds);
      }
      if (!bad.empty()) continue;
      s.set_positions(after);
      result.scale = scale;
      moved = true;
    }
    if (!moved) break;
  }
  return result;
}

/// deform_fine_on_surface on the network as it is (its long segments not cut).
template <typename TriangleMesh>
Deformation_report fine_on_surface(TriangleMesh& tm, const Curve_network& network, const std::vector<Correspondence>& pairs,
                                   const Deform_options& options) {
  using GT = boost::graph_traits<TriangleMesh>;
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t max_rounds = options.flip_prevention_rounds;
  const Progress_callback& progress = options.progress;
  // Stage 2's progress during the embedding is reported as this stage's.
  const Progress_callback forward = [&progress](const Progress_step& step) {
    return progress(Progress_step{"deform", "fine: embedding the curves: " + step.step, 1, 4});
  };

  auto vpm = get_property_map(CGAL::vertex_point, tm);
  internal::Deform_state<TriangleMesh, decltype(vpm)> s(tm, vpm);
  internal::check_pairs(pairs, s.vertex.size(), num_faces(tm), network);
  // A network that is not planar cannot be drawn on a genus-0 template without crossings.
  if (internal::genus_zero_border_cycles(tm)) {
    const std::vector<std::size_t> kuratowski = network.non_planar_segments();
    if (!kuratowski.empty())
      throw Algorithm_failure(
          "deform", "the curve network is not planar: " + internal::name_polylines(network.polylines_of_segments(kuratowski)) +
                        " (in file order) form a subdivision of K5 or K3,3, which cannot be drawn on this genus-0 "
                        "template without two curves crossing; curves that cross must share a vertex (a point written "
                        "identically in both polylines), or the template needs a handle");
  }
  Deformation_report report;
  report.fine_level = Fine_level::surface;
  report.user_pairs = pairs.size();
  const std::size_t unassigned = Closest_point_assignment::unassigned;
  const std::size_t nv = network.number_of_vertices();
  std::vector<std::size_t> mesh_of(nv, unassigned);
  std::vector<bool> reserved(s.vertex.size(), false);
  for (const Correspondence& c : pairs) {
    const bool other_vertex = mesh_of[c.network_vertex] != unassigned && mesh_of[c.network_vertex] != c.template_vertex;
    const bool other_point = reserved[c.template_vertex] && mesh_of[c.network_vertex] != c.template_vertex;
    if (other_vertex || other_point)
      throw Invalid_input(c.where, std::string("deform: this pair gives ") +
                                       (other_vertex ? "a network vertex a second template vertex"
                                                     : "a template vertex a second network vertex"));
    mesh_of[c.network_vertex] = c.template_vertex;
    reserved[c.template_vertex] = true;
  }

  // 1. Network vertices onto the surface. Whatever distance lies between a network vertex's
  // surface point and its mesh vertex is a tangential motion in step 3, which can fold small
  // faces: the margin that keeps new vertices off edges and corners is small.
  const double placement_margin = 0.05;
  internal::report_progress(progress, "deform", "fine: placing the network vertices on the surface", 0, 4);
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<TriangleMesh, decltype(vpm)>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  const std::size_t template_vertices = s.vertex.size();
  std::vector<double> distance(nv, 0);
  std::vector<Point_3> surface_point;
  {
    Tree tree(faces(tm).first, faces(tm).second, tm, vpm);
    tree.accelerate_distance_queries();
    surface_point = internal::tracked_projections(tm, vpm, tree, network, pairs, report.projections_off_nearest);
    // A polyline all of whose points are far from the surface cannot be embedded in it: say so
    // now, rather than after a long run.
    const double diag = internal::bbox_diagonal(tm, vpm);
    for (std::size_t v = 0; v < nv; ++v) {
      distance[v] = std::sqrt(CGAL::squared_distance(tree.closest_point(network.point(v)), network.point(v)));
      report.largest_projection_distance = std::max(report.largest_projection_distance, distance[v]);
    }
    internal::refuse_far_polylines(network, [&](std::size_t v) { return distance[v]; }, diag);
  }

  // Boundary: the vertices of curves that run along the template's border go onto the border (a
  // border edge is split, or a border vertex used), and a segment between two such vertices that
  // runs along the border becomes the border arc between them, rather than a chord cutting border
  // triangles off.
  std::vector<bool> on_border(nv, false);
  std::vector<typename GT::halfedge_descriptor> border;
  for (auto h : halfedges(tm))
    if (is_border(h, tm)) border.push_back(h);
  struct Border_point {
    typename GT::halfedge_descriptor h;
    double d2 = std::numeric_limits<double>::infinity(), u = 0, length = 0;
  };
  auto nearest_border_point = [&](const Point_3& p) {
    Border_point best;
    for (auto h : border) {
      const Point_3 a = s.to_point(source(h, tm)), b = s.to_point(target(h, tm));
      const Vector_3 ab = b - a;
      const double len2 = ab.squared_length();
      const double u = len2 > 0 ? std::min(1.0, std::max(0.0, ((p - a) * ab) / len2)) : 0.0;
      const double d2 = CGAL::squared_distance(p, a + u * ab);
      if (d2 < best.d2) best = {h, d2, u, std::sqrt(len2)};
    }
    return best;
  };
  if (!border.empty()) {
    // Near the border: nearer to it than half a border edge more than to the surface. A curve
    // (network.curves()) runs along the border when its shadow there (the path of the nearest
    // border points of its consecutive near vertices) is at least half as long as the curve, and
    // its vertices go onto the border. A curve that only ends there, or leaves the coarse surface
    // across the border (its points beyond are near the border too, but their shadows bunch up),
    // keeps its inner vertices inside.
    std::vector<bool> near(nv, false);
    std::vector<Point_3> shadow(nv);
    for (std::size_t v = 0; v < nv; ++v) {
      if (mesh_of[v] != unassigned) {
        near[v] = static_cast<bool>(is_border(s.vertex[mesh_of[v]], tm));
        shadow[v] = s.to_point(s.vertex[mesh_of[v]]);
        continue;
      }
      const Border_point b = nearest_border_point(network.point(v));
      near[v] = std::sqrt(b.d2) <= distance[v] + 0.5 * b.length;
      const Point_3 a = s.to_point(source(b.h, tm)), c = s.to_point(target(b.h, tm));
      shadow[v] = a + b.u * (c - a);
    }
    for (const auto& curve_vertices : network.curves()) {
      const auto& cv = curve_vertices.vertices;
      double length = 0, along = 0;
      for (std::size_t i = 0; i + 1 < cv.size(); ++i) {
        length += std::sqrt(CGAL::squared_distance(network.point(cv[i]), network.point(cv[i + 1])));
        if (near[cv[i]] && near[cv[i + 1]]) along += std::sqrt(CGAL::squared_distance(shadow[cv[i]], shadow[cv[i + 1]]));
      }
      if (length > 0 && 2 * along >= length)
        for (std::size_t v : cv) on_border[v] = on_border[v] || near[v] || v == cv.front() || v == cv.back();
    }
    for (std::size_t v = 0; v < nv; ++v)
      if (mesh_of[v] != unassigned) on_border[v] = near[v];
  }
  for (std::size_t v = 0; v < nv && !border.empty(); ++v) {
    if (mesh_of[v] != unassigned || !on_border[v]) continue;
    const Border_point bp = nearest_border_point(network.point(v));
    const auto best = bp.h;
    const double best_u = bp.u;
    const typename GT::vertex_descriptor near_end = best_u < 0.5 ? source(best, tm) : target(best, tm);
    const std::size_t e = get(s.index, near_end);
    if ((best_u < placement_margin || best_u > 1 - placement_margin) && !reserved[e]) {
      mesh_of[v] = e;
    } else {
      const double u = std::min(1 - placement_margin, std::max(placement_margin, best_u));
      const Point_3 a = s.to_point(source(best, tm)), b = s.to_point(target(best, tm));
      mesh_of[v] = s.split_edge_at(best, a + u * (b - a));
      reserved.resize(s.vertex.size(), false);
      const auto x = s.vertex[mesh_of[v]];
      for (auto h : CGAL::halfedges_around_target(halfedge(x, tm), tm)) {
        if (is_border(h, tm)) border.push_back(h);
        if (is_border(opposite(h, tm), tm)) border.push_back(opposite(h, tm));
      }
    }
    reserved[mesh_of[v]] = true;
  }
  std::vector<std::size_t> waiting;
  for (std::size_t v = 0; v < nv; ++v)
    if (mesh_of[v] == unassigned) waiting.push_back(v);
  for (std::size_t pass = 0; !waiting.empty(); ++pass) {
    Tree tree(faces(tm).first, faces(tm).second, tm, vpm);
    tree.accelerate_distance_queries();
    // One network vertex per face and pass, in the order of the network vertices (not of the
    // face handles, which on a Polyhedron_3 are addresses): the result does not depend on memory.
    std::set<typename GT::face_descriptor> taken;
    std::vector<std::pair<std::size_t, std::pair<typename GT::face_descriptor, Point_3>>> at;
    std::vector<std::size_t> later;
    for (std::size_t v : waiting) {
      const auto hit = tree.closest_point_and_primitive(surface_point[v]);
      if (taken.insert(hit.second).second)
        at.push_back({v, {hit.second, Point_3(hit.first.x(), hit.first.y(), hit.first.z())}});
      else
        later.push_back(v);
    }
    for (const auto& [v, fp] : at) {
      const std::size_t t = s.insert_near(fp.first, fp.second, reserved, placement_margin, false, !on_border[v]);
      reserved.resize(s.vertex.size(), false);
      reserved[t] = true;
      mesh_of[v] = t;
    }
    waiting.swap(later);
  }
  report.vertices_inserted_for_density = s.vertex.size() - template_vertices;
  report.faces_subdivided = s.faces_split;

  // Curves that cross without a shared vertex cannot both be edge chains: two segments of
  // different polylines with no common end whose surface images cross in the view along the surface normal there (exact
  // orientations in that view) while the segments themselves nearly meet in space.
  {
    using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;
    const auto& segs = network.segments();
    std::vector<Box> boxes;
    for (std::size_t k = 0; k < segs.size(); ++k)
      boxes.emplace_back(s.to_point(s.vertex[mesh_of[segs[k][0]]]).bbox() + s.to_point(s.vertex[mesh_of[segs[k][1]]]).bbox(), k);
    // The polyline of each segment: two segments of one polyline are not compared (a plane
    // section of a thin part passes close to itself, and its projection may cross there).
    std::vector<std::size_t> polyline_of(segs.size(), SIZE_MAX);
    {
      std::map<std::pair<std::size_t, std::size_t>, std::size_t> index;
      for (std::size_t k = 0; k < segs.size(); ++k) index[std::minmax(segs[k][0], segs[k][1])] = k;
      for (std::size_t l = 0; l < network.polylines().size(); ++l) {
        const auto& pl = network.polylines()[l];
        for (std::size_t i = 0; i + 1 < pl.size(); ++i) {
          const auto it = index.find(std::minmax(pl[i], pl[i + 1]));
          if (it != index.end() && polyline_of[it->second] == SIZE_MAX) polyline_of[it->second] = l;
        }
      }
    }
    std::vector<std::pair<std::size_t, std::size_t>> crossing;
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& x, const Box& y) {
      const auto& p = segs[x.info()];
      const auto& q = segs[y.info()];
      if (p[0] == q[0] || p[0] == q[1] || p[1] == q[0] || p[1] == q[1]) return;
      if (polyline_of[x.info()] == polyline_of[y.info()]) return;
      const Point_3 a = s.to_point(s.vertex[mesh_of[p[0]]]), b = s.to_point(s.vertex[mesh_of[p[1]]]),
                    c = s.to_point(s.vertex[mesh_of[q[0]]]), d = s.to_point(s.vertex[mesh_of[q[1]]]);
      const Segment_3 sp(network.point(p[0]), network.point(p[1])), sq(network.point(q[0]), network.point(q[1]));
      // Near in space (a hundredth of the longer segment): curves that pass each other at a distance
      // are not refused on the strength of their projections alone.
      const double reach = 0.01 * std::sqrt(std::max(sp.squared_length(), sq.squared_length()));
      const double gap = CGAL::squared_distance(sp, sq);
      if (!(gap < reach * reach)) return;
      // Nearest at an end of one of them: a segment that stops just short of the other curve (the
      // one before a crossing vertex inserted next to a sample point) passes it, it does not cross.
      const double end_gap = std::min({CGAL::squared_distance(sp.source(), sq), CGAL::squared_distance(sp.target(), sq),
                                       CGAL::squared_distance(sq.source(), sp), CGAL::squared_distance(sq.target(), sp)});
      if (!(end_gap > 4 * gap)) return;
      const Vector_3 N = s.normal(mesh_of[p[0]]) + s.normal(mesh_of[p[1]]) + s.normal(mesh_of[q[0]]) + s.normal(mesh_of[q[1]]);
      if (N == CGAL::NULL_VECTOR) return;
      const Vector_3 u = CGAL::cross_product(N, std::abs(N.x()) < std::abs(N.y()) ? Vector_3(1, 0, 0) : Vector_3(0, 1, 0));
      const Triangle_points view{a, a + u, a + CGAL::cross_product(N, u)};
      const auto side = [&](const Point_3& e, const Point_3& f, const Point_3& g) { return orientation_in_plane(view, e, f, g); };
      const CGAL::Sign c1 = side(a, b, c), c2 = side(a, b, d), c3 = side(c, d, a), c4 = side(c, d, b);
      if (c1 != CGAL::ZERO && c2 != CGAL::ZERO && c3 != CGAL::ZERO && c4 != CGAL::ZERO && c1 != c2 && c3 != c4)
        crossing.emplace_back(std::min(x.info(), y.info()), std::max(x.info(), y.info()));
    });
    if (!crossing.empty()) {
      std::sort(crossing.begin(), crossing.end());
      const auto [p, q] = crossing.front();
      const Point_3 m = CGAL::midpoint(network.point(segs[p][0]), network.point(segs[p][1]));
      std::ostringstream os;
      os.precision(6);
      os << crossing.size() << " pair" << (crossing.size() == 1 ? "" : "s")
         << " of segments cross without a shared vertex; the first: "
         << internal::name_polylines(network.polylines_of_segments({p, q})) << " (in file order) cross near (" << m
         << "): curves that cross must share a vertex there (the same point written in both polylines)";
      throw Algorithm_failure("deform", os.str());
    }
  }

  // 2. The network as projected, embedded in the surface.
  internal::report_progress(progress, "deform", "fine: embedding the curves in the coarse surface", 1, 4);
  // Segments along the boundary: the border arc from one end to the other that passes no other
  // network vertex, when it is at most half as long again as the segment (a segment across the
  // surface between two boundary points is not along the boundary).
  std::vector<bool> is_network_vertex(s.vertex.size(), false);
  for (std::size_t t : mesh_of) is_network_vertex[t] = true;
  auto fixed = get(CGAL::dynamic_vertex_property_t<bool>(), tm);
  for (auto v : vertices(tm)) put(fixed, v, false);
  std::vector<std::vector<typename GT::vertex_descriptor>> arc(network.segments().size());
  for (std::size_t k = 0; k < network.segments().size(); ++k) {
    const auto [a, b] = network.segments()[k];
    if (!on_border[a] || !on_border[b]) continue;
    const auto A = s.vertex[mesh_of[a]], B = s.vertex[mesh_of[b]];
    const double chord = std::sqrt(CGAL::squared_distance(s.to_point(A), s.to_point(B)));
    for (auto h0 : CGAL::halfedges_around_source(A, tm)) {
      // Border halfedges leaving A, and those entering it walked backwards.
      for (int direction = 0; direction < 2; ++direction) {
        const auto start = direction == 0 ? h0 : opposite(h0, tm);
        if (!is_border(start, tm)) continue;
        std::vector<typename GT::vertex_descriptor> path{A};
        double length = 0;
        auto h = start;
        for (std::size_t guard = 0; guard < border.size() + 2; ++guard) {
          const auto u = direction == 0 ? target(h, tm) : source(h, tm);
          length += std::sqrt(CGAL::squared_distance(s.to_point(path.back()), s.to_point(u)));
          path.push_back(u);
          if (u == B || is_network_vertex[get(s.index, u)] || length > 1.5 * chord) break;
          h = direction == 0 ? next(h, tm) : prev(h, tm);
        }
        if (path.back() == B && length <= 1.5 * chord && (arc[k].empty() || path.size() < arc[k].size()))
          arc[k] = path;
      }
    }
    for (std::size_t i = 1; i + 1 < arc[k].size(); ++i) put(fixed, arc[k][i], true);
  }

  // Normals of the coarse surface (its faces only split so far, no shape changed): what "turned
  // over" is judged against in step 4. Stage 2's insertion may leave faces standing on edge where
  // a curve runs through a template vertex; their own normals would not be a reference.
  std::vector<Vector_3> reference_normal(s.vertex.size());
  for (std::size_t i = 0; i < s.vertex.size(); ++i) reference_normal[i] = s.normal(i);

  // The network as projected, but for the boundary segments, embedded by stage 2's insertion.
  // Two network vertices placed at one point (curves denser than the template's faces there)
  // would make a segment of zero length, which no network holds.
  const char* too_dense = "network vertices land on the surface where others do: the curves are "
                          "denser than the template can hold there (refine the template)";
  std::vector<Curve_network::Polyline> lines;
  for (std::size_t k = 0; k < network.segments().size(); ++k)
    if (arc[k].empty()) {
      lines.push_back({s.to_point(s.vertex[mesh_of[network.segments()[k][0]]]),
                       s.to_point(s.vertex[mesh_of[network.segments()[k][1]]])});
      if (lines.back()[0] == lines.back()[1]) throw Algorithm_failure("deform", too_dense);
    }
  auto curve = get(CGAL::dynamic_edge_property_t<bool>(), tm);
  for (auto e : edges(tm)) put(curve, e, false);
  if (!lines.empty()) {
    // One polyline per segment, numbered by the code, not the user's file: the network's own
    // refusals (two points merged within its tolerance) say that the curves are too dense here.
    const Curve_network projected = [&] {
      try {
        return Curve_network(lines);
      } catch (const Invalid_input&) {
        throw Algorithm_failure("deform", too_dense);
      }
    }();
    std::vector<bool> used(nv, false);
    for (std::size_t k = 0; k < network.segments().size(); ++k)
      if (arc[k].empty()) used[network.segments()[k][0]] = used[network.segments()[k][1]] = true;
    if (projected.number_of_vertices() != static_cast<std::size_t>(std::count(used.begin(), used.end(), true)))
      throw Algorithm_failure("deform", too_dense);
    try {
      report.embedding = partition_work(tm, projected, forward, curve, &fixed, nullptr);
    } catch (const Invalid_input& e) {
      // Stage 2 finds network vertices by position: two of them placed nearer to each other than
      // to any other mesh vertex cannot be told apart.
      throw Algorithm_failure("deform", std::string("the curves are denser than the template can hold (") + e.what() +
                                            "): use a finer template, or sparser curves");
    }
  }
  // Chain vertices lie on their (projected) segments within rounding: the default merge
  // tolerance of the mesh's size.
  const double chain_tolerance = default_merge_tolerance * internal::bbox_diagonal(tm, vpm);

  // Each segment's chain: its boundary arc, or the chain stage 2 made of it. Where stage 2 could
  // not make one (its insertion refuses to fold the surface, and its fallback moves vertices onto
  // the chord, which may lie off the surface), the shortest edge path from one end to the other
  // that crosses no chain (through no chain vertex nor curve edge) is taken as it is: only its
  // topology matters here, since step 3 moves its vertices onto the segment anyway.
  const auto& segments = network.segments();
  std::vector<std::vector<typename GT::vertex_descriptor>> chain_of(segments.size());
  std::vector<bool> on_chain = is_network_vertex;
  on_chain.resize(s.vertex.size(), false);
  std::vector<std::size_t> missing;
  for (std::size_t k = 0; k < segments.size(); ++k) {
    chain_of[k] = !arc[k].empty() ? arc[k]
                                  : segment_edge_chain(tm, vpm, curve, s.vertex[mesh_of[segments[k][0]]],
                                                       s.vertex[mesh_of[segments[k][1]]], chain_tolerance);
    // A chain through another network vertex (three of them in a line on the projected surface)
    // would give that vertex two places: such a segment takes the shortest path instead.
    for (std::size_t i = 1; i + 1 < chain_of[k].size(); ++i)
      if (is_network_vertex[get(s.index, chain_of[k][i])]) {
        chain_of[k].clear();
        break;
      }
    if (chain_of[k].size() < 2) missing.push_back(k);
    for (std::size_t i = 0; i + 1 < chain_of[k].size(); ++i) {
      put(curve, edge(halfedge(chain_of[k][i], chain_of[k][i + 1], tm).first, tm), true);
      on_chain[get(s.index, chain_of[k][i])] = true;
    }
  }
  for (std::size_t k : missing) {
    const auto A = s.vertex[mesh_of[segments[k][0]]], B = s.vertex[mesh_of[segments[k][1]]];
    const Segment_3 chord(s.to_point(A), s.to_point(B));
    std::vector<double> dist(s.vertex.size(), std::numeric_limits<double>::infinity());
    std::vector<std::size_t> from(s.vertex.size(), unassigned);
    using Item = std::pair<double, std::size_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    const std::size_t ia = get(s.index, A), ib = get(s.index, B);
    dist[ia] = 0;
    queue.emplace(0.0, ia);
    while (!queue.empty()) {
      const auto [du, u] = queue.top();
      queue.pop();
      if (du > dist[u]) continue;
      if (u == ib) break;
      if (u != ia && on_chain[u]) continue;
      for (auto h : CGAL::halfedges_around_target(halfedge(s.vertex[u], tm), tm)) {
        if (get(curve, edge(h, tm))) continue;
        const std::size_t w = get(s.index, source(h, tm));
        if (w != ib && on_chain[w]) continue;
        const Point_3 pw = s.to_point(s.vertex[w]);
        const double dw = du + std::sqrt(CGAL::squared_distance(s.to_point(s.vertex[u]), pw)) +
                          2 * std::sqrt(CGAL::squared_distance(chord, pw));
        if (dw < dist[w]) dist[w] = dw, from[w] = u, queue.emplace(dw, w);
      }
    }
    if (from[ib] == unassigned) continue;
    std::vector<typename GT::vertex_descriptor> path;
    for (std::size_t u = ib; u != unassigned; u = from[u]) path.push_back(s.vertex[u]);
    std::reverse(path.begin(), path.end());
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      put(curve, edge(halfedge(path[i], path[i + 1], tm).first, tm), true);
      on_chain[get(s.index, path[i])] = true;
    }
    arc[k] = path;  // placed by arc length below, as boundary arcs are
    chain_of[k] = std::move(path);
    ++report.segments_by_shortest_path;
  }

  // Where two chains run side by side, or a chain turns round a triangle, a face has all its
  // corners on curves: nothing of it can move when the curves take their places, and it folds or
  // collapses onto a segment. An interior edge that joins two held vertices and is no curve edge
  // is split at its midpoint, so that every face keeps a free corner to be moved (step 4). When
  // such faces are a quarter of the mesh and the network has more than twice the template's
  // vertices, the curves leave the template no room between them: say so, rather than grow the
  // mesh and untangle what cannot be. (A template whose vertices all lie on the curves, a
  // tetrahedron onto its own edges say, needs no room.)
  {
    std::size_t all_held = 0, total = 0;
    for (auto f : faces(tm)) {
      const auto c = s.corners(f);
      ++total;
      if (on_chain[c[0]] && on_chain[c[1]] && on_chain[c[2]]) ++all_held;
    }
    if (4 * all_held > total && nv > 2 * template_vertices)
      throw Algorithm_failure("deform", "the curves are denser than the template can hold: " + std::to_string(all_held) +
                                            " of the " + std::to_string(total) +
                                            " faces of the embedding have all their corners on curves (" +
                                            std::to_string(nv) + " network vertices on a template of " +
                                            std::to_string(template_vertices) +
                                            "): use a finer template (subdivide it), or sparser curves");
    std::vector<typename GT::halfedge_descriptor> joining;
    for (auto e : edges(tm)) {
      const auto h = halfedge(e, tm);
      if (get(curve, e) || is_border(h, tm) || is_border(opposite(h, tm), tm)) continue;
      if (on_chain[get(s.index, source(h, tm))] && on_chain[get(s.index, target(h, tm))]) joining.push_back(h);
    }
    for (auto h : joining) {
      const std::size_t a = get(s.index, source(h, tm)), b = get(s.index, target(h, tm));
      s.split_edge_at(h, CGAL::midpoint(s.to_point(source(h, tm)), s.to_point(target(h, tm))));
      reference_normal.push_back(reference_normal[a] + reference_normal[b]);
      on_chain.push_back(false);
      is_network_vertex.push_back(false);
    }
    report.edges_split_between_curves = joining.size();
  }

  // 3. Targets: network vertices at their points, chain vertices on their segments.
  internal::report_progress(progress, "deform", "fine: moving the curves into place (thin-plate displacement)", 2, 4);
  const std::vector<Point_3> before = s.positions();
  const std::size_t n = before.size();
  std::vector<bool> constrained(n, false);
  std::vector<Point_3> goal(n);
  for (std::size_t v = 0; v < nv; ++v) {
    constrained[mesh_of[v]] = true;
    goal[mesh_of[v]] = network.point(v);
  }
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const auto [a, b] = segments[k];
    const auto A = s.vertex[mesh_of[a]], B = s.vertex[mesh_of[b]];
    const auto& chain = chain_of[k];
    if (chain.size() < 2) {
      report.segments_not_embedded.push_back(k);
      continue;
    }
    ++report.segments_embedded;
    // Where each inner vertex goes along the segment: its parameter along the projected segment,
    // or by arc length along a boundary arc or a shortest path.
    const Point_3 pa = s.to_point(A);
    const Vector_3 d = s.to_point(B) - pa;
    // (A path's projections onto the segment are used when they advance strictly inside it.)
    std::vector<double> along{0}, arc_length{0};
    for (std::size_t i = 1; i < chain.size(); ++i) {
      along.push_back(i + 1 < chain.size() ? ((s.to_point(chain[i]) - pa) * d) / d.squared_length() : 1.0);
      arc_length.push_back(arc_length.back() + std::sqrt(CGAL::squared_distance(s.to_point(chain[i - 1]), s.to_point(chain[i]))));
    }
    for (double& t : arc_length) t /= arc_length.back();
    const bool advancing = std::is_sorted(along.begin(), along.end(), std::less_equal<double>());
    // A fifth of each parameter is even spacing: two inner vertices that project onto nearly the
    // same point of the segment would make a needle that no held vertex lets smoothing undo.
    const double m = static_cast<double>(chain.size() - 1);
    for (std::size_t i = 1; i + 1 < chain.size(); ++i) {
      const std::size_t c = get(s.index, chain[i]);
      const double t = 0.8 * (arc[k].empty() || advancing ? along[i] : arc_length[i]) + 0.2 * (static_cast<double>(i) / m);
      constrained[c] = true;
      goal[c] = network.point(a) + t * (network.point(b) - network.point(a));
    }
  }
  const Vertex_adjacency adjacency = s.adjacency();
  std::vector<Vector_3> given(n, Vector_3(0, 0, 0));
  for (std::size_t i = 0; i < n; ++i)
    if (constrained[i]) given[i] = goal[i] - before[i];
  const std::vector<Vector_3> d = interpolate_displacements(adjacency, constrained, given, 2, &report.displacement);
  std::vector<Point_3> after = before;
  report.fine_pairs = static_cast<std::size_t>(std::count(constrained.begin(), constrained.end(), true));

  // 4. Untangling: move the free vertices around faces that turned over or fold (4a, 4b below).
  internal::report_progress(progress, "deform", "fine: relaxing where faces turned over", 3, 4);
  // Bad faces: those turned over against step 2's surface, and those beside an edge that folds
  // now and did not fold there. "Turned over" is judged against the coarse surface's vertex
  // normals (the sign of the face's orientation with the point a + N above its corner a, N the
  // sum of its corners' normals, an exact predicate), not in the face's own plane on step 2's
  // surface, which may stand on edge: a flip test there would call the repair of such a face a
  // flip.
  std::vector<bool> folded_before;
  s.folded_faces(before, &folded_before);
  std::size_t degenerate = 0;
  // Faces standing steeply on the reference (more than about 70 degrees from it) are relaxed as
  // well, though they count as neither flips nor folds: left alone, such a face (a sliver stage 2
  // leaves where a curve runs through a template vertex) ends up on either side of vertical.
  std::size_t serious = 0;  // flips + folds of the last call
  auto bad_faces = [&] {
    std::vector<typename GT::face_descriptor> bad, steep;
    for (auto f : faces(tm)) {
      const auto c = s.corners(f);
      const Vector_3 N = reference_normal[c[0]] + reference_normal[c[1]] + reference_normal[c[2]];
      if (CGAL::orientation(after[c[0]], after[c[1]], after[c[2]], after[c[0]] + N) != CGAL::POSITIVE) {
        bad.push_back(f);
        continue;
      }
      const Vector_3 nf = CGAL::cross_product(after[c[1]] - after[c[0]], after[c[2]] - after[c[0]]);
      if (nf * N < 0.34 * std::sqrt(nf.squared_length() * N.squared_length())) steep.push_back(f);
    }
    report.remaining_flips = bad.size();
    const auto folded = s.folded_faces(after, nullptr, &folded_before);
    report.remaining_folds = folded.size();
    serious = bad.size() + folded.size();
    bad.insert(bad.end(), folded.begin(), folded.end());
    bad.insert(bad.end(), steep.begin(), steep.end());
    return bad;
  };
  std::vector<typename GT::face_descriptor> flipped;
  // The free vertices of the bad faces and those up to `rings` edges away from them.
  auto rings_around = [&](const std::vector<typename GT::face_descriptor>& bad, std::size_t rings) {
    std::vector<bool> in(n, false);
    std::vector<std::size_t> ring;
    for (auto f : bad)
      for (std::size_t c : s.corners(f))
        if (!constrained[c] && !in[c]) in[c] = true, ring.push_back(c);
    for (std::size_t grow = 0; grow < rings; ++grow) {
      std::vector<std::size_t> next_ring;
      for (std::size_t i : ring)
        for (std::size_t k = adjacency.offsets[i]; k < adjacency.offsets[i + 1]; ++k) {
          const std::size_t j = adjacency.neighbours[k];
          if (!constrained[j] && !in[j]) in[j] = true, next_ring.push_back(j);
        }
      ring.swap(next_ring);
    }
    return in;
  };
  // 4a. A foldover-free energy (untangle_faces) on the free vertices within a few rings of the bad
  // faces, the rings growing while faces stay bad; each face judged in the plane of the reference
  // normal it is judged against here, each vertex moving in the plane of its own. The border
  // stays where it is. A result is kept only when it leaves fewer bad faces.
  auto untangle_around_bad = [&] {
    std::vector<std::array<std::size_t, 3>> corners;
    std::vector<Vector_3> face_normal;
    for (auto f : faces(tm)) {
      const auto c = s.corners(f);
      corners.push_back(c);
      face_normal.push_back(reference_normal[c[0]] + reference_normal[c[1]] + reference_normal[c[2]]);
    }
    for (std::size_t rings : {2, 6}) {
      std::vector<bool> free = rings_around(flipped, rings);
      for (std::size_t i = 0; i < n; ++i)
        if (free[i] && is_border(s.vertex[i], tm)) free[i] = false;
      Untangle_report untangled;
      std::vector<Point_3> trial = untangle_faces(after, corners, face_normal, free, reference_normal, 1.0, &untangled);
      report.untangled_vertices += untangled.free_vertices;
      const std::pair<std::size_t, std::size_t> was{serious, flipped.size()};
      std::swap(after, trial);
      auto now = bad_faces();
      if (std::make_pair(serious, now.size()) < was) {
        flipped = std::move(now);
      } else {
        std::swap(after, trial);
        flipped = bad_faces();
      }
      ++report.untangle_rounds;
      if (flipped.empty()) break;
    }
  };
  // When the whole motion leaves bad faces, it is made again in four equal parts, untangling
  // after each: a tangle is repaired while it is small, before the rest of the motion makes it
  // large (on the battery's ico2562-superellipsoid-latlong-dense10: exit 3 with one face turned
  // over in one step, clean in four).
  for (std::size_t i = 0; i < n; ++i) after[i] = constrained[i] ? goal[i] : before[i] + d[i];
  flipped = bad_faces();
  report.flips_found = flipped.size();
  if (!flipped.empty()) {
    constexpr std::size_t steps = 4;
    after = before;
    for (std::size_t step = 1; step <= steps; ++step) {
      const double t = static_cast<double>(step) / static_cast<double>(steps);
      for (std::size_t i = 0; i < n; ++i)
        after[i] = constrained[i] ? (step == steps ? goal[i] : before[i] + t * given[i])
                                  : after[i] + d[i] / static_cast<double>(steps);
      flipped = bad_faces();
      if (!flipped.empty()) untangle_around_bad();
    }
  }
  report.flip_rounds = 1;
  // 4b. Relaxation pulls vertices towards their neighbours' mean, which also shrinks what it
  // relaxes: rings grow only a little, and the best state seen is kept.
  std::vector<Point_3> best = after;
  std::pair<std::size_t, std::size_t> best_bad{serious, flipped.size()};
  constexpr std::size_t max_rings = 3;
  for (std::size_t round = 0; !flipped.empty() && round < max_rounds; ++round) {
    const std::vector<bool> relax = rings_around(flipped, std::min(round + 1, max_rings));
    std::vector<std::size_t> moving;
    for (std::size_t i = 0; i < n; ++i)
      if (relax[i]) moving.push_back(i);
    report.untangled_vertices += moving.size();
    for (int sweep = 0; sweep < 30; ++sweep)
      for (std::size_t i : moving) {
        double x = 0, y = 0, z = 0;
        const double deg = static_cast<double>(adjacency.offsets[i + 1] - adjacency.offsets[i]);
        for (std::size_t k = adjacency.offsets[i]; k < adjacency.offsets[i + 1]; ++k) {
          const Point_3& q = after[adjacency.neighbours[k]];
          x += q.x(), y += q.y(), z += q.z();
        }
        after[i] = Point_3(x / deg, y / deg, z / deg);
      }
    flipped = bad_faces();
    ++report.untangle_rounds;
    report.flip_rounds = round + 2;
    report.flips_found += flipped.size();
    if (std::make_pair(serious, flipped.size()) < best_bad) best = after, best_bad = {serious, flipped.size()};
  }
  if (std::make_pair(serious, flipped.size()) > best_bad) {
    after = std::move(best);
    flipped = bad_faces();
  }
  // A bad face all of whose corners are held (chain vertices of two curves and the network
  // vertex between them, say) cannot be relaxed; flipping one of its edges that is not a curve
  // edge can repair it when both new faces are good (the face and vertex counts are kept).
  auto good = [&](std::size_t a, std::size_t b, std::size_t c) {
    const Vector_3 N = reference_normal[a] + reference_normal[b] + reference_normal[c];
    return CGAL::orientation(after[a], after[b], after[c], after[a] + N) == CGAL::POSITIVE;
  };
  auto folds_with_neighbours = [&](typename GT::halfedge_descriptor h) {
    const auto c = s.corners(face(h, tm));
    const Triangle_points t{after[c[0]], after[c[1]], after[c[2]]};
    for (auto g : CGAL::halfedges_around_face(h, tm)) {
      const auto o = opposite(g, tm);
      if (is_border(o, tm)) continue;
      const auto other = s.corners(face(o, tm));
      if (orientation_in_plane(t, after[other[0]], after[other[1]], after[other[2]]) != CGAL::POSITIVE) return true;
    }
    return false;
  };
  // Flips the edge of h (u-v, faces u v x and v u y) to x-y when it is no curve edge nor on the
  // border, x-y is not an edge yet, both new faces are good and turn the same way and, with
  // `unfolded`, neither folds with a neighbour (else it is flipped back). True if flipped.
  auto flip_if_good = [&](typename GT::halfedge_descriptor h, bool unfolded) {
    const auto g = opposite(h, tm);
    if (get(curve, edge(h, tm)) || is_border(h, tm) || is_border(g, tm)) return false;
    const auto u = source(h, tm), v = target(h, tm), x = target(next(h, tm), tm), y = target(next(g, tm), tm);
    if (halfedge(x, y, tm).second) return false;
    const std::size_t iu = get(s.index, u), iv = get(s.index, v), ix = get(s.index, x), iy = get(s.index, y);
    if (!good(iu, iy, ix) || !good(iy, iv, ix)) return false;
    const Triangle_points first{after[iu], after[iy], after[ix]};
    if (orientation_in_plane(first, after[iy], after[iv], after[ix]) != CGAL::POSITIVE) return false;
    CGAL::Euler::flip_edge(h, tm);  // now x -> y
    if (unfolded && (folds_with_neighbours(h) || folds_with_neighbours(opposite(h, tm)))) {
      CGAL::Euler::flip_edge(h, tm);  // back to the diagonal u-v (two diagonals only)
      return false;
    }
    ++report.edges_flipped;
    return true;
  };
  // Each flip repairs a bad face, and each is followed by a scan of the whole mesh: at most four
  // flips per bad face, and 256 in all, keep this from running quadratically long (what is left
  // is reported in remaining_flips).
  const std::size_t max_edge_flips = std::min<std::size_t>(64 + 4 * flipped.size(), 256);
  for (int pass = 0; pass < 3 && !flipped.empty(); ++pass) {
    bool changed = false;
    for (auto f : flipped) {
      const auto c = s.corners(f);
      if (!(constrained[c[0]] && constrained[c[1]] && constrained[c[2]]) || good(c[0], c[1], c[2])) continue;
      for (auto h : CGAL::halfedges_around_face(halfedge(f, tm), tm))
        if (flip_if_good(h, false)) {
          changed = true;
          break;
        }
      if (changed) break;  // faces changed: find the bad ones again
    }
    if (!changed) break;
    flipped = bad_faces();
    pass = -1;  // keep going while flips repair something
    if (report.edges_flipped >= max_edge_flips) break;
  }
  // A fold left between two good faces is often the diagonal of their quadrilateral taken the
  // wrong way (across a row of nearly collinear chain vertices): flip that edge when it is not a
  // curve edge and both new faces are good and fold with none of their neighbours.
  for (std::size_t pass = 0; pass < 4 && report.remaining_folds > 0; ++pass) {
    std::vector<bool> folded_now;
    s.folded_faces(after, &folded_now, &folded_before);
    // The folded edge itself, or, for a curve edge, the other edges of a face beside it whose
    // corners are all held (three chain vertices where a chain turns round a triangle).
    std::vector<typename GT::edge_descriptor> candidates;
    std::size_t k = 0;
    for (auto e : edges(tm)) {
      const std::size_t ek = k++;
      if (ek >= folded_now.size() || !folded_now[ek]) continue;
      if (!get(curve, e)) {
        candidates.push_back(e);
        continue;
      }
      for (auto h : {halfedge(e, tm), opposite(halfedge(e, tm), tm)}) {
        if (is_border(h, tm)) continue;
        const auto c = s.corners(face(h, tm));
        if (!(constrained[c[0]] && constrained[c[1]] && constrained[c[2]])) continue;
        for (auto g : {next(h, tm), prev(h, tm)})
          if (!get(curve, edge(g, tm))) candidates.push_back(edge(g, tm));
      }
    }
    bool changed = false;
    for (auto e : candidates) changed = flip_if_good(halfedge(e, tm), true) || changed;
    flipped = bad_faces();
    if (!changed) break;
  }
  // Slivers: a face with an angle under 5 degrees (a curve vertex placed next to an edge) is
  // mended by flipping the edge that gives the pair of faces beside it a larger smallest angle, as
  // long as the flip is good (flip_if_good) — smoothing moves no held vertex and cannot. At most
  // one flip per edge and pass, 3 passes.
  auto smallest_angle = [&](typename GT::halfedge_descriptor h) {
    const auto c = s.corners(face(h, tm));
    return internal::smallest_angle(after[c[0]], after[c[1]], after[c[2]]);
  };
  const double sliver = 5 * CGAL_PI / 180;
  for (int pass = 0; pass < 3; ++pass) {
    bool changed = false;
    std::vector<typename GT::edge_descriptor> all(edges(tm).first, edges(tm).second);
    for (auto e : all) {
      const auto h = halfedge(e, tm), g = opposite(h, tm);
      if (is_border(h, tm) || is_border(g, tm) || get(curve, e)) continue;
      const double before_flip = std::min(smallest_angle(h), smallest_angle(g));
      if (!(before_flip < sliver) || !flip_if_good(h, true)) continue;
      if (std::min(smallest_angle(h), smallest_angle(opposite(h, tm))) > before_flip) {
        changed = true;
        continue;
      }
      CGAL::Euler::flip_edge(h, tm);  // no better: back
      --report.edges_flipped;
    }
    if (!changed) break;
  }
  flipped = bad_faces();
  report.degenerate_faces_skipped = degenerate;
  s.set_positions(after);

  for (std::size_t v = 0; v < nv; ++v)
    if (s.to_point(s.vertex[mesh_of[v]]) != network.point(v))
      throw Numerical_error("deform: network vertex " + std::to_string(v) + " did not end at its point (mesh vertex " +
                            std::to_string(mesh_of[v]) + ", " + std::to_string(std::count(mesh_of.begin(), mesh_of.end(), mesh_of[v])) + " network vertices on it)");
  report.fine_done = true;
  report.mesh_vertex_of_network_vertex = mesh_of;
  report.fine_seconds = internal::seconds_since(t0);
  report.vertices = num_vertices(tm);
  report.faces = num_faces(tm);
  return report;
}
/// The largest template that deform_template's subdivision makes.
constexpr std::size_t max_subdivided_faces = 2000000;

/// Curves sampled far more densely than the (subdivided, coarsely placed) template's edges would
/// put rows of network vertices a fraction of an edge apart into its faces: needles that fold,
/// found only after a long run. Refused when the median segment is shorter than an eighth of the
/// mean edge (lengths in the curves' frame, after the coarse level).
template <typename TriangleMesh, typename VPM>
void refuse_oversampled_curves(const TriangleMesh& tm, const VPM& vpm, const Curve_network& network,
                               std::size_t subdivisions) {
  const double edge = mean_edge_length(tm, vpm);
  std::vector<double> lengths;
  for (const auto& sk : network.segments())
    lengths.push_back(std::sqrt(CGAL::squared_distance(network.point(sk[0]), network.point(sk[1]))));
  if (lengths.empty()) return;
  std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
  const double median = lengths[lengths.size() / 2];
  if (!(median > 0 && median * 8 < edge)) return;
  std::ostringstream os;
  os.precision(3);
  os << "the curves are sampled " << edge / median << " times more densely than the template's edges";
  if (subdivisions > 0) os << " after " << subdivisions << " midpoint subdivision" << (subdivisions > 1 ? "s" : "");
  os << " (median segment " << median << ", mean edge " << edge
     << "): every network vertex becomes a mesh vertex, and rows of them inside single faces fold; sample the "
        "curves more sparsely (a point or two per template edge is enough), or give a finer template";
  throw Algorithm_failure("deform", os.str());
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_DEFORM_IMPL_H
