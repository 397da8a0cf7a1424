// register_quadratic_warp (registration.h): Coherent Point Drift and closest-point fits of a quadratic warp.
#include <meshfit/registration.h>

#include <meshfit/exceptions.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/property_map.h>
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

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

// The smallest k for which every k-th of n items leaves at most `most` (at least 1).
std::size_t kth_stride(std::size_t n, std::size_t most) { return std::max<std::size_t>((n + most - 1) / most, 1); }

// Every k-th point, k = kth_stride(points.size(), most).
std::vector<Eigen::Vector3d> every_kth_point(const std::vector<Point_3>& points, std::size_t most) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < points.size(); i += kth_stride(points.size(), most)) out.push_back(eigen_point(points[i]));
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

namespace {

using Penalty = Eigen::Matrix<double, warp_monomials, warp_monomials>;

// What the fits share: the template's frame (its centroid c and RMS radius s), the network's RMS
// radius sq (the unit of distances), the pairs' monomials and offsets, the penalty on the
// quadratic part (its mean square over the template's points, a measure that does not depend on
// the frame's axes) and the start, the affine map through the pairs (least squares; the smallest
// solution when the pairs leave it undetermined).
struct Fit_setup {
  Eigen::Vector3d c;
  double s = 0;
  double sq = 0;
  std::vector<Eigen::Vector3d> network;  // at most 3000
  std::vector<Warp_basis> Bp;
  std::vector<Eigen::Vector3d> pair_offset;
  Penalty penalty = Penalty::Zero();
  Warp_coefficients start = Warp_coefficients::Zero();

