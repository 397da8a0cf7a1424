// meshfit internal: stage 2's method (partition.h), as templates over any mesh; the library
// compiles it once for its own mesh (src/partition.cpp).
//
//
// Every network vertex is a mesh vertex (after stage 1). Each curve segment is made a chain of
// mesh edges:
//   1. a segment that is already an edge, or a chain of edges lying on it, is kept;
//   2. otherwise its projected path is walked (surface_walk.h: one cutting plane per segment,
//      through its ends and containing their mean normal N) and the crossed faces, the clear-out
//      region of §3.2, are re-triangulated with the segment as an edge, by edge flips: Sloan's
//      constrained-edge insertion (1993) in the view along N, where the region is a planar
//      triangulated polygon (checked), an edge being flipped only when both new triangles are
//      positively oriented there (exact); then Lawson flips inside the region, keeping the
//      segment, remove the needles that leaves. A flip replaces two triangles of a quadrilateral
//      by two, so the face and vertex counts never change, and the mesh is valid between flips,
//      so a failed insertion is undone exactly by flipping back. Every changed face must keep
//      the orientation of each original region face at its corners and fold with none of its
//      neighbours (exact, in their planes), else the insertion is undone. The thesis refills the
//      emptied region ear by ear, smallest angle first; flips give the same kind of result with
//      an exact check at every step.
//      When undone because a vertex lies so close to the segment that any triangle on the
//      segment would stand on edge, that vertex is moved onto the segment (if no face around it
//      folds) and the two halves are inserted on their own;
//   3. where the walk fails (concave parts, boundaries, a walk leaving the mesh) or the insertion
//      is refused, the fallback of §3.2 (fig. 3.6): a shortest edge path between the two vertices
//      (Dijkstra) whose inner vertices are moved onto the segment. A move that would flip or fold
//      a face is refused, and the segment is reported as not embedded, the mesh left as it was.
// Vertices the path runs through exactly (on the cutting plane) are moved onto the segment too.
// Moved vertices and the network's vertices are never moved again nor walked through. The curve
// edges are marked in `edge_is_constrained_map`; regions are the connected sets of faces between
// them (`face_patch_map`).
#ifndef MESHFIT_INTERNAL_PARTITION_IMPL_H
#define MESHFIT_INTERNAL_PARTITION_IMPL_H

#include <meshfit/correspondence.h>
#include <meshfit/predicates.h>
#include <meshfit/partition.h>
#include <meshfit/surface_walk.h>

#include <CGAL/Dynamic_property_map.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>
#include <boost/pending/disjoint_sets.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <deque>
#include <limits>
#include <map>
#include <queue>
#include <sstream>
#include <unordered_map>
#include <vector>

namespace meshfit {

namespace internal {

template <typename TriangleMesh, typename VPM, typename ECM>
class Partitioner {
  using GT = boost::graph_traits<TriangleMesh>;
  using vertex_descriptor = typename GT::vertex_descriptor;
  using halfedge_descriptor = typename GT::halfedge_descriptor;
  using edge_descriptor = typename GT::edge_descriptor;
  using face_descriptor = typename GT::face_descriptor;
  using Point = typename boost::property_traits<VPM>::value_type;

  // Everything an insertion changes, so that a failed insertion is undone exactly.
  // The faces of a clear-out region with their corners before re-triangulation, sorted by face.
  using Region = std::vector<std::pair<face_descriptor, std::array<vertex_descriptor, 3>>>;

  struct Journal {
    std::vector<halfedge_descriptor> flips;
    std::vector<std::pair<vertex_descriptor, Point_3>> moves;  // (vertex, position before)
    std::vector<edge_descriptor> marked;
    std::vector<vertex_descriptor> fixed;
    std::size_t faces_crossed = 0;
    struct Mark {
      std::size_t flips, moves, marked, fixed, faces_crossed;
    };
    Mark mark() const { return {flips.size(), moves.size(), marked.size(), fixed.size(), faces_crossed}; }
  };

 public:
  Partitioner(TriangleMesh& tm, VPM vpm, ECM ecm)
      : m_tm(tm), m_vpm(vpm), m_ecm(ecm), m_index(get(CGAL::dynamic_vertex_property_t<std::size_t>(), tm)) {
    for (auto v : vertices(tm)) {
      put(m_index, v, m_vertex.size());
      m_vertex.push_back(v);
    }
    m_fixed.assign(m_vertex.size(), 0);
  }

  std::size_t index(vertex_descriptor v) const { return get(m_index, v); }
  vertex_descriptor vertex(std::size_t i) const { return m_vertex[i]; }
  std::size_t number_of_vertices() const { return m_vertex.size(); }
  Point_3 point(vertex_descriptor v) const { return point_of<TriangleMesh>(m_vpm, v); }
  void fix(vertex_descriptor v) { m_fixed[index(v)] = 1; }
  bool is_fixed(vertex_descriptor v) const { return m_fixed[index(v)] != 0; }

