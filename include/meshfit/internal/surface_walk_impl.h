// meshfit internal: the walk along a cutting plane behind surface_walk.h (the plane, the exact
// side tests, the walk itself). Included by surface_walk.h after its types, not on its own.
#ifndef MESHFIT_INTERNAL_SURFACE_WALK_IMPL_H
#define MESHFIT_INTERNAL_SURFACE_WALK_IMPL_H

namespace meshfit {
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
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_SURFACE_WALK_IMPL_H
