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
/// The value is the least of the three atan2, to the last bit; atan2 is taken only of the corners
/// that a comparison of cotangents (c_k s_j against c_j s_k) cannot rule out (3 % of a fit's time
/// went to atan2).
inline double smallest_angle(const Point_3& a, const Point_3& b, const Point_3& c) {
  const std::array<Point_3, 3> p{a, b, c};
  std::array<double, 3> sine{}, cosine{};  // |e1 × e2| and e1 · e2, each corner at its own scale
  for (std::size_t k = 0; k < 3; ++k) {
    Vector_3 e1 = p[(k + 1) % 3] - p[k], e2 = p[(k + 2) % 3] - p[k];
    const double size = std::max({std::abs(e1.x()), std::abs(e1.y()), std::abs(e1.z()), std::abs(e2.x()),
                                  std::abs(e2.y()), std::abs(e2.z())});
    if (!(size > 0)) return 0;
    e1 = e1 / size, e2 = e2 / size;
    sine[k] = std::sqrt(CGAL::cross_product(e1, e2).squared_length());
    cosine[k] = e1 * e2;
  }
  auto angle = [&](std::size_t k) { return std::atan2(sine[k], cosine[k]); };
  if (!(sine[0] > 0 && sine[1] > 0 && sine[2] > 0)) return std::min({CGAL_PI, angle(0), angle(1), angle(2)});
  // Angle k is below angle j when its cotangent is above: cosine[k] sine[j] > cosine[j] sine[k].
  std::size_t best = 0;
  for (std::size_t k = 1; k < 3; ++k)
    if (cosine[k] * sine[best] > cosine[best] * sine[k]) best = k;
  double smallest = std::min(CGAL_PI, angle(best));
  for (std::size_t k = 0; k < 3; ++k) {
    if (k == best) continue;
    const double x = cosine[best] * sine[k], y = cosine[k] * sine[best];
    if (x - y <= 1e-9 * (std::abs(x) + std::abs(y))) smallest = std::min(smallest, angle(k));  // too close to rule out
  }
  return smallest;
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_SMALLEST_ANGLE_H