  /// Marks the edge a–b, if there is one, as a curve edge.
  bool take_existing_edge(vertex_descriptor a, vertex_descriptor b) {
    const auto h = halfedge(a, b, m_tm);
    if (!h.second) return false;
    put(m_ecm, edge(h.first, m_tm), true);
    return true;
  }

  /// Walks the segment a–b and re-triangulates its clear-out region; on failure the mesh is as
  /// it was.
  bool insert_by_walk(vertex_descriptor a, vertex_descriptor b, Partition_report& report) {
    Journal j;
    if (!walk_and_insert(a, b, j, 0)) {
      undo(j, typename Journal::Mark{0, 0, 0, 0, 0});
      return false;
    }
    report.faces_crossed += j.faces_crossed;
    report.edge_flips += j.flips.size();
    report.vertices_moved += j.moves.size();
    return true;
  }

  /// The fallback (thesis fig. 3.6): a shortest edge path from a to b through vertices that may
  /// move, its inner vertices moved onto the segment. On failure the mesh is as it was.
  bool insert_by_shortest_path(vertex_descriptor a, vertex_descriptor b, Partition_report& report) {
    const std::vector<vertex_descriptor> path = shortest_path(a, b);
    if (path.size() < 2) return false;
    const Point_3 pa = point(a), pb = point(b);
    const Vector_3 d = pb - pa;
    const std::vector<vertex_descriptor> inner(path.begin() + 1, path.end() - 1);
    // Where each inner vertex goes: first its projection on the segment (the least motion), when
    // the projections advance strictly inside it; else its arc-length position along the path.
    std::vector<double> projected{0.0}, arc{0.0};
    for (std::size_t i = 1; i < path.size(); ++i) {
      projected.push_back(((point(path[i]) - pa) * d) / d.squared_length());
      arc.push_back(arc.back() + std::sqrt(CGAL::squared_distance(point(path[i - 1]), point(path[i]))));
    }
    projected.back() = 1;
    for (double& t : arc) t /= arc.back();
    for (const std::vector<double>* t : {&projected, &arc}) {
      if (!std::is_sorted(t->begin(), t->end(), std::less_equal<double>())) continue;
      std::vector<Point_3> targets;
      for (std::size_t i = 1; i + 1 < path.size(); ++i) targets.push_back(pa + (*t)[i] * d);
      Journal j;
      if (!move_without_folding(inner, targets, j)) {
        undo(j, typename Journal::Mark{0, 0, 0, 0, 0});
        continue;
      }
      mark_chain(path, j);
      report.vertices_moved += inner.size();
      return true;
    }
    return false;
  }

  /// Numbers the connected sets of faces between curve edges, in the order of their first face;
  /// returns how many. (Union-find over the edges in storage order: a flood fill jumps about the
  /// face arrays and was the slowest part of partitioning a 1e6-face mesh.)
  template <typename FacePatchMap>
  std::size_t label_regions(FacePatchMap fpm) {
    auto index_of = get(CGAL::dynamic_face_property_t<std::size_t>(), m_tm);
    std::size_t n = 0;
    for (auto f : faces(m_tm)) put(index_of, f, n++);
    boost::disjoint_sets_with_storage<> sets(n);
    auto root = [&sets](std::size_t i) { return sets.find_set(i); };
    for (auto e : edges(m_tm)) {
      const halfedge_descriptor h = halfedge(e, m_tm), g = opposite(h, m_tm);
      if (is_border(h, m_tm) || is_border(g, m_tm) || get(m_ecm, e)) continue;
      sets.union_set(get(index_of, face(h, m_tm)), get(index_of, face(g, m_tm)));
    }
    // Labels are given in the order of each set's first face.
    std::vector<std::size_t> label(n, static_cast<std::size_t>(-1));
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t r = root(i);
      if (label[r] == static_cast<std::size_t>(-1)) label[r] = count++;
      label[i] = label[r];
    }
    if constexpr (!std::is_same_v<FacePatchMap, CGAL::internal_np::Param_not_found>) {
      std::size_t i = 0;
      for (auto f : faces(m_tm))
        put(fpm, f, static_cast<typename boost::property_traits<FacePatchMap>::value_type>(label[i++]));
    }
    return count;
  }

