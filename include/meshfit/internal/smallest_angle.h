// meshfit internal: the smallest angle of a triangle, the one measure of angle quality that the
// stages (angle flips, chain spacing, the fine level's sliver flips) and the checks share.
#ifndef MESHFIT_INTERNAL_SMALLEST_ANGLE_H
#define MESHFIT_INTERNAL_SMALLEST_ANGLE_H

#include <meshfit/kernel.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace meshfit {
namespace internal {

/// The smallest angle (radians) of the triangle a b c, each angle as atan2(|e1 × e2|, e1 · e2)
/// (accurate near 0 and π, unlike acos); 0 when the triangle is degenerate. The edges are divided
/// by their largest coordinate first, so that the products neither overflow at coordinates of
/// 1e100 nor underflow at extents of 1e-100 (the supported range, coordinate_range.h).
inline double smallest_angle(const Point_3& a, const Point_3& b, const Point_3& c) {
  const std::array<Point_3, 3> p{a, b, c};
  double smallest = CGAL_PI;
  for (int k = 0; k < 3; ++k) {
    Vector_3 e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
    const double size = std::max({std::abs(e1.x()), std::abs(e1.y()), std::abs(e1.z()), std::abs(e2.x()),
                                  std::abs(e2.y()), std::abs(e2.z())});
    if (!(size > 0)) return 0;
    e1 = e1 / size, e2 = e2 / size;
    smallest = std::min(smallest, std::atan2(std::sqrt(CGAL::cross_product(e1, e2).squared_length()), e1 * e2));
  }
  return smallest;
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_SMALLEST_ANGLE_H
