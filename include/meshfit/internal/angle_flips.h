// meshfit internal: edge flips that raise the smallest angle of a fitted mesh.
#ifndef MESHFIT_INTERNAL_ANGLE_FLIPS_H
#define MESHFIT_INTERNAL_ANGLE_FLIPS_H

#include <meshfit/predicates.h>
#include <meshfit/internal/smallest_angle.h>
#include <meshfit/internal/stage_support.h>
#include <meshfit/kernel.h>

#include <CGAL/Dynamic_property_map.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/helpers.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>

namespace meshfit {
namespace internal {

/// Lawson's flips for the smallest angle on a surface: an interior edge u-v that is no curve edge
/// (`constrained`) is flipped to x-y, the other diagonal of the quadrilateral v x u y of its two
/// faces, when that raises the smaller of the two faces' smallest angles (by 1e-6 radians at
/// least), and
/// - the quadrilateral is nearly flat: the normals of the two faces, before and after, are within
///   `max_dihedral` radians of each other (the surface keeps its shape to a small fraction of an
///   edge);
/// - both new faces keep the side of the old ones (exact orientation against the sum of the old
///   faces' unit normals), x-y is not an edge yet, and u and v keep a face on each side of
///   every edge (three edges at least inside, two on the border);
/// - no edge around the quadrilateral folds (internal::edge_folds) that did not before.
/// Vertices do not move; the face count, the faces' descriptors and so a face patch map are kept
/// (both faces of a non-curve edge lie in one region). Edges are visited from a queue: every
/// edge once, then those around each flip; at most `4 × faces` flips. Returns the flips made.
template <typename TriangleMesh, typename VPM, typename ECM>
std::size_t flip_for_angles(TriangleMesh& tm, const VPM& vpm, const ECM& constrained, double max_dihedral) {
  using GT = boost::graph_traits<TriangleMesh>;
  auto point = [&](typename GT::vertex_descriptor v) { return point_of<TriangleMesh>(vpm, v); };
  auto normal = [](const Point_3& a, const Point_3& b, const Point_3& c) {
    return CGAL::cross_product(b - a, c - a);
  };
  const double cos_max = std::cos(max_dihedral);
  auto within = [&](const Vector_3& m, const Vector_3& n) {
    const double l = std::sqrt(m.squared_length() * n.squared_length());
    return l > 0 && m * n >= cos_max * l;
  };
  auto queued = get(CGAL::dynamic_edge_property_t<bool>(), tm);
  std::deque<typename GT::edge_descriptor> queue;
  for (auto e : edges(tm)) {
    put(queued, e, true);
    queue.push_back(e);
  }
  const std::size_t max_flips = 4 * num_faces(tm);
  std::size_t flips = 0;
  while (!queue.empty() && flips < max_flips) {
    const auto e = queue.front();
    queue.pop_front();
    put(queued, e, false);
    const auto h = halfedge(e, tm), g = opposite(h, tm);
    if (get(constrained, e) || is_border(h, tm) || is_border(g, tm)) continue;
    const auto u = source(h, tm), v = target(h, tm), x = target(next(h, tm), tm), y = target(next(g, tm), tm);
    // An interior vertex keeps three edges at least, a border vertex two (one face).
    auto spare = [&](typename GT::vertex_descriptor w) { return degree(w, tm) > (is_border(w, tm) ? 2u : 3u); };
    if (x == y || halfedge(x, y, tm).second || !spare(u) || !spare(v)) continue;
    const Point_3 pu = point(u), pv = point(v), px = point(x), py = point(y);
    const double before = std::min(smallest_angle(pu, pv, px), smallest_angle(pv, pu, py));
    const double after = std::min(smallest_angle(pv, px, py), smallest_angle(px, pu, py));
    // A gain of a millionth of a radian at least: two diagonals of equal angles (a square) differ
    // only by rounding, and would be flipped back and forth.
    if (!(after > before + 1e-6)) continue;
    const Vector_3 n1 = normal(pu, pv, px), n2 = normal(pv, pu, py), m1 = normal(pv, px, py), m2 = normal(px, pu, py);
    if (!within(n1, n2) || !within(m1, m2)) continue;
    const Vector_3 N = n1 / std::sqrt(n1.squared_length()) + n2 / std::sqrt(n2.squared_length());
    if (CGAL::orientation(pv, px, py, pv + N) != CGAL::POSITIVE || CGAL::orientation(px, pu, py, px + N) != CGAL::POSITIVE)
      continue;
    const std::array<typename GT::halfedge_descriptor, 4> outer{next(h, tm), prev(h, tm), next(g, tm), prev(g, tm)};
    auto folds = [&](typename GT::halfedge_descriptor k) {
      return !is_border(k, tm) && !is_border(opposite(k, tm), tm) && edge_folds(tm, k, point);
    };
    std::array<bool, 4> folded{};
    for (int k = 0; k < 4; ++k) folded[k] = folds(outer[k]);
    CGAL::Euler::flip_edge(h, tm);  // now x-y (or y-x)
    bool worse = folds(h);
    for (int k = 0; k < 4 && !worse; ++k) worse = folds(outer[k]) && !folded[k];
    if (worse) {
      CGAL::Euler::flip_edge(h, tm);  // back to u-v: a quadrilateral has two diagonals
      continue;
    }
    ++flips;
    for (auto k : outer)
      if (!get(queued, edge(k, tm))) {
        put(queued, edge(k, tm), true);
        queue.push_back(edge(k, tm));
      }
  }
  return flips;
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_ANGLE_FLIPS_H