 private:
  // A segment's walk and insertion, recording every change in `j`. When the region cannot be
  // re-triangulated because a vertex lies so close to the segment that any triangle on the
  // segment standing on it would stand on edge, that vertex (the region's nearest to the
  // segment) is moved onto the segment and the two halves are inserted on their own (at most
  // `max_depth` times over).
  bool walk_and_insert(vertex_descriptor a, vertex_descriptor b, Journal& j, int depth) {
    constexpr int max_depth = 3;
    auto edge_blocked = [this](edge_descriptor e) { return bool(get(m_ecm, e)); };
    auto vertex_blocked = [this](vertex_descriptor v) { return is_fixed(v); };
    bool ok = false;
    const Cutting_plane plane = cutting_plane(m_tm, m_vpm, a, b, ok);
    if (!ok) return false;
    Segment_walker<TriangleMesh, VPM, decltype(edge_blocked), decltype(vertex_blocked)> walker(
        m_tm, m_vpm, edge_blocked, vertex_blocked);
    const Surface_path<TriangleMesh> path = walker.walk(a, b, plane);
    if (path.status != Walk_status::reached) return false;

    const typename Journal::Mark start = j.mark();
    for (std::size_t i = 0; ok && i + 1 < path.waypoints.size(); ++i)
      ok = flip_out_crossings(path.waypoints[i], path.waypoints[i + 1], path.crossings[i], plane, j) &&
           halfedge(path.waypoints[i], path.waypoints[i + 1], m_tm).second;
    if (ok) {
      // Vertices the path ran through lie on the cutting plane, strictly between a and b: they
      // go to their projections on the segment.
      const std::vector<vertex_descriptor> inner(path.waypoints.begin() + 1, path.waypoints.end() - 1);
      std::vector<Point_3> targets;
      for (vertex_descriptor v : inner) targets.push_back(projection(plane, point(v)));
      ok = move_without_folding(inner, targets, j);
    }
    if (ok) {
      mark_chain(path.waypoints, j);
      j.faces_crossed += path.faces_crossed();
      return true;
    }
    undo(j, start);
    if (depth >= max_depth) return false;

    vertex_descriptor split = GT::null_vertex();
    double nearest = std::numeric_limits<double>::infinity();
    const Segment_3 segment(plane.a, plane.b);
    for (const auto& crossings : path.crossings)
      for (halfedge_descriptor h : crossings)
        for (vertex_descriptor v : {source(h, m_tm), target(h, m_tm)}) {
          const Point_3 p = point(v);
          const double dist = CGAL::squared_distance(p, segment);
          if (dist < nearest && !is_fixed(v) && plane.strictly_between(p)) {
            nearest = dist;
            split = v;
          }
        }
    if (split == GT::null_vertex()) return false;
    if (move_without_folding({split}, {projection(plane, point(split))}, j) &&
        walk_and_insert(a, split, j, depth + 1) && walk_and_insert(split, b, j, depth + 1))
      return true;
    undo(j, start);
    return false;
  }

  static Point_3 projection(const Cutting_plane& plane, const Point_3& p) {
    const Vector_3 d = plane.b - plane.a;
    return plane.a + (((p - plane.a) * d) / d.squared_length()) * d;
  }

  void undo(Journal& j, const typename Journal::Mark& m) {
    while (j.fixed.size() > m.fixed) {
      m_fixed[index(j.fixed.back())] = 0;
      j.fixed.pop_back();
    }
    while (j.marked.size() > m.marked) {
      put(m_ecm, j.marked.back(), false);
      j.marked.pop_back();
    }
    while (j.moves.size() > m.moves) {
      const Point_3& p = j.moves.back().second;
      put(m_vpm, j.moves.back().first, Point(p.x(), p.y(), p.z()));
      j.moves.pop_back();
    }
    // Flipping an edge of a quadrilateral twice gives back the first diagonal.
    while (j.flips.size() > m.flips) {
      CGAL::Euler::flip_edge(j.flips.back(), m_tm);
      j.flips.pop_back();
    }
    j.faces_crossed = m.faces_crossed;
  }

