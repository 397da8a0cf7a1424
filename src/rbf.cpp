#include <meshfit/rbf.h>

#include <meshfit/internal/format_number.h>
#include <meshfit/memory_limit.h>

#include "fp_traps.h"
#include "point_set_predicates.h"
#include "rbf_evaluate.h"

#include <Eigen/Dense>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>

namespace meshfit {

const char* to_string(Rbf_kernel kernel) {
  return kernel == Rbf_kernel::linear ? "linear" : "cubic";
}

namespace {

/// Evaluates `count` points in blocks on `threads` threads (0: all): `load(i, x, y, z)` gives the
/// normalised point i, `store(i, x, y, z, sx, sy, sz)` receives it with its RBF sums. All points of
/// a block are loaded before any of them is stored, so the output may overwrite the input.
template <typename Load, typename Store>
void rbf_evaluate_blocks(const internal::Rbf_arrays& a, std::size_t count, unsigned threads, Load load, Store store) {
  const std::ptrdiff_t blocks = static_cast<std::ptrdiff_t>((count + internal::rbf_block - 1) / internal::rbf_block);
  int nt = 1;
#ifdef _OPENMP
  nt = threads == 0 ? omp_get_max_threads() : static_cast<int>(threads);
  nt = static_cast<int>(std::min<std::ptrdiff_t>(nt, std::max<std::ptrdiff_t>(blocks, 1)));
#else
  (void)threads;
#endif
#pragma omp parallel num_threads(nt)
  {
  internal::Fp_trap_scope traps;  // per thread: the floating-point environment is per thread
#pragma omp for schedule(dynamic, 4)
  for (std::ptrdiff_t b = 0; b < blocks; ++b) {
    alignas(64) double px[internal::rbf_block], py[internal::rbf_block], pz[internal::rbf_block], sx[internal::rbf_block], sy[internal::rbf_block],
        sz[internal::rbf_block];
    const std::size_t first = static_cast<std::size_t>(b) * internal::rbf_block;
    const std::size_t m = std::min(internal::rbf_block, count - first);
    for (std::size_t i = 0; i < m; ++i) load(first + i, px[i], py[i], pz[i]);
    internal::rbf_sum_block(a, px, py, pz, m, sx, sy, sz);
    for (std::size_t i = 0; i < m; ++i) store(first + i, px[i], py[i], pz[i], sx[i], sy[i], sz[i]);
  }
  }
}


bool finite(const Point_3& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
}

double phi(Rbf_kernel k, double r) { return k == Rbf_kernel::linear ? r : r * r * r; }

// The mean of the unit vectors along vs (zero vectors skipped).
Vector_3 mean_unit_vector(const std::vector<Vector_3>& vs) {
  Vector_3 mean(0, 0, 0);
  for (const Vector_3& v : vs) {
    const double len = std::sqrt(v.squared_length());
    if (len > 0) mean = mean + v / len;
  }
  return vs.empty() ? mean : mean / static_cast<double>(vs.size());
}

// Centroid and bounding-box diagonal of a point set.
std::pair<Vector_3, double> frame_of(const std::vector<Point_3>& pts) {
  double sx = 0, sy = 0, sz = 0;
  Bbox_3 box;
  for (const Point_3& p : pts) {
    sx += p.x();
    sy += p.y();
    sz += p.z();
    box += p.bbox();
  }
  const double n = static_cast<double>(pts.size());
  const double diag = std::sqrt(CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                                CGAL::square(box.zmax() - box.zmin()));
  return {Vector_3(sx / n, sy / n, sz / n), diag};
}

// Smallest singular value of the affine block [x y z 1] relative to the largest, and the
// direction (in normalised coordinates) along which the centres are thinnest.
std::pair<double, Vector_3> affine_conditioning(const std::vector<Point_3>& pts, const Vector_3& shift,
                                                double scale) {
  Eigen::MatrixXd P(pts.size(), 4);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Vector_3 q = (pts[i] - CGAL::ORIGIN - shift) * scale;
    P.row(static_cast<Eigen::Index>(i)) << q.x(), q.y(), q.z(), 1.0;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(P, Eigen::ComputeThinV);
  const auto& s = svd.singularValues();
  const double ratio = s(0) > 0 ? s(3) / s(0) : 0.0;
  // The thinnest direction of the centred cloud.
  Eigen::MatrixXd C = P.leftCols(3);
  C.rowwise() -= C.colwise().mean();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd3(C, Eigen::ComputeThinV);
  const Eigen::Vector3d n = svd3.matrixV().col(2);
  return {ratio, Vector_3(n(0), n(1), n(2))};
}

}  // namespace

Rbf_interpolant Rbf_interpolant::solve(const std::vector<Point_3>& centres, const std::vector<Point_3>& values,
                                       Rbf_kernel kernel, std::size_t memory_limit, double& residual) {
  const auto [centre_shift, centre_diag] = frame_of(centres);
  Rbf_interpolant E;
  E.m_kernel = kernel;
  E.m_shift_in = centre_shift;
  E.m_scale_in = 1.0 / centre_diag;
  const auto [value_shift, value_diag] = frame_of(values);
  E.m_shift_out = value_shift;
  E.m_scale_out = value_diag > 0 ? 1.0 / value_diag : 1.0;

  const Eigen::Index n = static_cast<Eigen::Index>(centres.size());
  // K and its LU factors, before either is allocated.
  const double system = static_cast<double>(n + 4);
  check_memory_estimate(2 * 8 * system * system, memory_limit, "deform",
                        "the RBF's dense " + std::to_string(n + 4) + "×" + std::to_string(n + 4) + " system");
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n + 4, n + 4);
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(n + 4, 3);
  std::vector<Vector_3> c(centres.size());
  for (Eigen::Index i = 0; i < n; ++i) {
    c[i] = (centres[i] - CGAL::ORIGIN - E.m_shift_in) * E.m_scale_in;
    const Vector_3 v = (values[i] - CGAL::ORIGIN - E.m_shift_out) * E.m_scale_out;
    Y.row(i) << v.x(), v.y(), v.z();
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < i; ++j) {
      const double r = std::sqrt((c[i] - c[j]).squared_length());
      K(i, j) = K(j, i) = phi(kernel, r);
    }
    const double row[4] = {c[i].x(), c[i].y(), c[i].z(), 1.0};
    for (int k = 0; k < 4; ++k) K(i, n + k) = K(n + k, i) = row[k];
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(K);
  // A (numerically) singular system would divide by a zero pivot: centres that nearly coincide,
  // or a degenerate configuration the exact tests above let through.
  const auto pivots = lu.matrixLU().diagonal().cwiseAbs();
  const double pivot_ratio = pivots.maxCoeff() > 0 ? pivots.minCoeff() / pivots.maxCoeff() : 0.0;
  const double rcond = pivot_ratio > rbf_rcond_bound ? lu.rcond() : 0.0;  // (a zero pivot would trap)
  if (!(rcond > rbf_rcond_bound))
    throw Numerical_error("RBF: the " + std::to_string(n + 4) + "×" + std::to_string(n + 4) +
                          " system is singular (reciprocal condition number " + internal::format_number(rcond) +
                          "): some centres nearly coincide");
  const Eigen::MatrixXd X = lu.solve(Y);
  residual = (K * X - Y).norm() / std::max(Y.norm(), 1e-300);
  if (!X.allFinite() || !(residual <= rbf_residual_bound))
    throw Numerical_error("RBF: the solve of the " + std::to_string(n + 4) + "×" + std::to_string(n + 4) +
                          " system failed (relative residual " + internal::format_number(residual) + ", bound " +
                          internal::format_number(rbf_residual_bound) + ")");

