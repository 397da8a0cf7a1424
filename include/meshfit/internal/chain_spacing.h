// meshfit internal: inner vertices of the curve chains slid along their segments, away from each
// other, where that mends needles.
#ifndef MESHFIT_INTERNAL_CHAIN_SPACING_H
#define MESHFIT_INTERNAL_CHAIN_SPACING_H

#include <meshfit/curve_network.h>
#include <meshfit/predicates.h>
#include <meshfit/internal/angle_flips.h>
#include <meshfit/internal/stage_support.h>
#include <meshfit/partition.h>

#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace meshfit {
namespace internal {

/// A walk that crosses a fan of edges near a vertex leaves a row of chain vertices bunched on a
/// short stretch of its segment, and each tiny curve edge is the short side of a needle that
/// smoothing cannot mend (curve vertices do not move) nor an edge flip (curve edges stay). Here
/// every inner vertex of a segment's chain (segment_edge_chain; the network's own vertices stay)
/// slides along the segment towards the middle (in the segment's parameter) of its two chain
/// neighbours, by the whole way, or else a half, a quarter or a tenth of it, when that raises the
/// smallest angle of the faces around it, turns none of them over (each face, moved, is
/// positively oriented in its own plane before the move: exact) and folds no edge of those faces
/// that did not fold. A moved vertex is the point a + t (b − a) of the segment a b, as the fine
/// level places chain vertices. Sweeps over all chains until none moves, at most 50 (the figures
/// of the battery's peanut cases: up to 130 moves). Returns the moves.
template <typename TriangleMesh, typename VPM, typename ECM>
std::size_t space_chain_vertices(TriangleMesh& tm, const VPM& vpm, const ECM& curve, const Curve_network& network,
                                 const std::vector<std::size_t>& mesh_vertex_of_network_vertex, double tolerance) {
  using GT = boost::graph_traits<TriangleMesh>;
  using vertex_descriptor = typename GT::vertex_descriptor;
  using halfedge_descriptor = typename GT::halfedge_descriptor;
  using P = typename boost::property_traits<VPM>::value_type;
  std::vector<vertex_descriptor> vertex_of(vertices(tm).first, vertices(tm).second);
  auto point = [&](vertex_descriptor v) { return point_of<TriangleMesh>(vpm, v); };
  struct Chain {
    Point_3 a, b;
    std::vector<vertex_descriptor> vertices;
  };
  std::vector<Chain> chains;
  for (const auto& s : network.segments()) {
    const Point_3 &a = network.point(s[0]), &b = network.point(s[1]);
    if (a == b) continue;
    auto chain = segment_edge_chain(tm, vpm, curve, vertex_of[mesh_vertex_of_network_vertex[s[0]]],
                                    vertex_of[mesh_vertex_of_network_vertex[s[1]]], tolerance);
    if (chain.size() > 2) chains.push_back({a, b, std::move(chain)});
  }
  // The smallest angle of the faces around v, and the folded edges among those faces' edges.
  auto around = [&](vertex_descriptor v, std::size_t& folds) {
    double smallest = CGAL_PI;
    folds = 0;
    for (halfedge_descriptor h : CGAL::halfedges_around_target(halfedge(v, tm), tm)) {
      if (is_border(h, tm)) continue;
      smallest = std::min(smallest, smallest_angle(point(source(h, tm)), point(target(h, tm)), point(target(next(h, tm), tm))));
      for (halfedge_descriptor g : CGAL::halfedges_around_face(h, tm))
        if (!is_border(opposite(g, tm), tm) && edge_folds(tm, g, point)) ++folds;
    }
    return smallest;
  };
  auto keeps_orientation = [&](vertex_descriptor v, const Point_3& old) {
    for (halfedge_descriptor h : CGAL::halfedges_around_target(halfedge(v, tm), tm)) {
      if (is_border(h, tm)) continue;
      const Point_3 p = point(source(h, tm)), r = point(target(next(h, tm), tm));
      if (orientation_in_plane(Triangle_points{p, old, r}, p, point(v), r) != CGAL::POSITIVE) return false;
    }
    return true;
  };
  std::size_t moves = 0;
  for (int sweep = 0; sweep < 50; ++sweep) {
    std::size_t moved = 0;
    for (const Chain& c : chains) {
      const Vector_3 d = c.b - c.a;
      const double d2 = d.squared_length();
      auto parameter = [&](vertex_descriptor v) { return ((point(v) - c.a) * d) / d2; };
      for (std::size_t i = 1; i + 1 < c.vertices.size(); ++i) {
        const vertex_descriptor v = c.vertices[i];
        const double t = parameter(v), goal = 0.5 * (parameter(c.vertices[i - 1]) + parameter(c.vertices[i + 1]));
        if (!(std::abs(goal - t) > 1e-3)) continue;
        const Point_3 old = point(v);
        std::size_t folds_before = 0, folds_after = 0;
        const double before = around(v, folds_before);
        bool done = false;
        for (double step : {1.0, 0.5, 0.25, 0.1}) {
          const Point_3 q = c.a + (t + step * (goal - t)) * d;
          put(vpm, v, P(q.x(), q.y(), q.z()));
          if (keeps_orientation(v, old) && around(v, folds_after) > before && folds_after <= folds_before) {
            done = true;
            break;
          }
        }
        if (done)
          ++moved;
        else
          put(vpm, v, P(old.x(), old.y(), old.z()));
      }
    }
    moves += moved;
    if (moved == 0) break;
  }
  return moves;
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_CHAIN_SPACING_H