  Warp_basis basis(const Eigen::Vector3d& x) const { return warp_basis((x - c) / s); }
};

Quadratic_warp warp_of(const Fit_setup& f, const Warp_coefficients& C) {
  Quadratic_warp W;
  W.centre = Point_3(f.c(0), f.c(1), f.c(2));
  W.scale = f.s;
  for (std::size_t m = 0; m < warp_monomials; ++m)
    for (int d = 0; d < 3; ++d) W.coefficients[m][d] = C(m, d);
  return W;
}

// Coherent Point Drift from f.start on X (at most 3000 template points); the EM iterations and
// the mixture's final standard deviation (over sq) go to r.
Warp_coefficients coherent_point_drift(const Fit_setup& f, const std::vector<Eigen::Vector3d>& X, Registration_report& r) {
  const std::vector<Eigen::Vector3d>& Q = f.network;
  const std::size_t M = X.size(), N = Q.size();
  const double sq = f.sq;
  std::vector<Warp_basis> B(M);
  for (std::size_t m = 0; m < M; ++m) B[m] = f.basis(X[m]);
  Warp_coefficients C = f.start;
  std::vector<Eigen::Vector3d> Y(M);
  auto warp_points = [&] {
    for (std::size_t m = 0; m < M; ++m) Y[m] = X[m] + C.transpose() * B[m];
  };
  warp_points();
  // The mixture's variance starts at four times the mean squared gap.
  double sigma2 = 0;
  for (const Eigen::Vector3d& q : Q) {
    double d = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& y : Y) d = std::min(d, (q - y).squaredNorm());
    sigma2 += d;
  }
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
    const double w = np / static_cast<double>(f.Bp.size());
    Eigen::Matrix<double, warp_monomials, warp_monomials> A = lambda * np * f.penalty;
    Warp_coefficients rhs = Warp_coefficients::Zero();
    for (std::size_t m = 0; m < M; ++m) {
      A += P1[m] * B[m] * B[m].transpose();
      rhs += B[m] * (PX[m] - P1[m] * X[m]).transpose();
    }
    for (std::size_t k = 0; k < f.Bp.size(); ++k) {
      A += w * f.Bp[k] * f.Bp[k].transpose();
      rhs += w * f.Bp[k] * f.pair_offset[k].transpose();
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
  return C;
}

// Point-to-plane closest-point matching (ICP) from f.start: each network point is matched with
// the warped template point nearest to it, and the warp is fitted so that the network point lies
// in the tangent plane there (the template's normal carried by the warp's Jacobian: cofactor
// times normal), with a small pull towards the point itself (α, falling from 0.3 to 0.01) and the
// pairs weighing `pair_weight` times all matches together; the quadratic part is penalised with
// a weight that falls from 1 to 1e-3 over the iterations. With `reject`, matches farther than
// three times the median are left out. X: at most 20000 template points, `normals` their unit
// normals on the template. At most 150 iterations; the fit ends earlier when, the weights at
// their floors, an iteration matches and leaves out as the one before did.
Warp_coefficients closest_point_fit(const Fit_setup& f, const std::vector<Eigen::Vector3d>& X,
                                    const std::vector<Eigen::Vector3d>& normals, double pair_weight, bool reject,
                                    std::size_t& iterations) {
  using Base_traits = CGAL::Search_traits_3<Kernel>;
  using Point_map = CGAL::Pointer_property_map<Point_3>::type;
  using Traits = CGAL::Search_traits_adapter<std::size_t, Point_map, Base_traits>;
  using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;
  using Tree = Search::Tree;
  const std::vector<Eigen::Vector3d>& Q = f.network;
  const std::size_t M = X.size(), N = Q.size();
  std::vector<Warp_basis> B(M);
  for (std::size_t m = 0; m < M; ++m) B[m] = f.basis(X[m]);
  std::vector<std::size_t> index(M);
  for (std::size_t m = 0; m < M; ++m) index[m] = m;
  Warp_coefficients C = f.start;
  std::vector<Point_3> Y(M);
  std::vector<std::size_t> match(N), previous_match;
  std::vector<double> gap(N);
  std::vector<bool> used(N), previous_used;
  using Normal_matrix = Eigen::Matrix<double, 3 * warp_monomials, 3 * warp_monomials>;
  using Normal_vector = Eigen::Matrix<double, 3 * warp_monomials, 1>;
  constexpr std::size_t most_iterations = 150;
  for (iterations = 1; iterations <= most_iterations; ++iterations) {
    for (std::size_t m = 0; m < M; ++m) {
      const Eigen::Vector3d y = X[m] + C.transpose() * B[m];
      Y[m] = Point_3(y(0), y(1), y(2));
    }
    const Point_map point_map(Y.data());
    Tree tree(index.begin(), index.end(), Tree::Splitter(), Traits(point_map));
    tree.build();
    const Search::Distance distance(point_map);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t n = 0; n < static_cast<std::ptrdiff_t>(N); ++n) {
      const Eigen::Vector3d& q = Q[static_cast<std::size_t>(n)];
      const Search search(tree, Point_3(q(0), q(1), q(2)), 1, 0, true, distance);
      match[static_cast<std::size_t>(n)] = search.begin()->first;
      gap[static_cast<std::size_t>(n)] = search.begin()->second;
    }
    double limit = std::numeric_limits<double>::infinity();
    if (reject) {
      std::vector<double> sorted = gap;
      std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(N / 2), sorted.end());
      limit = 9 * sorted[N / 2];  // squared distances: three times the median distance
    }
    const double k = static_cast<double>(iterations - 1);
    const double alpha = std::max(0.3 * std::pow(0.85, k), 0.01), lambda = std::max(std::pow(0.9, k), 1e-3);
    Normal_matrix A = Normal_matrix::Zero();
    Normal_vector rhs = Normal_vector::Zero();
    std::size_t kept = 0;
    for (std::size_t n = 0; n < N; ++n) {
      used[n] = false;
      if (!(gap[n] <= limit)) continue;
      const std::size_t m = match[n];
      // The normal carried by the warp: cof J n = det J J⁻ᵀ n.
      const Eigen::Matrix<double, warp_monomials, 3> g = warp_basis_gradient((X[m] - f.c) / f.s);
      const Eigen::Matrix3d J = Eigen::Matrix3d::Identity() + C.transpose() * g / f.s;
      Eigen::Vector3d nm = J.determinant() * J.inverse().transpose() * normals[m];
      const double length = nm.norm();
      if (!(length > 0) || !std::isfinite(length)) continue;
      nm /= length;
      const Eigen::Vector3d offset = Q[n] - X[m];
      Normal_vector a;
      for (int d = 0; d < 3; ++d) a.segment<warp_monomials>(d * warp_monomials) = nm(d) * B[m];
      A += a * a.transpose();
      rhs += a * offset.dot(nm);
      const Eigen::Matrix<double, warp_monomials, warp_monomials> bb = alpha * B[m] * B[m].transpose();
      for (int d = 0; d < 3; ++d) {
        A.block<warp_monomials, warp_monomials>(d * warp_monomials, d * warp_monomials) += bb;
        rhs.segment<warp_monomials>(d * warp_monomials) += alpha * offset(d) * B[m];
      }
      used[n] = true;
      ++kept;
    }
    if (kept == 0) break;
    const double w = pair_weight * static_cast<double>(kept) / static_cast<double>(f.Bp.size());
    for (int d = 0; d < 3; ++d) {
      auto block = A.block<warp_monomials, warp_monomials>(d * warp_monomials, d * warp_monomials);
      block += lambda * static_cast<double>(kept) * f.penalty;
      for (std::size_t p = 0; p < f.Bp.size(); ++p) {
        block += w * f.Bp[p] * f.Bp[p].transpose();
        rhs.segment<warp_monomials>(d * warp_monomials) += w * f.pair_offset[p](d) * f.Bp[p];
      }
    }
    // Once the weights are at their floors, the same matches (and the same left out) give the
    // same system but for the normals' turn with the warp: the fit has settled.
    const bool floors = lambda <= 1e-3 && alpha <= 0.01;
    if (floors && match == previous_match && used == previous_used) break;
    previous_match = match;
    previous_used = used;
    const Normal_vector z = A.ldlt().solve(rhs);
    if (!z.allFinite()) break;
    for (int d = 0; d < 3; ++d) C.col(d) = z.segment<warp_monomials>(d * warp_monomials);
  }
  iterations = std::min(iterations, most_iterations);
  return C;
}