  // Removes the crossings of the piece p–q of a path by flips (see the top of this file).
  bool flip_out_crossings(vertex_descriptor p, vertex_descriptor q, const std::vector<halfedge_descriptor>& crossed,
                          const Cutting_plane& plane, Journal& j) {
    // The clear-out region's faces as they were: flips reuse the two face descriptors of each
    // quadrilateral, so the region keeps these descriptors throughout.
    // (Buffers kept from call to call: partitioning calls this once per segment.)
    Region& before = m_region;
    before.clear();
    for (halfedge_descriptor h : crossed)
      for (halfedge_descriptor g : {h, opposite(h, m_tm)}) before.emplace_back(face(g, m_tm), corners(face(g, m_tm)));
    std::sort(before.begin(), before.end());
    before.erase(std::unique(before.begin(), before.end()), before.end());
    // Seen along N (the view of the cutting plane) the region must be a flat triangulated
    // polygon: then flipping is the planar algorithm, which always finds an edge to flip.
    for (const auto& entry : before) {
      const auto& c = entry.second;
      if (plane.view(point(c[0]), point(c[1]), point(c[2])) != CGAL::POSITIVE) return false;
    }
    const std::size_t first_flip = j.flips.size();
    if (!flip_until_uncrossed(crossed, plane, j)) return false;
    improve_angles(before, p, q, plane, first_flip, j);
    // Each flip is valid in the view along N; in 3D a triangle on a long segment can still lean
    // away from the surface it covers. Every changed face must turn as each original face of the
    // region at each of its corners did (exact, in those faces' planes).
    auto& faces_at = m_faces_at;  // (corner, index in `before`)
    faces_at.clear();
    for (std::size_t i = 0; i < before.size(); ++i)
      for (vertex_descriptor v : before[i].second) faces_at.emplace_back(v, i);
    std::sort(faces_at.begin(), faces_at.end());
    auto& planes = m_planes;
    auto& old_plane = m_old_planes;
    old_plane.clear();
    for (const auto& entry : before) {
      const auto& o = entry.second;
      old_plane.emplace_back(Triangle_points{point(o[0]), point(o[1]), point(o[2])});
    }
    for (const auto& [f, old_corners] : before) {
      const std::array<vertex_descriptor, 3> c = corners(f);
      if (std::is_permutation(c.begin(), c.end(), old_corners.begin())) continue;
      planes.clear();
      for (vertex_descriptor v : c)
        for (auto it = std::lower_bound(faces_at.begin(), faces_at.end(), std::make_pair(v, std::size_t(0)));
             it != faces_at.end() && it->first == v; ++it)
          planes.push_back(it->second);
      std::sort(planes.begin(), planes.end());
      planes.erase(std::unique(planes.begin(), planes.end()), planes.end());
      const Point_3 p0 = point(c[0]), p1 = point(c[1]), p2 = point(c[2]);
      for (std::size_t i : planes)
        if (old_plane[i](p0, p1, p2) != CGAL::POSITIVE) return false;
      if (folds_with_neighbours(f)) return false;
    }
    return true;
  }

  // The face makes a fold with a face across one of its edges: the two turn more than 90 degrees
  // apart (exact: the neighbour is not positively oriented in the face's plane). A vertex very
  // close to a segment leaves a needle standing on edge; this catches it, and the caller then
  // moves that vertex onto the segment instead (walk_and_insert).
  bool folds_with_neighbours(face_descriptor f) const {
    const halfedge_descriptor h0 = halfedge(f, m_tm);
    const Plane_orientation plane(
        Triangle_points{point(source(h0, m_tm)), point(target(h0, m_tm)), point(target(next(h0, m_tm), m_tm))});
    for (auto h : CGAL::halfedges_around_face(h0, m_tm)) {
      const halfedge_descriptor g = opposite(h, m_tm);
      if (is_border(g, m_tm)) continue;
      if (plane(point(source(g, m_tm)), point(target(g, m_tm)), point(target(next(g, m_tm), m_tm))) != CGAL::POSITIVE)
        return true;
    }
    return false;
  }

  std::array<vertex_descriptor, 3> corners(face_descriptor f) const {
    const halfedge_descriptor h = halfedge(f, m_tm);
    return {source(h, m_tm), target(h, m_tm), target(next(h, m_tm), m_tm)};
  }

  // Sloan's insertion: flip crossed edges whose quadrilateral is strictly convex in the view,
  // putting back those still crossed, until none is.
  bool flip_until_uncrossed(const std::vector<halfedge_descriptor>& crossed, const Cutting_plane& plane, Journal& j) {
    std::deque<halfedge_descriptor>& queue = m_queue;
    queue.assign(crossed.begin(), crossed.end());
    const std::size_t max_flips = 16 * (crossed.size() + 1) * (crossed.size() + 1);
    std::size_t stalled = 0, flips = 0;
    while (!queue.empty()) {
      const halfedge_descriptor h = queue.front();
      queue.pop_front();
      if (!flippable(h, plane)) {
        queue.push_back(h);
        if (++stalled > queue.size()) return false;
        continue;
      }
      if (++flips > max_flips) return false;
      CGAL::Euler::flip_edge(h, m_tm);
      j.flips.push_back(h);
      stalled = 0;
      const CGAL::Sign s = plane.side(point(source(h, m_tm))), t = plane.side(point(target(h, m_tm)));
      if (s != CGAL::ZERO && t != CGAL::ZERO && s != t) queue.push_back(h);
    }
    return true;
  }

