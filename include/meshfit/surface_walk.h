// meshfit: the projected path of a curve segment on the mesh (thesis appendix A).
//
// The thesis walks from the segment's start vertex face by face along dir_p = n × (dir_c × n)
// (eq. A.1–A.2), re-aiming at the end vertex after each crossing. Re-aiming from a constructed
// crossing point makes every later branch a decision on rounded numbers. Here the walk follows
// one cutting plane instead: the plane through the segment's two end vertices a, b that contains
// the mean of their vertex normals N (so, on each face, the path runs in the direction of dir_p
// for the mean normal, and the plane is fixed once per segment). The plane is given by a, b and
// one auxiliary point e rounded once (see Cutting_plane); after that every branch is an exact
// predicate on these three points and the mesh's points:
//   - which side of the plane a vertex lies on (orientation_in_plane, flip.h), hence which edge
//     of a face the path leaves through, and whether it passes exactly through a vertex or runs
//     along an edge (a vertex on the plane);
//   - whether a vertex lies before a, between a and b, or past b along the segment
//     (CGAL::angle, the sign of a dot product of differences of input points).
// The walk ends at b, or fails (a Walk_status says why); it never visits a face twice, so it
// takes at most num_faces steps. Crossings are stored symbolically (the halfedge crossed); the
// crossing point is constructed only on request.
#ifndef MESHFIT_SURFACE_WALK_H
#define MESHFIT_SURFACE_WALK_H

#include <meshfit/flip.h>
#include <meshfit/internal/stage_support.h>
#include <meshfit/kernel.h>

#include <CGAL/Named_function_parameters.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>
#include <CGAL/boost/graph/named_params_helper.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

namespace meshfit {

/// How a walk ended.
enum class Walk_status {
  reached,             ///< the path reached the segment's end vertex
  boundary,            ///< the path left the mesh through a border edge
  constrained_edge,    ///< the path would cross an edge it must not cross (another curve)
  constrained_vertex,  ///< the path runs through a vertex it must not use (a network vertex, …)
  left_segment,        ///< the path went past the end or behind the start of the segment
  revisited,           ///< the path came back to a face or vertex it had passed (a loop)
  degenerate_plane,    ///< the segment is parallel to the surface normal: no cutting plane
  no_exit              ///< from a vertex on the path, no face continues it
};

/// A short phrase for messages: "reached", "left the mesh through its boundary", ….
inline const char* to_string(Walk_status s) {
  switch (s) {
    case Walk_status::reached: return "reached";
    case Walk_status::boundary: return "left the mesh through its boundary";
    case Walk_status::constrained_edge: return "would cross another curve";
    case Walk_status::constrained_vertex: return "runs through a constrained vertex";
    case Walk_status::left_segment: return "left the segment";
    case Walk_status::revisited: return "looped";
    case Walk_status::degenerate_plane: return "no cutting plane (segment along the normal)";
    case Walk_status::no_exit: return "found no way on";
  }
  return "?";
}

/// The plane a walk follows and the view in which its clear-out region is re-triangulated.
/// `e` is the auxiliary point: the triangle (a, b, e) has the normal N, the surface's mean normal
/// at a and b made orthogonal to the segment. Projected along N, the segment is a line and a
/// point's side of it is orientation_in_plane({a, b, e}, a, b, p): the same exact predicate
/// decides which edges the walk crosses and which edges the re-triangulation must remove, so
/// the two always agree. The cutting plane is the plane through a and b containing N.
struct Cutting_plane {
  Point_3 a;  ///< the segment's start
  Point_3 b;  ///< the segment's end
  Point_3 e;  ///< the auxiliary point (see above)
  Plane_orientation view;  ///< orientation in the view along N: in the plane of (a, b, e)
  /// Exact side of `p` (a and b themselves, which end most walks, without arithmetic).
  CGAL::Sign side(const Point_3& p) const { return p == a || p == b ? CGAL::ZERO : view(a, b, p); }
  /// Exact: p's projection on the line ab lies strictly between a and b.
  bool strictly_between(const Point_3& p) const {
    return CGAL::angle(b, a, p) == CGAL::ACUTE && CGAL::angle(a, b, p) == CGAL::ACUTE;
  }
  /// Exact: p's projection on the line ab lies before a (away from b).
  bool behind_a(const Point_3& p) const { return CGAL::angle(b, a, p) == CGAL::OBTUSE; }
  /// Exact: p's projection on the line ab lies past b.
  bool past_b(const Point_3& p) const { return CGAL::angle(a, b, p) == CGAL::OBTUSE; }
  /// Signed distance-like value of `p` (floating point; only to construct crossing points).
  double height(const Point_3& p) const {
    return CGAL::cross_product(b - a, e - a) * CGAL::cross_product(b - a, p - a);
  }
};

/// The projected path of a segment: the vertices it passes through (waypoints: its two end
/// vertices, plus any vertex lying exactly on the cutting plane between them) and, between
/// consecutive waypoints, the edges it crosses.
template <typename TriangleMesh>
struct Surface_path {
  /// The mesh's vertex type.
  using vertex_descriptor = typename boost::graph_traits<TriangleMesh>::vertex_descriptor;
  /// The mesh's halfedge type.
  using halfedge_descriptor = typename boost::graph_traits<TriangleMesh>::halfedge_descriptor;