  E.m_cx.resize(n); E.m_cy.resize(n); E.m_cz.resize(n);
  E.m_ax.resize(n); E.m_ay.resize(n); E.m_az.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    E.m_cx[i] = c[i].x(); E.m_cy[i] = c[i].y(); E.m_cz[i] = c[i].z();
    E.m_ax[i] = X(i, 0); E.m_ay[i] = X(i, 1); E.m_az[i] = X(i, 2);
  }
  for (int k = 0; k < 4; ++k)
    for (int d = 0; d < 3; ++d) E.m_affine[k][d] = X(n + k, d);
  return E;
}

namespace {

void check_pairs(const std::vector<Point_3>& centres, const std::vector<Point_3>& values,
                 const std::vector<Vector_3>& normals) {
  if (centres.size() != values.size())
    throw Invalid_input("RBF: " + std::to_string(centres.size()) + " centres but " +
                        std::to_string(values.size()) + " values");
  if (!normals.empty() && normals.size() != centres.size())
    throw Invalid_input("RBF: " + std::to_string(normals.size()) + " normals for " +
                        std::to_string(centres.size()) + " centres");
  for (std::size_t i = 0; i < centres.size(); ++i)
    if (!finite(centres[i]) || !finite(values[i]) ||
        (!normals.empty() && !(std::isfinite(normals[i].x()) && std::isfinite(normals[i].y()) &&
                               std::isfinite(normals[i].z()))))
      throw Invalid_input("RBF: pair " + std::to_string(i) + " has a non-finite coordinate");
}

// The pairs fit() solves for: the given ones without repeats, then the auxiliary ones.
struct Rbf_pairs {
  std::vector<Point_3> centres, values;
  std::vector<Vector_3> normals;
  std::size_t repeated = 0;  // identical pairs dropped
};

// Repeated centres: identical pairs are dropped (the later ones), conflicting ones are an error.
Rbf_pairs distinct_pairs(const std::vector<Point_3>& centres_in, const std::vector<Point_3>& values_in,
                         const std::vector<Vector_3>& normals_in) {
  std::vector<std::size_t> order(centres_in.size());
  std::iota(order.begin(), order.end(), 0);
  auto key = [&](std::size_t i) {
    return std::make_tuple(centres_in[i].x(), centres_in[i].y(), centres_in[i].z());
  };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  Rbf_pairs pairs;
  std::vector<bool> keep(centres_in.size(), true);
  for (std::size_t k = 1; k < order.size(); ++k) {
    const std::size_t a = order[k - 1], b = order[k];
    if (centres_in[a] != centres_in[b]) continue;
    if (values_in[a] != values_in[b])
      throw Invalid_input("RBF: pairs " + std::to_string(std::min(a, b)) + " and " +
                          std::to_string(std::max(a, b)) +
                          " have the same centre but different values");
    keep[std::max(a, b)] = false;
    ++pairs.repeated;
  }
  for (std::size_t i = 0; i < centres_in.size(); ++i)
    if (keep[i]) {
      pairs.centres.push_back(centres_in[i]);
      pairs.values.push_back(values_in[i]);
      if (!normals_in.empty()) pairs.normals.push_back(normals_in[i]);
    }
  return pairs;
}

void check_span(const std::vector<Point_3>& centres) {
  if (centres.size() < 4)
    throw Invalid_input("RBF: " + std::to_string(centres.size()) +
                        " distinct centres; at least 4 are needed");
  if (internal::all_collinear(centres)) {
    throw Invalid_input("RBF: all " + std::to_string(centres.size()) +
                        " centres are collinear; they must span 3D (or at least a plane)");
  }
}

// The largest distance of the points from `centre`: a size that does not change when they turn
// (a bounding box's diagonal does).
double radius(const std::vector<Point_3>& pts, const Vector_3& centre) {
  double r = 0;
  for (const Point_3& p : pts) r = std::max(r, std::sqrt((p - CGAL::ORIGIN - centre).squared_length()));
  return r;
}

// σ: the sign that makes the best affine map of the centres' plane (normal n) onto the values keep
// its orientation (det[m_1, m_2, σe] > 0). The in-plane part of the map, least squares:
// v - v̄ ≈ m_1 (c - c̄)·u_1 + m_2 (c - c̄)·u_2.
double orientation_sign(const std::vector<Point_3>& centres, const Vector_3& centre_shift, double centre_diag,
                        const std::vector<Point_3>& values, const Vector_3& value_shift, const Vector_3& n,
                        const Vector_3& e) {
  const std::size_t n0 = centres.size();
  const Vector_3 u1 = [&] {
    const Vector_3 a = std::abs(n.x()) < 0.9 ? Vector_3(1, 0, 0) : Vector_3(0, 1, 0);
    const Vector_3 u = CGAL::cross_product(n, a);
    return u / std::sqrt(u.squared_length());
  }();
  const Vector_3 u2 = CGAL::cross_product(n, u1);
  Eigen::MatrixXd A(n0, 3), B(n0, 3);
  for (std::size_t i = 0; i < n0; ++i) {
    const Vector_3 q = (centres[i] - CGAL::ORIGIN - centre_shift) / centre_diag;
    const Vector_3 w = values[i] - CGAL::ORIGIN - value_shift;
    A.row(static_cast<Eigen::Index>(i)) << q * u1, q * u2, 1.0;
    B.row(static_cast<Eigen::Index>(i)) << w.x(), w.y(), w.z();
  }
  const Eigen::MatrixXd M = A.colPivHouseholderQr().solve(B);  // rows: m_1, m_2, offset
  const Vector_3 m1(M(0, 0), M(0, 1), M(0, 2)), m2(M(1, 0), M(1, 1), M(1, 2));
  return CGAL::cross_product(m1, m2) * e < 0 ? -1.0 : 1.0;
}

// Coplanar (exactly or nearly): add auxiliary pairs off the plane (thesis §2.2). Centre c_i
// offset by h_c·n (n the centres' plane normal, turned to the side of the given normals) maps to
// value v_i offset by h_v·σ·e, where e is the direction along which the values are thinnest,
// h_c and h_v a fifth of each side's radius about its centroid, and σ the sign that makes the best
// affine map of the plane onto the values keep its orientation (det[m_1, m_2, σe] > 0). Every
// quantity is taken from its own side, so the auxiliary pairs turn, move and scale with the
// template and with the network independently: the fit does not depend on where either is.
void add_auxiliary_pairs(Rbf_pairs& pairs) {
  std::vector<Point_3>& centres = pairs.centres;
  std::vector<Point_3>& values = pairs.values;
  const std::size_t n0 = centres.size();
  const auto [centre_shift, centre_diag] = frame_of(centres);
  const Vector_3 thin = affine_conditioning(centres, centre_shift, 1.0 / centre_diag).second;
  Vector_3 n = thin / std::sqrt(thin.squared_length());
  if (!pairs.normals.empty() && mean_unit_vector(pairs.normals) * n < 0) n = -n;
  const auto [value_shift0, value_diag0] = frame_of(values);
  const Vector_3 e0 = affine_conditioning(values, value_shift0, value_diag0 > 0 ? 1.0 / value_diag0 : 1.0).second;
  const Vector_3 e = e0 / std::sqrt(e0.squared_length());
  const double sigma = orientation_sign(centres, centre_shift, centre_diag, values, value_shift0, n, e);
  const double rc = radius(centres, centre_shift), rv = radius(values, value_shift0);
  const double hc = 0.2 * rc, hv = 0.2 * (rv > 0 ? rv : rc);
  for (std::size_t i = 0; i < n0; ++i) {
    centres.push_back(centres[i] + hc * n);
    values.push_back(values[i] + (hv * sigma) * e);
  }
}

}  // namespace