  // Once the segment is an edge, the flips that removed the crossings may have left needles.
  // Lawson's flips, restricted to the region and keeping the segment: an inner edge is flipped
  // when the two angles facing it sum to more than pi (it is not locally Delaunay) and the flip
  // is valid in the view along N (exact). The angle sums only rank triangulations that are all
  // valid; they are measured in 3D in floating point. Bounded, since in 3D the criterion need
  // not decrease.
  void improve_angles(const Region& region, vertex_descriptor p, vertex_descriptor q, const Cutting_plane& plane,
                      std::size_t first_flip, Journal& j) {
    auto in_region = [&](halfedge_descriptor h) {
      if (is_border(h, m_tm)) return false;
      const face_descriptor f = face(h, m_tm);
      const auto it = std::lower_bound(region.begin(), region.end(), f,
                                       [](const auto& entry, face_descriptor g) { return entry.first < g; });
      return it != region.end() && it->first == f;
    };
    // The angle facing h, as the two vectors from its apex.
    auto facing = [&](halfedge_descriptor h) {
      const Point_3 x = point(target(next(h, m_tm), m_tm));
      return std::make_pair(point(source(h, m_tm)) - x, point(target(h, m_tm)) - x);
    };
    // α + β > π exactly when sin(α + β) = sin α cos β + cos α sin β < 0, impossible when both
    // cosines are >= 0 (the common case, decided without square roots).
    auto not_delaunay = [&](halfedge_descriptor h, halfedge_descriptor g) {
      const auto [a1, b1] = facing(h);
      const auto [a2, b2] = facing(g);
      const double cos_a = a1 * b1, cos_b = a2 * b2;
      if (cos_a >= 0 && cos_b >= 0) return false;
      const double sin_a = std::sqrt(CGAL::cross_product(a1, b1).squared_length()),
                   sin_b = std::sqrt(CGAL::cross_product(a2, b2).squared_length());
      return sin_a * cos_b + cos_a * sin_b < -1e-12 * (sin_a + std::abs(cos_a)) * (sin_b + std::abs(cos_b));
    };
    std::deque<halfedge_descriptor>& queue = m_queue;
    queue.clear();
    // The edges the uncrossing flips made (the original edges were the input's choice).
    for (std::size_t k = first_flip; k < j.flips.size(); ++k) queue.push_back(j.flips[k]);
    const std::size_t max_flips = 8 * region.size() * region.size() + 16;
    for (std::size_t flips = 0; !queue.empty() && flips < max_flips;) {
      const halfedge_descriptor h = queue.front();
      queue.pop_front();
      const halfedge_descriptor g = opposite(h, m_tm);
      if (!in_region(h) || !in_region(g)) continue;
      const vertex_descriptor u = source(h, m_tm), w = target(h, m_tm);
      if ((u == p && w == q) || (u == q && w == p)) continue;
      if (!not_delaunay(h, g) || !flippable(h, plane)) continue;
      CGAL::Euler::flip_edge(h, m_tm);
      j.flips.push_back(h);
      ++flips;
      for (auto k : {next(h, m_tm), prev(h, m_tm), next(g, m_tm), prev(g, m_tm)}) queue.push_back(k);
    }
  }

  // h: u -> w in face (u, w, x); opposite in face (w, u, y). The flip makes (u, y, x) and
  // (y, w, x): allowed when both turn positively in the view along N (the quadrilateral is
  // strictly convex there).
  bool flippable(halfedge_descriptor h, const Cutting_plane& plane) const {
    const halfedge_descriptor g = opposite(h, m_tm);
    if (is_border(h, m_tm) || is_border(g, m_tm) || get(m_ecm, edge(h, m_tm))) return false;
    const vertex_descriptor u = source(h, m_tm), w = target(h, m_tm);
    const vertex_descriptor x = target(next(h, m_tm), m_tm), y = target(next(g, m_tm), m_tm);
    if (x == y || halfedge(x, y, m_tm).second) return false;
    const Point_3 pu = point(u), pw = point(w), px = point(x), py = point(y);
    return plane.view(pu, py, px) == CGAL::POSITIVE && plane.view(py, pw, px) == CGAL::POSITIVE;
  }

  // Moves vs[k] to targets[k], one after the other (recorded in `j`), and fails at the first
  // move that would flip or degenerate a face around the moved vertex: after the move, each
  // face around the vertex must turn as every face around it did before, in each of those
  // faces' planes (exact; comparing only with its own old plane, the flip counter's test, lets
  // a long move stand a face on edge against its neighbours), and fold with none of its
  // neighbours.
  bool move_without_folding(const std::vector<vertex_descriptor>& vs, const std::vector<Point_3>& targets, Journal& j) {
    for (std::size_t k = 0; k < vs.size(); ++k) {
      const vertex_descriptor v = vs[k];
      const Point_3 from = point(v), to = targets[k];
      if (!std::isfinite(to.x()) || !std::isfinite(to.y()) || !std::isfinite(to.z())) return false;
      std::vector<Triangle_points> star;  // the faces (p, v, q) around v, before
      for (auto h : CGAL::halfedges_around_target(halfedge(v, m_tm), m_tm))
        if (!is_border(h, m_tm)) star.push_back({point(source(h, m_tm)), from, point(target(next(h, m_tm), m_tm))});
      for (const Triangle_points& moved : star)
        for (const Triangle_points& old : star)
          if (orientation_in_plane(old, moved[0], to, moved[2]) != CGAL::POSITIVE) return false;
      j.moves.emplace_back(v, from);
      put(m_vpm, v, Point(to.x(), to.y(), to.z()));
      for (auto h : CGAL::halfedges_around_target(halfedge(v, m_tm), m_tm))
        if (!is_border(h, m_tm) && folds_with_neighbours(face(h, m_tm))) return false;  // undone by the caller
    }
    return true;
  }

