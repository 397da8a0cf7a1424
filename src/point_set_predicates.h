// Private: exact tests on whole point sets (CGAL predicates on the input points).
#ifndef MESHFIT_SRC_POINT_SET_PREDICATES_H
#define MESHFIT_SRC_POINT_SET_PREDICATES_H

#include <meshfit/kernel.h>

#include <vector>

namespace meshfit {
namespace internal {

/// True when every point lies on one line (all equal counts; fewer than three points always do).
inline bool all_collinear(const std::vector<Point_3>& pts) {
  std::size_t j = 1;
  while (j < pts.size() && pts[j] == pts[0]) ++j;
  for (std::size_t k = j + 1; k < pts.size(); ++k)
    if (!CGAL::collinear(pts[0], pts[j], pts[k])) return false;
  return true;
}

/// True when every point lies in one plane (fewer than four points always do).
inline bool all_coplanar(const std::vector<Point_3>& pts) {
  std::size_t j = 1;
  while (j < pts.size() && pts[j] == pts[0]) ++j;
  if (j == pts.size()) return true;
  std::size_t k = j + 1;
  while (k < pts.size() && CGAL::collinear(pts[0], pts[j], pts[k])) ++k;
  if (k == pts.size()) return true;
  for (std::size_t i = k + 1; i < pts.size(); ++i)
    if (!CGAL::coplanar(pts[0], pts[j], pts[k], pts[i])) return false;
  return true;
}

/// True when the points lie in one plane up to the rounding of their coordinates: exactly, or
/// within 4 units in the last place of the coordinates' largest magnitude of their least-squares
/// plane (a plane of points that was turned or moved, its coordinates rounded afterwards). Defined
/// in rbf.cpp, beside the RBF's own, more lenient, nearly_coplanar.
bool coplanar_within_rounding(const std::vector<Point_3>& pts);

/// True when the RBF takes the points for coplanar and adds auxiliary pairs off their plane
/// (rbf_coplanarity_bound): exactly, or nearly. Defined in rbf.cpp.
bool nearly_coplanar(const std::vector<Point_3>& pts);

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_SRC_POINT_SET_PREDICATES_H