namespace internal {

// Coplanar exactly, or nearly (the affine block's conditioning).
bool nearly_coplanar(const std::vector<Point_3>& pts) {
  const auto [shift, diag] = frame_of(pts);
  return all_coplanar(pts) || affine_conditioning(pts, shift, 1.0 / diag).first < rbf_coplanarity_bound;
}

// The cloud's thickness (the largest distance of a point from its least-squares plane) against
// what rounding leaves of a plane: a few units in the last place of the coordinates' largest
// magnitude. An absolute test, not one relative to the cloud's extent: 8 pairs of extent 4 moved
// to x = 1e15 (where coordinates are multiples of 1/8) are 6 units thick, not a rounded plane.
bool coplanar_within_rounding(const std::vector<Point_3>& pts) {
  if (all_coplanar(pts)) return true;
  double magnitude = 0;
  for (const Point_3& p : pts) magnitude = std::max({magnitude, std::abs(p.x()), std::abs(p.y()), std::abs(p.z())});
  const double ulp = std::nextafter(magnitude, std::numeric_limits<double>::infinity()) - magnitude;
  // Differences from the first point: exact for nearby coordinates, unlike a centroid far out.
  Eigen::MatrixXd C(pts.size(), 3);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Vector_3 d = pts[i] - pts.front();
    C.row(static_cast<Eigen::Index>(i)) << d.x(), d.y(), d.z();
  }
  C.rowwise() -= C.colwise().mean();
  const Eigen::Vector3d normal = Eigen::JacobiSVD<Eigen::MatrixXd>(C, Eigen::ComputeThinV).matrixV().col(2);
  return (C * normal).cwiseAbs().maxCoeff() <= 4 * ulp;
}

}  // namespace internal