  Walk_status status = Walk_status::no_exit;  ///< how the walk ended
  Cutting_plane plane;                        ///< the plane the walk followed
  std::vector<vertex_descriptor> waypoints;   ///< from the segment's start to its end (when reached)
  /// crossings[i]: the edges crossed between waypoints[i] and waypoints[i+1], in order, each as
  /// the halfedge of the face the path leaves.
  std::vector<std::vector<halfedge_descriptor>> crossings;

  /// The number of faces the path runs through (0 unless the end was reached).
  std::size_t faces_crossed() const {
    std::size_t n = 0;
    for (const auto& c : crossings) n += c.size() + 1;
    return status == Walk_status::reached ? n : 0;
  }
};

namespace internal {

/// Area-weighted normal of `v` (sum of its faces' cross products), floating point.
template <typename TriangleMesh, typename VPM>
Vector_3 area_normal(const TriangleMesh& tm, const VPM& vpm,
                     typename boost::graph_traits<TriangleMesh>::vertex_descriptor v) {
  Vector_3 n(0, 0, 0);
  for (auto h : CGAL::halfedges_around_target(halfedge(v, tm), tm)) {
    if (is_border(h, tm)) continue;
    const Point_3 p = point_of<TriangleMesh>(vpm, source(h, tm)), q = point_of<TriangleMesh>(vpm, v),
                  r = point_of<TriangleMesh>(vpm, target(next(h, tm), tm));
    n = n + CGAL::cross_product(q - p, r - p);
  }
  return n;
}

/// The cutting plane of segment (a, b): it contains the mean of the vertex normals at a and b
/// (their component along the segment removed). `ok` is false when that leaves nothing.
template <typename TriangleMesh, typename VPM>
Cutting_plane cutting_plane(const TriangleMesh& tm, const VPM& vpm,
                            typename boost::graph_traits<TriangleMesh>::vertex_descriptor a,
                            typename boost::graph_traits<TriangleMesh>::vertex_descriptor b, bool& ok) {
  Cutting_plane P;
  P.a = point_of<TriangleMesh>(vpm, a);
  P.b = point_of<TriangleMesh>(vpm, b);
  const Vector_3 d = P.b - P.a;
  Vector_3 na = area_normal(tm, vpm, a), nb = area_normal(tm, vpm, b);
  const double la = std::sqrt(na.squared_length()), lb = std::sqrt(nb.squared_length());
  const Vector_3 n = (la > 0 ? na / la : na) + (lb > 0 ? nb / lb : nb);
  // (b − a) × (e − a) = |d|² N⊥ for e − a = N × d.
  const Vector_3 side = CGAL::cross_product(n, d);
  const double ls = std::sqrt(side.squared_length()), ld = std::sqrt(d.squared_length());
  ok = ls > 0 && std::isfinite(ls) && ld > 0;
  P.e = ok ? P.a + side * (ld / ls) : P.a;
  ok = ok && !CGAL::collinear(P.a, P.b, P.e);
  P.view = Plane_orientation({P.a, P.b, P.e});
  return P;
}

/// A set for the elements a walk has passed: a short vector (most walks cross a few faces), then a
/// std::set when it grows.
template <typename T>
class Seen {
 public:
  /// Inserts `x`; false when it was there already.
  bool insert(const T& x) {
    if (m_large.empty()) {
      if (std::find(m_small.begin(), m_small.end(), x) != m_small.end()) return false;
      m_small.push_back(x);
      if (m_small.size() > 64) m_large.insert(m_small.begin(), m_small.end());
      return true;
    }
    return m_large.insert(x).second;
  }

