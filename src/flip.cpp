#include <meshfit/flip.h>

#include <CGAL/Interval_nt.h>
#include <CGAL/Mpzf.h>

#include <cmath>

namespace meshfit {

namespace {

// n · ((b − a) × (c − a)), n = (p2 − p1) × (p3 − p1): a polynomial of degree 4 in the inputs.
template <typename NT>
NT plane_orientation_det(const Triangle_points& t, const Point_3& a, const Point_3& b, const Point_3& c) {
  auto coords = [](const Point_3& p) { return std::array<NT, 3>{NT(p.x()), NT(p.y()), NT(p.z())}; };
  const auto p1 = coords(t[0]), p2 = coords(t[1]), p3 = coords(t[2]);
  const auto A = coords(a), B = coords(b), C = coords(c);
  NT e1[3], e2[3], u[3], v[3];
  for (int k = 0; k < 3; ++k) {
    e1[k] = p2[k] - p1[k];
    e2[k] = p3[k] - p1[k];
    u[k] = B[k] - A[k];
    v[k] = C[k] - A[k];
  }
  const NT n0 = e1[1] * e2[2] - e1[2] * e2[1], n1 = e1[2] * e2[0] - e1[0] * e2[2],
           n2 = e1[0] * e2[1] - e1[1] * e2[0];
  const NT w0 = u[1] * v[2] - u[2] * v[1], w1 = u[2] * v[0] - u[0] * v[2], w2 = u[0] * v[1] - u[1] * v[0];
  return n0 * w0 + n1 * w1 + n2 * w2;
}

}  // namespace

CGAL::Sign internal::orientation_in_plane_unfiltered(const Triangle_points& plane, const Point_3& a,
                                                     const Point_3& b, const Point_3& c) {
  {
    CGAL::Protect_FPU_rounding<true> protect;
    const CGAL::Interval_nt<false> d = plane_orientation_det<CGAL::Interval_nt<false>>(plane, a, b, c);
    if (d.inf() > 0) return CGAL::POSITIVE;
    if (d.sup() < 0) return CGAL::NEGATIVE;
  }
  // Mpzf holds sums and products of doubles exactly.
  const CGAL::Mpzf d = plane_orientation_det<CGAL::Mpzf>(plane, a, b, c);
  return CGAL::sign(d);
}

Flip_count flip_counter(const Triangle_points& before, const Triangle_points& after) {
  Flip_count count;
  Triangle_points cur = before;
  CGAL::Sign last = orientation_in_plane(before, cur[0], cur[1], cur[2]);
  if (last == CGAL::ZERO) {
    count.degenerate = true;
    return count;
  }
  for (int i = 0; i < 3; ++i) {
    if (after[i] == cur[i]) continue;  // t_i = 0 crosses nothing
    const Point_3& a = cur[(i + 1) % 3];
    const Point_3& b = cur[(i + 2) % 3];
    // The side of line d_i = (a, b) on which the moving vertex ends; it started on side `last`.
    const CGAL::Sign end = orientation_in_plane(before, a, b, after[i]);
    cur[i] = after[i];
    if (end == CGAL::ZERO) {
      // Ending on the line: the face is degenerate now; the next motion may still move it off.
      count.degenerate = true;
      continue;
    }
    count.degenerate = false;
    if (end != last) ++count.crossings;
    last = end;
  }
  return count;
}

Flip_state orientation_flip_test(const Triangle_points& before, const Triangle_points& after) {
  if (orientation_in_plane(before, before[0], before[1], before[2]) == CGAL::ZERO) return Flip_state::degenerate;
  switch (orientation_in_plane(before, after[0], after[1], after[2])) {
    case CGAL::POSITIVE: return Flip_state::kept;
    case CGAL::NEGATIVE: return Flip_state::flipped;
    default: return Flip_state::degenerate;
  }
}

Flip_state normal_angle_flip_test(const Triangle_points& before, const Triangle_points& after,
                                  double max_angle) {
  const Vector_3 n0 = CGAL::cross_product(before[1] - before[0], before[2] - before[0]);
  const Vector_3 n1 = CGAL::cross_product(after[1] - after[0], after[2] - after[0]);
  const double l0 = std::sqrt(n0.squared_length()), l1 = std::sqrt(n1.squared_length());
  if (!(l0 > 0) || !(l1 > 0)) return Flip_state::degenerate;
  const double c = std::max(-1.0, std::min(1.0, (n0 * n1) / (l0 * l1)));
  return std::acos(c) > max_angle ? Flip_state::flipped : Flip_state::kept;
}

}  // namespace meshfit