Rbf_interpolant Rbf_interpolant::fit(const std::vector<Point_3>& centres_in,
                                     const std::vector<Point_3>& values_in, Rbf_kernel kernel,
                                     const std::vector<Vector_3>& normals_in, Rbf_fit_report* report,
                                     std::size_t memory_limit, bool orientation_from_layout) {
  internal::Fp_trap_scope traps;
  check_pairs(centres_in, values_in, normals_in);
  Rbf_pairs pairs = distinct_pairs(centres_in, values_in, normals_in);
  check_span(pairs.centres);
  const std::size_t n0 = pairs.centres.size();
  if (internal::nearly_coplanar(pairs.centres)) add_auxiliary_pairs(pairs);
  double residual = 0;
  Rbf_interpolant E = solve(pairs.centres, pairs.values, kernel, memory_limit, residual);
  // Pairs on an open template (a disc, a patch): their layout along the surface fixes the
  // orientation, and their offsets across it are shape, not orientation (a curved patch onto
  // flatter curves, or onto a saddle, correlates either way). When the plain fit mirrors them, the
  // auxiliary pairs decide instead: they keep the layout's orientation.
  if (orientation_from_layout && pairs.centres.size() == n0 && !(E.affine_determinant() > 0)) {
    add_auxiliary_pairs(pairs);
    E = solve(pairs.centres, pairs.values, kernel, memory_limit, residual);
  }
  const std::size_t auxiliary = pairs.centres.size() - n0;

  if (report) {
    report->centres = pairs.centres.size() - auxiliary;
    report->repeated_pairs = pairs.repeated;
    report->auxiliary_pairs = auxiliary;
    report->relative_residual = residual;
  }
  return E;
}