 private:
  std::vector<T> m_small;
  std::set<T> m_large;
};

template <typename TriangleMesh, typename VPM, typename EdgeBlocked, typename VertexBlocked>
class Segment_walker {
  using GT = boost::graph_traits<TriangleMesh>;
  using vertex_descriptor = typename GT::vertex_descriptor;
  using halfedge_descriptor = typename GT::halfedge_descriptor;
  using face_descriptor = typename GT::face_descriptor;

 public:
  Segment_walker(const TriangleMesh& tm, const VPM& vpm, const EdgeBlocked& edge_blocked,
                 const VertexBlocked& vertex_blocked)
      : m_tm(tm), m_vpm(vpm), m_edge_blocked(edge_blocked), m_vertex_blocked(vertex_blocked) {}

  Surface_path<TriangleMesh> walk(vertex_descriptor a, vertex_descriptor b, const Cutting_plane& plane) const {
    Surface_path<TriangleMesh> best;
    best.plane = plane;
    m_a = a;
    m_b = b;
    m_plane = plane;
    // Usually two exits leave a: towards b and away from it. Each is a complete exact walk; the
    // order (most forward first, judged in floating point) only decides which is tried first.
    std::vector<Exit> first = exits(a);
    std::sort(first.begin(), first.end(), [](const Exit& x, const Exit& y) { return x.forward > y.forward; });
    bool any = false;
    for (const Exit& e : first) {
      Surface_path<TriangleMesh> path;
      path.plane = plane;
      path.status = walk_from(e, path);
      if (path.status == Walk_status::reached) return path;
      if (!any) best = path;
      any = true;
    }
    if (!any) best.status = Walk_status::no_exit;
    best.waypoints.clear();
    best.crossings.clear();
    return best;
  }

 private:
  // Leaving a vertex v: along the edge to a neighbour on the plane, or across the edge opposite
  // v of one of its faces, when that edge's ends lie on opposite sides.
  struct Exit {
    bool through_vertex = false;
    vertex_descriptor to{};           // through_vertex
    halfedge_descriptor crossed{};    // otherwise: halfedge of `face` opposite v
    face_descriptor face{};
    double forward = 0;               // cosine of the angle to b (floating point: order only)
  };

  Point_3 point(vertex_descriptor v) const { return point_of<TriangleMesh>(m_vpm, v); }

  double cosine_to_b(const Point_3& from, const Point_3& to) const {
    const Vector_3 u = to - from, w = m_plane.b - from;
    const double l = std::sqrt(u.squared_length() * w.squared_length());
    return l > 0 ? (u * w) / l : -1;
  }