  void mark_chain(const std::vector<vertex_descriptor>& chain, Journal& j) {
    for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
      const edge_descriptor e = edge(halfedge(chain[i], chain[i + 1], m_tm).first, m_tm);
      if (get(m_ecm, e)) continue;
      put(m_ecm, e, true);
      j.marked.push_back(e);
    }
    for (vertex_descriptor v : chain) {
      if (is_fixed(v)) continue;
      fix(v);
      j.fixed.push_back(v);
    }
  }

  // Dijkstra from a to b over edges that are not curve edges, through vertices that are not
  // fixed; stops when b is settled. Only the vertices reached are touched. An edge costs its
  // length plus twice its far end's distance from the segment, so that among paths of about the
  // same length the one hugging the segment wins: its vertices then move least.
  std::vector<vertex_descriptor> shortest_path(vertex_descriptor a, vertex_descriptor b) {
    struct Label {
      double distance;
      std::size_t previous;
    };
    std::unordered_map<std::size_t, Label> label;
    using Item = std::pair<double, std::size_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    const std::size_t ia = index(a), ib = index(b), none = static_cast<std::size_t>(-1);
    const Segment_3 segment(point(a), point(b));
    label[ia] = {0.0, none};
    queue.push({0.0, ia});
    while (!queue.empty()) {
      const auto [d, i] = queue.top();
      queue.pop();
      if (d > label[i].distance) continue;
      if (i == ib) break;
      const vertex_descriptor v = m_vertex[i];
      const Point_3 pv = point(v);
      for (auto h : CGAL::halfedges_around_target(halfedge(v, m_tm), m_tm)) {
        const vertex_descriptor u = source(h, m_tm);
        if (get(m_ecm, edge(h, m_tm)) || (u != b && is_fixed(u))) continue;
        const Point_3 pu = point(u);
        const double nd = d + std::sqrt(CGAL::squared_distance(pv, pu)) + 2 * std::sqrt(CGAL::squared_distance(pu, segment));
        const std::size_t k = index(u);
        const auto it = label.find(k);
        if (it != label.end() && it->second.distance <= nd) continue;
        label[k] = {nd, i};
        queue.push({nd, k});
      }
    }
    std::vector<vertex_descriptor> path;
    if (!label.count(ib)) return path;
    for (std::size_t i = ib; i != none; i = label[i].previous) path.push_back(m_vertex[i]);
    std::reverse(path.begin(), path.end());
    return path;
  }

  TriangleMesh& m_tm;
  VPM m_vpm;
  ECM m_ecm;
  typename boost::property_map<TriangleMesh, CGAL::dynamic_vertex_property_t<std::size_t>>::type m_index;
  std::vector<vertex_descriptor> m_vertex;
  std::vector<char> m_fixed;
  // Buffers of flip_out_crossings.
  Region m_region;
  std::vector<std::pair<vertex_descriptor, std::size_t>> m_faces_at;
  std::vector<std::size_t> m_planes;
  std::vector<Plane_orientation> m_old_planes;
  std::deque<halfedge_descriptor> m_queue;
};

/// The mesh vertex of each network vertex: the nearest one, which must lie within the network's
/// merge tolerance (\throws Invalid_input naming the network vertex otherwise, or when two network
/// vertices have the same mesh vertex).
inline std::vector<std::size_t> match_network_vertices(const std::vector<Point_3>& mesh_points,
                                                       const Curve_network& network) {
  // Usually (after deform) every network vertex is exactly a mesh vertex: look the mesh's points
  // up by value first; the nearest-vertex search is needed only when one is not.
  {
    struct Hash {
      std::size_t operator()(const Point_3& p) const {
        const std::hash<double> h;
        return h(p.x()) ^ (h(p.y()) * 0x9e3779b97f4a7c15ULL) ^ (h(p.z()) * 0xc2b2ae3d27d4eb4fULL);
      }
    };
    std::unordered_map<Point_3, std::size_t, Hash> network_vertex;
    network_vertex.reserve(network.number_of_vertices());
    for (std::size_t v = 0; v < network.number_of_vertices(); ++v) network_vertex.emplace(network.point(v), v);
    std::vector<std::size_t> mesh_vertex(network.number_of_vertices(), Closest_point_assignment::unassigned);
    std::size_t found = 0;
    for (std::size_t i = 0; i < mesh_points.size(); ++i) {
      const auto it = network_vertex.find(mesh_points[i]);
      // The first of several mesh vertices at one position, as the nearest-vertex search would.
      if (it != network_vertex.end() && mesh_vertex[it->second] == Closest_point_assignment::unassigned) {
        mesh_vertex[it->second] = i;
        ++found;
      }
    }
    if (found == mesh_vertex.size()) return mesh_vertex;
  }
  const Closest_point_assignment a = closest_point_correspondences(mesh_points, network);
  for (std::size_t v = 0; v < network.number_of_vertices(); ++v) {
    std::ostringstream where;
    where.precision(17);
    where << "network vertex " << v << " (" << network.point(v) << ")";
    const std::size_t t = a.template_of[v];
    if (t == Closest_point_assignment::unassigned)
      throw Invalid_input(where.str() + " shares its nearest mesh vertex with another network vertex: it is not a "
                                        "vertex of the mesh (deform the template first)");
    const double d = std::sqrt(CGAL::squared_distance(network.point(v), mesh_points[t]));
    if (d > network.tolerance()) {
      where.precision(3);
      where << " is not a vertex of the mesh: the nearest mesh vertex, " << t << ", is " << d
            << " away, more than the merge tolerance " << network.tolerance() << " (deform the template first)";
      throw Invalid_input(where.str());
    }
  }
  return a.template_of;
}

}  // namespace internal

