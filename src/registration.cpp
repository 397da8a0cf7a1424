// register_quadratic_warp (registration.h): Coherent Point Drift with a quadratic warp.
#include <meshfit/registration.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace meshfit {
namespace {

constexpr std::size_t warp_monomials = 10;
using Warp_basis = Eigen::Matrix<double, warp_monomials, 1>;
using Warp_coefficients = Eigen::Matrix<double, warp_monomials, 3>;

Warp_basis warp_basis(const Eigen::Vector3d& u) {
  Warp_basis b;
  b << 1, u(0), u(1), u(2), u(0) * u(0), u(0) * u(1), u(0) * u(2), u(1) * u(1), u(1) * u(2), u(2) * u(2);
  return b;
}

// ∂b/∂u (10 × 3).
Eigen::Matrix<double, warp_monomials, 3> warp_basis_gradient(const Eigen::Vector3d& u) {
  Eigen::Matrix<double, warp_monomials, 3> g = Eigen::Matrix<double, warp_monomials, 3>::Zero();
  g(1, 0) = g(2, 1) = g(3, 2) = 1;
  g(4, 0) = 2 * u(0);
  g(5, 0) = u(1), g(5, 1) = u(0);
  g(6, 0) = u(2), g(6, 2) = u(0);
  g(7, 1) = 2 * u(1);
  g(8, 1) = u(2), g(8, 2) = u(1);
  g(9, 2) = 2 * u(2);
  return g;
}

Eigen::Vector3d eigen_point(const Point_3& p) { return {p.x(), p.y(), p.z()}; }

// Every k-th point, k the smallest that leaves at most `most`.
std::vector<Eigen::Vector3d> every_kth_point(const std::vector<Point_3>& points, std::size_t most) {
  const std::size_t k = (points.size() + most - 1) / most;
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < points.size(); i += std::max<std::size_t>(k, 1)) out.push_back(eigen_point(points[i]));
  return out;
}

}  // namespace

Point_3 Quadratic_warp::operator()(const Point_3& p) const {
  const Eigen::Vector3d x = eigen_point(p);
  const Warp_basis b = warp_basis((x - eigen_point(centre)) / scale);
  Eigen::Vector3d y = x;
  for (std::size_t m = 0; m < warp_monomials; ++m)
    for (int d = 0; d < 3; ++d) y(d) += coefficients[m][d] * b(m);
  return Point_3(y(0), y(1), y(2));
}

double Quadratic_warp::jacobian_determinant(const Point_3& p) const {
  const Eigen::Matrix<double, warp_monomials, 3> g = warp_basis_gradient((eigen_point(p) - eigen_point(centre)) / scale);
  Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
  for (std::size_t m = 0; m < warp_monomials; ++m)
    for (int d = 0; d < 3; ++d)
      for (int e = 0; e < 3; ++e) J(d, e) += coefficients[m][d] * g(m, e) / scale;
  return J.determinant();
}