// The mean distance of the network points to the template's triangles warped by W (to the
// nearest of at most 3000 warped points when there are no triangles), over the network's RMS
// radius.
double mean_distance_after_warp(const Fit_setup& f, const std::vector<Point_3>& points,
                                const std::vector<std::array<std::size_t, 3>>& triangles, const Quadratic_warp& W) {
  std::vector<Point_3> moved(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) moved[i] = W(points[i]);
  double sum = 0;
  if (triangles.empty()) {
    const std::vector<Eigen::Vector3d> sample = every_kth_point(moved, 3000);
    for (const Eigen::Vector3d& q : f.network) {
      double d = std::numeric_limits<double>::infinity();
      for (const Eigen::Vector3d& y : sample) d = std::min(d, (y - q).squaredNorm());
      sum += std::sqrt(d);
    }
  } else {
    std::vector<Kernel::Triangle_3> soup;
    for (const auto& t : triangles)
      if (!CGAL::collinear(moved[t[0]], moved[t[1]], moved[t[2]])) soup.emplace_back(moved[t[0]], moved[t[1]], moved[t[2]]);
    if (soup.empty()) return std::numeric_limits<double>::infinity();
    using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Kernel::Triangle_3>::const_iterator>;
    CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>> tree(soup.begin(), soup.end());
    tree.accelerate_distance_queries();
    for (const Eigen::Vector3d& q : f.network) sum += std::sqrt(tree.squared_distance(Point_3(q(0), q(1), q(2))));
  }
  return sum / static_cast<double>(f.network.size()) / f.sq;
}

}  // namespace

