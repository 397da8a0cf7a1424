// meshfit: exact orientation in the plane of a triangle, the predicate every stage decides with
// (stage 1's flip counter, stage 2's walk and insertion, stage 3's flip guard, fit's
// verification). Orientation in the plane Π of triangle p1 p2 p3 of points projected onto Π is
// the sign of n · ((b − a) × (c − a)) with n = (p2 − p1) × (p3 − p1): projecting adds multiples of
// n, which this expression ignores, so no point is constructed and the sign is exact (a
// floating-point filter, then interval and exact arithmetic).
#ifndef MESHFIT_PREDICATES_H
#define MESHFIT_PREDICATES_H

#include <meshfit/kernel.h>

#include <boost/graph/graph_traits.hpp>

#include <array>
#include <cmath>

namespace meshfit {

/// The three corners of a triangle, in order.
using Triangle_points = std::array<Point_3, 3>;

namespace internal {
/// orientation_in_plane without the floating-point filter: interval arithmetic, then exact.
CGAL::Sign orientation_in_plane_unfiltered(const Triangle_points& plane, const Point_3& a, const Point_3& b,
                                           const Point_3& c);
}  // namespace internal

/// Exact orientation in the plane of a triangle, for many triangles in one plane: the plane's
/// normal is computed once, a floating-point filter decides almost every case, and the rest go to
/// interval then exact arithmetic (see orientation_in_plane).
class Plane_orientation {
 public:
  /// An unusable default (no plane); assign one made from a triangle.
  Plane_orientation() = default;
  /// Orientation in the plane of `plane`, turning as `plane` does.
  explicit Plane_orientation(const Triangle_points& plane) : m_plane(plane) {
    const Vector_3 e1 = plane[1] - plane[0], e2 = plane[2] - plane[0];
    m_n[0] = e1.y() * e2.z() - e1.z() * e2.y();
    m_n[1] = e1.z() * e2.x() - e1.x() * e2.z();
    m_n[2] = e1.x() * e2.y() - e1.y() * e2.x();
    m_m[0] = std::abs(e1.y() * e2.z()) + std::abs(e1.z() * e2.y());
    m_m[1] = std::abs(e1.z() * e2.x()) + std::abs(e1.x() * e2.z());
    m_m[2] = std::abs(e1.x() * e2.y()) + std::abs(e1.y() * e2.x());
  }
  /// The triangle given to the constructor.
  const Triangle_points& plane() const { return m_plane; }
  /// orientation_in_plane(plane(), a, b, c). The filter: the value n · ((b − a) × (c − a)) in
  /// double, every term a product of four differences of inputs passed through at most 7
  /// roundings after the differences, so its error is below 8u·M(1 + 8u) with M the same
  /// expression on absolute values and u = 2^-53; 1e-14·M is a safe bound. Magnitudes near
  /// underflow or overflow, and values within the bound, go to the exact evaluation.
  CGAL::Sign operator()(const Point_3& a, const Point_3& b, const Point_3& c) const {
    const double u0 = b.x() - a.x(), u1 = b.y() - a.y(), u2 = b.z() - a.z();
    const double v0 = c.x() - a.x(), v1 = c.y() - a.y(), v2 = c.z() - a.z();
    const double d = m_n[0] * (u1 * v2 - u2 * v1) + m_n[1] * (u2 * v0 - u0 * v2) + m_n[2] * (u0 * v1 - u1 * v0);
    const double M = m_m[0] * (std::abs(u1 * v2) + std::abs(u2 * v1)) + m_m[1] * (std::abs(u2 * v0) + std::abs(u0 * v2)) +
                     m_m[2] * (std::abs(u0 * v1) + std::abs(u1 * v0));
    if (M > 1e-250 && M < 1e250) {
      if (d > 1e-14 * M) return CGAL::POSITIVE;
      if (d < -1e-14 * M) return CGAL::NEGATIVE;
    }
    return internal::orientation_in_plane_unfiltered(m_plane, a, b, c);
  }

 private:
  Triangle_points m_plane;
  double m_n[3] = {0, 0, 0}, m_m[3] = {0, 0, 0};
};

/// Exact sign of the orientation in the plane of `plane` (before the motion) of a b c projected
/// onto that plane: POSITIVE when a b c turn as `plane` does. ZERO also when `plane` is degenerate.
inline CGAL::Sign orientation_in_plane(const Triangle_points& plane, const Point_3& a, const Point_3& b,
                                       const Point_3& c) {
  return Plane_orientation(plane)(a, b, c);
}

/// Whether the interior edge of `h` folds: its two faces turn more than 90 degrees apart (the face
/// across the edge is not positively oriented in the plane of the face of `h`; exact). `point(v)`
/// gives the position of vertex v. The fine level's repair and fit's verification both count this.
template <typename TriangleMesh, typename PointOf>
bool edge_folds(const TriangleMesh& tm, typename boost::graph_traits<TriangleMesh>::halfedge_descriptor h,
                const PointOf& point) {
  const auto g = opposite(h, tm);
  const Triangle_points a{point(source(h, tm)), point(target(h, tm)), point(target(next(h, tm), tm))};
  return orientation_in_plane(a, point(source(g, tm)), point(target(g, tm)), point(target(next(g, tm), tm))) !=
         CGAL::POSITIVE;
}

}  // namespace meshfit

#endif  // MESHFIT_PREDICATES_H