std::optional<Quadratic_warp> register_quadratic_warp(const std::vector<Point_3>& template_points,
                                                      const std::vector<Point_3>& network_points,
                                                      const std::vector<std::pair<Point_3, Point_3>>& pairs,
                                                      Registration_report* report) {
  if (template_points.size() < 4 || network_points.size() < 4 || pairs.empty()) return std::nullopt;
  // The frame: the template's centroid and RMS radius, so that a rigid motion or a uniform
  // scaling of the template gives the same warp, moved with it.
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const Point_3& p : template_points) c += eigen_point(p);
  c /= static_cast<double>(template_points.size());
  double s2 = 0;
  for (const Point_3& p : template_points) s2 += (eigen_point(p) - c).squaredNorm();
  const double s = std::sqrt(s2 / static_cast<double>(template_points.size()));
  if (!(s > 0) || !std::isfinite(s)) return std::nullopt;

  const std::vector<Eigen::Vector3d> X = every_kth_point(template_points, 3000), Q = every_kth_point(network_points, 3000);
  const std::size_t M = X.size(), N = Q.size();
  // The network's RMS radius: the unit of the mixture's variance and of its uniform term (the
  // template and the network may be in units of their own until the affine start).
  Eigen::Vector3d cq = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& q : Q) cq += q;
  cq /= static_cast<double>(N);
  double sq = 0;
  for (const Eigen::Vector3d& q : Q) sq += (q - cq).squaredNorm();
  sq = std::sqrt(sq / static_cast<double>(N));
  if (!(sq > 0)) return std::nullopt;
  std::vector<Warp_basis> B(M);
  for (std::size_t m = 0; m < M; ++m) B[m] = warp_basis((X[m] - c) / s);
  std::vector<Warp_basis> Bp;
  std::vector<Eigen::Vector3d> pair_offset;
  for (const auto& [from, to] : pairs) {
    Bp.push_back(warp_basis((eigen_point(from) - c) / s));
    pair_offset.push_back(eigen_point(to) - eigen_point(from));
  }
  // The penalty on the quadratic part: its mean square over the template's points, a measure
  // that does not depend on the frame's axes.
  Eigen::Matrix<double, warp_monomials, warp_monomials> penalty = Eigen::Matrix<double, warp_monomials, warp_monomials>::Zero();
  for (const Warp_basis& b : B) penalty.bottomRightCorner<6, 6>() += b.tail<6>() * b.tail<6>().transpose();
  penalty /= static_cast<double>(M);

  // The start: the affine map through the pairs (least squares; the smallest solution when the
  // pairs leave it undetermined).
  Warp_coefficients C = Warp_coefficients::Zero();
  {
    Eigen::MatrixXd A(Bp.size(), 4), R(Bp.size(), 3);
    for (std::size_t k = 0; k < Bp.size(); ++k) A.row(k) = Bp[k].head<4>().transpose(), R.row(k) = pair_offset[k].transpose();
    C.topRows<4>() = A.completeOrthogonalDecomposition().solve(R);
  }
  std::vector<Eigen::Vector3d> Y(M);
  auto warp_points = [&] {
    for (std::size_t m = 0; m < M; ++m) Y[m] = X[m] + C.transpose() * B[m];
  };
  // Each network point's squared distance to its nearest warped template point, and their
  // roots' mean over the network's RMS radius.
  auto nearest_squared = [&] {
    std::vector<double> d(N, std::numeric_limits<double>::infinity());
    for (std::size_t n = 0; n < N; ++n)
      for (const Eigen::Vector3d& y : Y) d[n] = std::min(d[n], (Q[n] - y).squaredNorm());
    return d;
  };
  auto mean_distance = [&](const std::vector<double>& d2) {
    double sum = 0;
    for (double d : d2) sum += std::sqrt(d);
    return sum / static_cast<double>(N) / sq;
  };
  warp_points();
  Registration_report r;
  const std::vector<double> start = nearest_squared();
  r.mean_distance_before = mean_distance(start);
  // The mixture's variance starts at four times the mean squared gap.
  double sigma2 = 0;
  for (double d : start) sigma2 += d;
  sigma2 = 4 * sigma2 / static_cast<double>(N);
  const double sigma2_floor = 1e-10 * sq * sq;
  sigma2 = std::max(sigma2, sigma2_floor);
  const double outlier_weight = 0.1;
  double lambda = 1;
  std::vector<double> P1(M), nearest(N), gaussians(N), total(N);
  // The network points sorted by x, for the windows of the E step.
  std::vector<std::size_t> q_by_x(N);
  for (std::size_t n = 0; n < N; ++n) q_by_x[n] = n;
  std::sort(q_by_x.begin(), q_by_x.end(), [&](std::size_t a, std::size_t b) { return Q[a](0) < Q[b](0); });
  std::vector<double> q_x(N);
  for (std::size_t i = 0; i < N; ++i) q_x[i] = Q[q_by_x[i]](0);
  std::vector<Eigen::Vector3d> PX(M);
  constexpr std::size_t most_iterations = 300;
  for (r.iterations = 1; r.iterations <= most_iterations; ++r.iterations) {
    // E step: the posteriors of the mixture's centres for each network point, accumulated.
    const double outlier = outlier_weight * std::pow(2 * M_PI * sigma2, 1.5) * static_cast<double>(M) /
                           static_cast<double>(N) / (sq * sq * sq);
    // Terms beyond `reach` (below e^-50 of a term at distance 0) are left out: each point meets
    // only the centres within reach, found in a window of the sorted x coordinates.
    const double reach2 = 100 * sigma2, reach = std::sqrt(reach2);
    std::vector<std::size_t> by_x(M);
    for (std::size_t m = 0; m < M; ++m) by_x[m] = m;
    std::sort(by_x.begin(), by_x.end(), [&](std::size_t a, std::size_t b) { return Y[a](0) < Y[b](0); });
    std::vector<double> y_x(M);
    for (std::size_t i = 0; i < M; ++i) y_x[i] = Y[by_x[i]](0);
    // Each network point's nearest squared distance within reach and the sum of its terms (every
    // term scaled by exp(nearest / 2σ²)), then each centre's sums over the points: two passes,
    // each of independent rows, so that the result does not depend on the number of threads.
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t n = 0; n < static_cast<std::ptrdiff_t>(N); ++n) {
      const Eigen::Vector3d& q = Q[static_cast<std::size_t>(n)];
      const std::size_t from = static_cast<std::size_t>(std::lower_bound(y_x.begin(), y_x.end(), q(0) - reach) - y_x.begin());
      double d = std::numeric_limits<double>::infinity();
      for (std::size_t i = from; i < M && y_x[i] <= q(0) + reach; ++i) d = std::min(d, (q - Y[by_x[i]]).squaredNorm());
      double sum = 0;
      if (d <= reach2)
        for (std::size_t i = from; i < M && y_x[i] <= q(0) + reach; ++i) {
          const double e = (q - Y[by_x[i]]).squaredNorm();
          if (e <= reach2) sum += std::exp(-(e - d) / (2 * sigma2));
        }
      nearest[static_cast<std::size_t>(n)] = d;
      gaussians[static_cast<std::size_t>(n)] = sum;
      total[static_cast<std::size_t>(n)] = sum + outlier * std::exp(std::min(d / (2 * sigma2), 700.0));
    }
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t mi = 0; mi < static_cast<std::ptrdiff_t>(M); ++mi) {
      const std::size_t m = static_cast<std::size_t>(mi);
      double p1 = 0;
      Eigen::Vector3d px = Eigen::Vector3d::Zero();
      const std::size_t from =
          static_cast<std::size_t>(std::lower_bound(q_x.begin(), q_x.end(), Y[m](0) - reach) - q_x.begin());
      for (std::size_t i = from; i < N && q_x[i] <= Y[m](0) + reach; ++i) {
        const std::size_t n = q_by_x[i];
        const double e = (Q[n] - Y[m]).squaredNorm();
        if (e > reach2 || !(nearest[n] <= reach2)) continue;
        const double p = std::exp(-(e - nearest[n]) / (2 * sigma2)) / total[n];
        p1 += p;
        px += p * Q[n];
      }
      P1[m] = p1;
      PX[m] = px;
    }
    double np = 0, q2 = 0;
    for (std::size_t n = 0; n < N; ++n) {
      const double pq = gaussians[n] / total[n];
      np += pq;
      q2 += pq * Q[n].squaredNorm();
    }
    if (!(np > 0)) break;
    // M step: C by weighted least squares, the pairs weighing as much as all points together.
    const double w = np / static_cast<double>(Bp.size());
    Eigen::Matrix<double, warp_monomials, warp_monomials> A = lambda * np * penalty;
    Warp_coefficients rhs = Warp_coefficients::Zero();
    for (std::size_t m = 0; m < M; ++m) {
      A += P1[m] * B[m] * B[m].transpose();
      rhs += B[m] * (PX[m] - P1[m] * X[m]).transpose();
    }
    for (std::size_t k = 0; k < Bp.size(); ++k) {
      A += w * Bp[k] * Bp[k].transpose();
      rhs += w * Bp[k] * pair_offset[k].transpose();
    }
    const Warp_coefficients next = A.ldlt().solve(rhs);
    if (!next.allFinite()) break;
    C = next;
    warp_points();
    // The variance: Σ P |q − y|² / 3 Np, from the sums already made.
    double spread = q2;
    for (std::size_t m = 0; m < M; ++m) spread += -2 * Y[m].dot(PX[m]) + P1[m] * Y[m].squaredNorm();
    const double updated = std::max(spread / (3 * np), sigma2_floor);
    lambda *= 0.9;
    const bool settled = std::abs(updated - sigma2) <= 1e-6 * sigma2 && lambda < 1e-6;
    sigma2 = updated;
    if (settled) break;
  }
  r.iterations = std::min(r.iterations, most_iterations);  // the loop's count, not one past it
  r.final_sigma = std::sqrt(sigma2) / sq;
  r.mean_distance_after = mean_distance(nearest_squared());
  Quadratic_warp W;
  W.centre = Point_3(c(0), c(1), c(2));
  W.scale = s;
  for (std::size_t m = 0; m < warp_monomials; ++m)
    for (int d = 0; d < 3; ++d) W.coefficients[m][d] = C(m, d);
  r.turns_over = std::any_of(template_points.begin(), template_points.end(),
                             [&](const Point_3& p) { return !(W.jacobian_determinant(p) > 0); });
  if (report) *report = r;
  if (r.turns_over) return std::nullopt;
  return W;
}

}  // namespace meshfit