Point_3 Rbf_interpolant::affine_part(const Point_3& p) const {
  const double x = (p.x() - m_shift_in.x()) * m_scale_in, y = (p.y() - m_shift_in.y()) * m_scale_in,
               z = (p.z() - m_shift_in.z()) * m_scale_in;
  double r[3];
  for (int d = 0; d < 3; ++d) r[d] = m_affine[0][d] * x + m_affine[1][d] * y + m_affine[2][d] * z + m_affine[3][d];
  return Point_3(m_shift_out.x() + r[0] / m_scale_out, m_shift_out.y() + r[1] / m_scale_out,
                 m_shift_out.z() + r[2] / m_scale_out);
}

double Rbf_interpolant::affine_determinant() const {
  const auto& a = m_affine;  // rows x, y, z of the normalised input; columns the output
  return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
         a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

Point_3 Rbf_interpolant::operator()(const Point_3& p) const {
  std::vector<Point_3> out, in{p};
  evaluate(in, out, 1);
  return out[0];
}

void Rbf_interpolant::evaluate(const std::vector<Point_3>& in, std::vector<Point_3>& out,
                               unsigned threads) const {
  const internal::Rbf_arrays a{m_kernel, m_cx.data(), m_cy.data(), m_cz.data(), m_ax.data(), m_ay.data(),
                         m_az.data(), m_cx.size()};
  const double s_in = m_scale_in, s_out = m_scale_out;
  const Vector_3 shift_in = m_shift_in, shift_out = m_shift_out;
  const auto& A = m_affine;
  out.resize(in.size());
  rbf_evaluate_blocks(
      a, in.size(), threads,
      [&](std::size_t i, double& x, double& y, double& z) {
        x = (in[i].x() - shift_in.x()) * s_in;
        y = (in[i].y() - shift_in.y()) * s_in;
        z = (in[i].z() - shift_in.z()) * s_in;
      },
      [&](std::size_t i, double x, double y, double z, double sx, double sy, double sz) {
        double r[3];
        for (int d = 0; d < 3; ++d) r[d] = A[0][d] * x + A[1][d] * y + A[2][d] * z + A[3][d];
        out[i] = Point_3(shift_out.x() + (sx + r[0]) / s_out, shift_out.y() + (sy + r[1]) / s_out,
                         shift_out.z() + (sz + r[2]) / s_out);
      });
}

}  // namespace meshfit