std::optional<Quadratic_warp> register_quadratic_warp(const std::vector<Point_3>& template_points,
                                                      const std::vector<std::array<std::size_t, 3>>& triangles,
                                                      const std::vector<Point_3>& network_points,
                                                      const std::vector<std::pair<Point_3, Point_3>>& pairs,
                                                      const std::vector<double>& pair_tolerances,
                                                      Registration_report* report,
                                                      std::optional<Quadratic_warp>* drift_warp) {
  if (drift_warp) drift_warp->reset();
  if (template_points.size() < 4 || network_points.size() < 4 || pairs.empty()) return std::nullopt;
  if (!pair_tolerances.empty() && pair_tolerances.size() != pairs.size())
    throw Invalid_input("register_quadratic_warp: " + std::to_string(pair_tolerances.size()) + " pair tolerances for " +
                        std::to_string(pairs.size()) + " pairs");
  for (const auto& t : triangles)
    for (std::size_t i : t)
      if (i >= template_points.size()) throw Invalid_input("register_quadratic_warp: triangle corner " + std::to_string(i) + " is out of range (" +
                            std::to_string(template_points.size()) + " template points)");
  // The frame: the template's centroid and RMS radius, so that a rigid motion or a uniform
  // scaling of the template gives the same warp, moved with it.
  Fit_setup f;
  f.c = Eigen::Vector3d::Zero();
  for (const Point_3& p : template_points) f.c += eigen_point(p);
  f.c /= static_cast<double>(template_points.size());
  double s2 = 0;
  for (const Point_3& p : template_points) s2 += (eigen_point(p) - f.c).squaredNorm();
  f.s = std::sqrt(s2 / static_cast<double>(template_points.size()));
  if (!(f.s > 0) || !std::isfinite(f.s)) return std::nullopt;
  f.network = every_kth_point(network_points, 3000);
  // The network's RMS radius: the unit of the mixture's variance and of the distances reported
  // (the template and the network may be in units of their own until the affine start).
  Eigen::Vector3d cq = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& q : f.network) cq += q;
  cq /= static_cast<double>(f.network.size());
  for (const Eigen::Vector3d& q : f.network) f.sq += (q - cq).squaredNorm();
  f.sq = std::sqrt(f.sq / static_cast<double>(f.network.size()));
  if (!(f.sq > 0)) return std::nullopt;
  for (const auto& [from, to] : pairs) {
    f.Bp.push_back(f.basis(eigen_point(from)));
    f.pair_offset.push_back(eigen_point(to) - eigen_point(from));
  }
  const std::vector<Eigen::Vector3d> X = every_kth_point(template_points, 3000);
  for (const Eigen::Vector3d& x : X) {
    const Warp_basis b = f.basis(x);
    f.penalty.bottomRightCorner<6, 6>() += b.tail<6>() * b.tail<6>().transpose();
  }
  f.penalty /= static_cast<double>(X.size());
  {
    Eigen::MatrixXd A(f.Bp.size(), 4), R(f.Bp.size(), 3);
    for (std::size_t k = 0; k < f.Bp.size(); ++k) A.row(k) = f.Bp[k].head<4>().transpose(), R.row(k) = f.pair_offset[k].transpose();
    f.start.topRows<4>() = A.completeOrthogonalDecomposition().solve(R);
  }
  if (!f.start.allFinite()) return std::nullopt;  // a pair's point not finite
  auto turns_over = [&](const Quadratic_warp& W) {
    return std::any_of(template_points.begin(), template_points.end(),
                       [&](const Point_3& p) { return !(W.jacobian_determinant(p) > 0); });
  };

  // Whether W takes every pair's template point to within its tolerance of its network point,
  // the tolerance scaled by W's local change of length there (the cube root of det ∂W/∂x).
  auto keeps_pairs = [&](const Quadratic_warp& W) {
    for (std::size_t k = 0; k < pair_tolerances.size(); ++k) {
      const Point_3& p = pairs[k].first;
      const double reach = pair_tolerances[k] * std::cbrt(W.jacobian_determinant(p));
      if (!(std::sqrt(CGAL::squared_distance(W(p), pairs[k].second)) <= reach)) return false;
    }
    return true;
  };

  Registration_report r;
  r.mean_distance_before = mean_distance_after_warp(f, template_points, triangles, warp_of(f, f.start));
  std::optional<Quadratic_warp> best;
  bool best_keeps_pairs = false;
  auto consider = [&](const Warp_coefficients& C, Registration_method method, double pair_weight, bool reject) {
    const Quadratic_warp W = warp_of(f, C);
    ++r.candidates;
    if (turns_over(W)) {
      ++r.candidates_turning_over;
      return;
    }
    const bool kept = keeps_pairs(W);
    r.candidates_keeping_pairs += kept;
    const double d = mean_distance_after_warp(f, template_points, triangles, W);
    if (best && (best_keeps_pairs > kept || (best_keeps_pairs == kept && !(d < r.mean_distance_after)))) return;
    best = W;
    best_keeps_pairs = kept;
    r.mean_distance_after = d;
    r.method = method;
    r.pair_weight = pair_weight;
    r.far_matches_left_out = reject;
  };
  consider(coherent_point_drift(f, X, r), Registration_method::coherent_point_drift, 1, false);
  if (drift_warp) *drift_warp = best;
  // Closest-point fits need the template's normals: from its triangles (area-weighted).
  if (!triangles.empty()) {
    std::vector<Eigen::Vector3d> normal(template_points.size(), Eigen::Vector3d::Zero());
    for (const auto& t : triangles) {
      const Eigen::Vector3d a = eigen_point(template_points[t[0]]), b = eigen_point(template_points[t[1]]),
                            c = eigen_point(template_points[t[2]]);
      const Eigen::Vector3d n = (b - a).cross(c - a);
      for (std::size_t i : t) normal[i] += n;
    }
    std::vector<Point_3> with_normal;
    std::vector<Eigen::Vector3d> Nn;
    for (std::size_t i = 0; i < template_points.size(); ++i)
      if (normal[i].norm() > 0 && std::isfinite(normal[i].norm())) with_normal.push_back(template_points[i]), Nn.push_back(normal[i].normalized());
    const std::vector<Eigen::Vector3d> Xs = every_kth_point(with_normal, 20000);
    std::vector<Eigen::Vector3d> Ns;
    for (std::size_t i = 0; i < with_normal.size(); i += kth_stride(with_normal.size(), 20000)) Ns.push_back(Nn[i]);
    if (Xs.size() >= 4) {
      // Pairs as a user gives them (a template vertex near the curve point, not at its exact
      // preimage) pull the warp off the curves when they weigh as much as all matches: weights
      // from 1 down to 1/100 are tried, and every match kept or the far ones left out at weight 1.
      const std::array<std::pair<double, bool>, 4> settings = {{{1, true}, {1, false}, {0.1, false}, {0.01, false}}};
      for (const auto& [weight, reject] : settings) {
        std::size_t iterations = 0;
        const Warp_coefficients C = closest_point_fit(f, Xs, Ns, weight, reject, iterations);
        r.closest_point_iterations += iterations;
        consider(C, Registration_method::closest_point, weight, reject);
      }
    }
  }
  r.turns_over = !best;
  if (report) *report = r;
  return best;
}

}  // namespace meshfit