namespace internal {
/// The steps of partition_mesh_in_place, on a Partitioner of `tm` (its own copies of `vpm` and
/// `ecm`; the steps here write through the caller's), filling `report`.
template <typename TriangleMesh, typename VPM, typename ECM>
class Partition_run {
  using GT = boost::graph_traits<TriangleMesh>;
  using vertex_descriptor = typename GT::vertex_descriptor;

 public:
  Partition_run(TriangleMesh& tm, const VPM& vpm, ECM& ecm, const Curve_network& network, Partition_report& report)
      : m_tm(tm), m_vpm(vpm), m_ecm(ecm), m_network(network), m_report(report), m_partitioner(tm, vpm, ecm) {}

  /// The mesh vertex of each network vertex (match_network_vertices); no segment embedded yet.
  void match_vertices() {
    Partitioner<TriangleMesh, VPM, ECM>& p = m_partitioner;
    std::vector<Point_3> points;
    points.reserve(p.number_of_vertices());
    for (std::size_t i = 0; i < p.number_of_vertices(); ++i) points.push_back(p.point(p.vertex(i)));
    m_report.mesh_vertex_of_network_vertex = match_network_vertices(points, m_network);
    m_report.segments = m_network.segments().size();
    m_report.how.assign(m_network.segments().size(), Segment_embedding::not_embedded);
  }

  /// A segment that is already a chain of mesh edges lying on it (as stage 1's surface fine level
  /// leaves them, or an earlier partition) is kept as it is, its inner vertices fixed.
  void keep_edge_chains() {
    for (auto e : edges(m_tm)) put(m_ecm, e, false);
    const CGAL::Static_boolean_property_map<typename GT::edge_descriptor, true> every_edge;
    for (std::size_t s = 0; s < m_network.segments().size(); ++s) {
      const auto [a, b] = ends(s);
      const auto chain = segment_edge_chain(m_tm, m_vpm, every_edge, a, b, m_network.tolerance());
      if (chain.size() < 2) continue;
      m_report.how[s] = Segment_embedding::existing_edge;
      for (std::size_t k = 0; k + 1 < chain.size(); ++k) {
        put(m_ecm, edge(halfedge(chain[k], chain[k + 1], m_tm).first, m_tm), true);
        m_partitioner.fix(chain[k + 1]);
      }
    }
  }

  /// Fixes the network's vertices and those `vcm` constrains: no walk goes through them and no
  /// insertion moves them.
  template <typename VCM>
  void fix_vertices(const VCM& vcm) {
    for (std::size_t t : m_report.mesh_vertex_of_network_vertex) m_partitioner.fix(m_partitioner.vertex(t));
    for (auto v : vertices(m_tm))
      if (get(vcm, v)) m_partitioner.fix(v);
  }

  /// The segments not embedded yet that are an edge of the mesh become that edge.
  void take_existing_edges() {
    for_each_not_embedded([this](std::size_t s, vertex_descriptor a, vertex_descriptor b) {
      if (m_partitioner.take_existing_edge(a, b)) m_report.how[s] = Segment_embedding::existing_edge;
    });
  }

  /// The segments not embedded yet, inserted along their projected paths (an edge an earlier
  /// insertion made is taken as it is).
  void insert_by_walks() {
    for_each_not_embedded([this](std::size_t s, vertex_descriptor a, vertex_descriptor b) {
      if (m_partitioner.take_existing_edge(a, b)) {
        m_report.how[s] = Segment_embedding::existing_edge;
      } else if (m_partitioner.insert_by_walk(a, b, m_report)) {
        m_report.how[s] = Segment_embedding::walk;
      } else {
        ++m_report.walks_failed;
      }
    });
  }