  Point_3 crossing_point(halfedge_descriptor h) const {
    const Point_3 p = point(source(h, m_tm)), q = point(target(h, m_tm));
    const double hp = m_plane.height(p), hq = m_plane.height(q);
    const double t = hp / (hp - hq);
    return p + (std::isfinite(t) ? std::min(1.0, std::max(0.0, t)) : 0.5) * (q - p);
  }

  std::vector<Exit> exits(vertex_descriptor v) const {
    std::vector<Exit> out;
    const Point_3 pv = point(v);
    for (auto h : CGAL::halfedges_around_target(halfedge(v, m_tm), m_tm)) {  // h: u -> v
      const vertex_descriptor u = source(h, m_tm);
      const Point_3 pu = point(u);
      const CGAL::Sign su = m_plane.side(pu);
      if (su == CGAL::ZERO) {
        Exit e;
        e.through_vertex = true;
        e.to = u;
        e.forward = cosine_to_b(pv, pu);
        out.push_back(e);
      }
      if (is_border(h, m_tm)) continue;
      const vertex_descriptor w = target(next(h, m_tm), m_tm);
      const CGAL::Sign sw = m_plane.side(point(w));
      if (su != CGAL::ZERO && sw != CGAL::ZERO && su != sw) {
        Exit e;
        e.crossed = prev(h, m_tm);  // w -> u
        e.face = face(h, m_tm);
        e.forward = cosine_to_b(pv, crossing_point(e.crossed));
        out.push_back(e);
      }
    }
    return out;
  }

  Walk_status walk_from(Exit exit, Surface_path<TriangleMesh>& path) const {
    Seen<face_descriptor> visited;
    Seen<vertex_descriptor> passed;
    path.waypoints.assign(1, m_a);
    path.crossings.assign(1, {});
    passed.insert(m_a);
    const std::size_t max_steps = num_faces(m_tm) + num_vertices(m_tm) + 1;
    for (std::size_t step = 0; step < max_steps; ++step) {
      vertex_descriptor x;
      face_descriptor entered = GT::null_face();  // the face through which x was reached, if any
      vertex_descriptor from_vertex = GT::null_vertex();
      if (exit.through_vertex) {
        x = exit.to;
        from_vertex = path.waypoints.back();
      } else {
        // Cross edges face by face until a vertex on the plane is reached.
        halfedge_descriptor e = exit.crossed;
        if (!visited.insert(exit.face)) return Walk_status::revisited;
        for (;; ++step) {
          if (step >= max_steps) return Walk_status::revisited;
          const Point_3 pu = point(source(e, m_tm)), pw = point(target(e, m_tm));
          if ((m_plane.behind_a(pu) && m_plane.behind_a(pw)) || (m_plane.past_b(pu) && m_plane.past_b(pw)))
            return Walk_status::left_segment;
          if (m_edge_blocked(edge(e, m_tm))) return Walk_status::constrained_edge;
          const halfedge_descriptor g = opposite(e, m_tm);
          if (is_border(g, m_tm)) return Walk_status::boundary;
          const face_descriptor f = face(g, m_tm);
          if (!visited.insert(f)) return Walk_status::revisited;
          path.crossings.back().push_back(e);
          // g: u -> w; the third vertex of f is x.
          const vertex_descriptor third = target(next(g, m_tm), m_tm);
          const CGAL::Sign sx = m_plane.side(point(third));
          if (sx == CGAL::ZERO) {
            x = third;
            entered = f;
            break;
          }
          e = sx == m_plane.side(point(source(g, m_tm))) ? next(g, m_tm) : prev(g, m_tm);
        }
      }
      if (x == m_b) {
        path.waypoints.push_back(x);
        return Walk_status::reached;
      }
      if (!m_plane.strictly_between(point(x))) return Walk_status::left_segment;
      if (m_vertex_blocked(x)) return Walk_status::constrained_vertex;
      if (!passed.insert(x)) return Walk_status::revisited;
      path.waypoints.push_back(x);
      path.crossings.emplace_back();
      // Go on from x, not back the way the path came.
      std::vector<Exit> next_exits;
      for (const Exit& e : exits(x)) {
        if (e.through_vertex ? e.to == from_vertex || e.to == path.waypoints[path.waypoints.size() - 2]
                             : e.face == entered)
          continue;
        next_exits.push_back(e);
      }
      if (next_exits.empty()) return Walk_status::no_exit;
      exit = *std::max_element(next_exits.begin(), next_exits.end(),
                               [](const Exit& p, const Exit& q) { return p.forward < q.forward; });
    }
    return Walk_status::revisited;
  }

