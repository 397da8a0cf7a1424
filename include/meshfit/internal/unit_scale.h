// meshfit internal: running a stage on inputs scaled by a power of two to a unit-sized box.
// Scaling by 2^k is exact in floating point (within the supported range, see coordinate_range.h),
// so every exact predicate decides as it would on the original inputs, while the absolute
// thresholds and the squared and higher products of the algorithms see numbers of order one.
#ifndef MESHFIT_INTERNAL_UNIT_SCALE_H
#define MESHFIT_INTERNAL_UNIT_SCALE_H

#include <meshfit/coordinate_range.h>
#include <meshfit/curve_network.h>
#include <meshfit/kernel.h>

#include <boost/graph/graph_traits.hpp>

#include <cmath>
#include <string>

namespace meshfit {
namespace internal {

inline Point_3 scaled(const Point_3& p, double s) { return Point_3(p.x() * s, p.y() * s, p.z() * s); }

/// The power of two that brings the largest side of `box` into [0.5, 1) (1 for an empty or flat
/// box), limited so that no scaled coordinate exceeds max_coordinate.
double unit_scale(const Bbox_3& box);

/// `network` with every point multiplied by `s` (a power of two): the same vertices, segments and
/// indices, the same relative merge tolerance.
Curve_network scaled(const Curve_network& network, double s);

/// The bounding box of the template's points that lie on a face, after checking every point
/// against the supported range (check_coordinate_range, check_extent; the element named is
/// "template vertex i"). A vertex on no face sets no scale: one unused vertex at 1e80 would
/// otherwise shrink the surface itself to 1e-80 in the unit frame.
template <typename TriangleMesh, typename VPM>
Bbox_3 checked_template_box(const TriangleMesh& tm, const VPM& vpm) {
  Bbox_3 box, all;
  std::size_t i = 0;
  for (auto v : vertices(tm)) {
    const auto& q = get(vpm, v);
    const Point_3 p(q.x(), q.y(), q.z());  // (any point type with double coordinates)
    if (!in_coordinate_range(p)) check_coordinate_range(p, Input_location{}, "template vertex " + std::to_string(i));
    ++i;
    all += p.bbox();
    if (halfedge(v, tm) != boost::graph_traits<TriangleMesh>::null_halfedge()) box += p.bbox();
  }
  if (i > 0) check_extent(all, Input_location{}, "the template");
  return box;
}

/// Multiplies every point of `tm` by `s`.
template <typename TriangleMesh, typename VPM>
void scale_points(TriangleMesh& tm, const VPM& vpm, double s) {
  for (auto v : vertices(tm)) put(vpm, v, scaled(get(vpm, v), s));
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_UNIT_SCALE_H