  /// The segments not embedded yet, inserted by the fallback; those it fails on are reported as
  /// not embedded.
  void insert_by_fallback() {
    for_each_not_embedded([this](std::size_t s, vertex_descriptor a, vertex_descriptor b) {
      if (m_partitioner.take_existing_edge(a, b))
        m_report.how[s] = Segment_embedding::existing_edge;
      else if (m_partitioner.insert_by_shortest_path(a, b, m_report))
        m_report.how[s] = Segment_embedding::fallback;
      else
        m_report.not_embedded.push_back(s);
    });
  }

  /// The report's counts of segments by how they were embedded.
  void count_embeddings() {
    for (Segment_embedding h : m_report.how) {
      m_report.existing_edges += h == Segment_embedding::existing_edge;
      m_report.by_walk += h == Segment_embedding::walk;
      m_report.by_fallback += h == Segment_embedding::fallback;
    }
  }

  /// Partitioner::label_regions.
  template <typename FacePatchMap>
  std::size_t label_regions(FacePatchMap fpm) {
    return m_partitioner.label_regions(fpm);
  }

 private:
  // The mesh vertices of segment s's ends.
  std::pair<vertex_descriptor, vertex_descriptor> ends(std::size_t s) const {
    const auto& segment = m_network.segments()[s];
    return std::make_pair(m_partitioner.vertex(m_report.mesh_vertex_of_network_vertex[segment[0]]),
                          m_partitioner.vertex(m_report.mesh_vertex_of_network_vertex[segment[1]]));
  }

  // Calls `embed(s, a, b)`, a and b the ends of segment s, for each segment s not embedded yet.
  template <typename Embed>
  void for_each_not_embedded(const Embed& embed) {
    for (std::size_t s = 0; s < m_network.segments().size(); ++s) {
      if (m_report.how[s] != Segment_embedding::not_embedded) continue;
      const auto [a, b] = ends(s);
      embed(s, a, b);
    }
  }

  TriangleMesh& m_tm;
  const VPM& m_vpm;
  ECM& m_ecm;
  const Curve_network& m_network;
  Partition_report& m_report;
  Partitioner<TriangleMesh, VPM, ECM> m_partitioner;
};

/// partition_mesh on `tm` itself: the mesh changes as the work goes (a cancel leaves it partly
/// partitioned). For meshes the pipeline owns (fit's and deform's copies).
template <typename TriangleMesh, typename NamedParameters>
Partition_report partition_mesh_in_place(TriangleMesh& tm, const Curve_network& network, const NamedParameters& np) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  using GT = boost::graph_traits<TriangleMesh>;
  const auto t0 = std::chrono::steady_clock::now();
  const auto progress = get_parameter(np, internal_np::progress);
  auto vpm = vertex_point_map_of(tm, np);
  auto ecm = choose_parameter(get_parameter(np, CGAL::internal_np::edge_is_constrained),
                              get(CGAL::dynamic_edge_property_t<bool>(), tm));
  const auto vcm = choose_parameter(get_parameter(np, CGAL::internal_np::vertex_is_constrained),
                                    CGAL::Static_boolean_property_map<typename GT::vertex_descriptor, false>());
  if (!CGAL::is_triangle_mesh(tm)) throw Invalid_input("partition: the mesh is not a triangle mesh");
  if (network.number_of_segments() == 0) throw Invalid_input("partition: the curve network has no segment");

  report_progress(progress, "partition", "matching network vertices to mesh vertices", 0, 4);
  Partition_report report;
  Partition_run<TriangleMesh, decltype(vpm), decltype(ecm)> run(tm, vpm, ecm, network, report);
  run.match_vertices();
  run.keep_edge_chains();
  run.fix_vertices(vcm);
  // Existing edges first, so that no walk crosses or flips them away.
  run.take_existing_edges();
  report.matching_seconds = seconds_since(t0);
  report_progress(progress, "partition", "inserting segments along their projected paths", 1, 4);
  const auto t1 = std::chrono::steady_clock::now();
  run.insert_by_walks();
  report.walk_seconds = seconds_since(t1);
  report_progress(progress, "partition", "fallback: moving shortest edge paths onto the other segments", 2,
                            4);
  const auto t2 = std::chrono::steady_clock::now();
  run.insert_by_fallback();
  run.count_embeddings();
  report.fallback_seconds = seconds_since(t2);
  report_progress(progress, "partition", "labelling regions", 3, 4);
  const auto t3 = std::chrono::steady_clock::now();
  report.regions = run.label_regions(get_parameter(np, CGAL::internal_np::face_patch));
  report.region_seconds = seconds_since(t3);
  for (auto e : edges(tm)) report.curve_edges += get(ecm, e) ? 1 : 0;
  report.vertices = num_vertices(tm);
  report.faces = num_faces(tm);
  report.seconds = seconds_since(t0);
  return report;
}

}  // namespace internal

}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_PARTITION_IMPL_H