  const TriangleMesh& m_tm;
  VPM m_vpm;
  EdgeBlocked m_edge_blocked;
  VertexBlocked m_vertex_blocked;
  mutable vertex_descriptor m_a{}, m_b{};
  mutable Cutting_plane m_plane;
};

}  // namespace internal

/// The projected path of the segment from vertex `source` to vertex `target` of `tm` (thesis
/// appendix A, with one cutting plane per segment as described at the top of this file).
/// The result's `status` says whether `target` was reached; the waypoints and crossings are
/// filled only then.
/// \tparam TriangleMesh a model of `FaceGraph` whose faces are triangles
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param tm the mesh
/// \param source the segment's start, a vertex of `tm`
/// \param target the segment's end, another vertex of `tm`
/// \param np an optional sequence of named parameters among the ones listed below
/// \return the path (Surface_path), or why the walk stopped (`status`)
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///       meshfit::Point_3 as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for `CGAL::vertex_point_t` must be
///       available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{edge_is_constrained_map}
///     \cgalParamDescription{input: the edges the path must not cross}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%edge_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: every edge may be crossed}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_is_constrained_map}
///     \cgalParamDescription{input: the vertices the path must not pass through (its two ends excepted)}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: every vertex may be passed through}
///   \cgalParamNEnd
/// \cgalNamedParamsEnd
///
/// \throws Invalid_input when `source` and `target` are the same vertex.
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Surface_path<TriangleMesh> project_segment(const TriangleMesh& tm,
                                           typename boost::graph_traits<TriangleMesh>::vertex_descriptor source,
                                           typename boost::graph_traits<TriangleMesh>::vertex_descriptor target,
                                           const NamedParameters& np = CGAL::parameters::default_values()) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  using GT = boost::graph_traits<TriangleMesh>;
  const auto vpm = choose_parameter(get_parameter(np, CGAL::internal_np::vertex_point),
                                    get_const_property_map(CGAL::vertex_point, tm));
  const auto ecm = choose_parameter(get_parameter(np, CGAL::internal_np::edge_is_constrained),
                                    CGAL::Static_boolean_property_map<typename GT::edge_descriptor, false>());
  const auto vcm = choose_parameter(get_parameter(np, CGAL::internal_np::vertex_is_constrained),
                                    CGAL::Static_boolean_property_map<typename GT::vertex_descriptor, false>());
  if (source == target) throw Invalid_input("project_segment: the segment's two ends are one vertex");
  bool ok = false;
  const Cutting_plane plane = internal::cutting_plane(tm, vpm, source, target, ok);
  if (!ok) {
    Surface_path<TriangleMesh> path;
    path.plane = plane;
    path.status = Walk_status::degenerate_plane;
    return path;
  }
  auto edge_blocked = [&](typename GT::edge_descriptor e) { return bool(get(ecm, e)); };
  auto vertex_blocked = [&](typename GT::vertex_descriptor v) { return bool(get(vcm, v)); };
  internal::Segment_walker<TriangleMesh, decltype(vpm), decltype(edge_blocked), decltype(vertex_blocked)> walker(
      tm, vpm, edge_blocked, vertex_blocked);
  return walker.walk(source, target, plane);
}

}  // namespace meshfit

#endif  // MESHFIT_SURFACE_WALK_H
