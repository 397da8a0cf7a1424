#include <meshfit/registration.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace meshfit_registration_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using meshfit::Point_3;
using meshfit::Vector_3;

namespace {

const double pi = std::acos(-1.0);

// A known warp, written out on its own (not through Quadratic_warp): an anisotropic scale, a
// bend along x of 0.3 z², a shear of 0.2 x y into z, a rotation about z by `turn` and a shift.
Point_3 truth(const Point_3& p, double turn = 0.7) {
  const double x = 1.2 * p.x() + 0.3 * p.z() * p.z(), y = 0.9 * p.y(), z = 1.05 * p.z() + 0.2 * p.x() * p.y();
  return Point_3(std::cos(turn) * x - std::sin(turn) * y + 3, std::sin(turn) * x + std::cos(turn) * y - 1, z + 2);
}

// The template: 2000 points spread over the unit sphere (a Fibonacci spiral).
std::vector<Point_3> sphere_points(std::size_t n = 2000) {
  std::vector<Point_3> points;
  const double golden = pi * (3 - std::sqrt(5.0));
  for (std::size_t i = 0; i < n; ++i) {
    const double z = 1 - 2 * (static_cast<double>(i) + 0.5) / static_cast<double>(n), r = std::sqrt(1 - z * z);
    points.emplace_back(r * std::cos(golden * static_cast<double>(i)), r * std::sin(golden * static_cast<double>(i)), z);
  }
  return points;
}

// The network: three great circles of the unit sphere (x = 0, y = 0, z = 0), 150 points each at
// angles that are no template point's, carried by the known warp.
std::vector<Point_3> circle_points() {
  std::vector<Point_3> points;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 150; ++k) {
      const double a = 2 * pi * (k + 0.37) / 150, u = std::cos(a), v = std::sin(a);
      const Point_3 p = c == 0 ? Point_3(0, u, v) : c == 1 ? Point_3(u, 0, v) : Point_3(u, v, 0);
      points.push_back(truth(p));
    }
  return points;
}

// Six pairs: the circles' crossings (±x, ±y, ±z) and where the known warp takes them.
std::vector<std::pair<Point_3, Point_3>> crossing_pairs() {
  std::vector<std::pair<Point_3, Point_3>> pairs;
  for (const Point_3& p : {Point_3(1, 0, 0), Point_3(-1, 0, 0), Point_3(0, 1, 0), Point_3(0, -1, 0), Point_3(0, 0, 1),
                           Point_3(0, 0, -1)})
    pairs.emplace_back(p, truth(p));
  return pairs;
}

// The largest and the mean distance from W(p) to the known warp's image of p, over the
// template's points.
struct Errors {
  double largest = 0, mean = 0;
};
template <typename Map>
Errors errors(const Map& map, const std::vector<Point_3>& points) {
  Errors e;
  for (const Point_3& p : points) {
    const double d = std::sqrt(CGAL::squared_distance(map(p), truth(p)));
    e.largest = std::max(e.largest, d);
    e.mean += d / static_cast<double>(points.size());
  }
  return e;
}

// The affine map through the pairs (least squares), the registration's start, worked out on its
// own: the six crossings are symmetric about the origin, so its linear part takes e_i to
// (W(e_i) − W(−e_i)) / 2 and its shift is the mean of the six images. The known warp's affine
// part is not it: the bend and the shear move the crossings too.
Point_3 affine_start(const Point_3& p) {
  const auto pairs = crossing_pairs();
  Vector_3 shift(0, 0, 0);
  for (const auto& pr : pairs) shift = shift + (pr.second - CGAL::ORIGIN) / 6.0;
  const Vector_3 ex = (pairs[0].second - pairs[1].second) / 2, ey = (pairs[2].second - pairs[3].second) / 2,
                 ez = (pairs[4].second - pairs[5].second) / 2;
  return CGAL::ORIGIN + shift + p.x() * ex + p.y() * ey + p.z() * ez;
}
Errors affine_start_errors(const std::vector<Point_3>& points) { return errors(affine_start, points); }

}  // namespace

TEST_CASE("registration: a quadratic warp of a sphere is recovered from three of its great circles and six pairs",
          "[registration]") {
  const std::vector<Point_3> points = sphere_points();
  const std::vector<Point_3> network = circle_points();
  meshfit::Registration_report report;
  const std::optional<meshfit::Quadratic_warp> warp =
      meshfit::register_quadratic_warp(points, network, crossing_pairs(), &report);
  REQUIRE(warp);
  const Errors start = affine_start_errors(points), after = errors(*warp, points);
  // The bend and the shear, unseen by an affine map through the pairs: the warp brings the
  // template towards the known one, though not onto it (three circles leave some quadratic maps
  // of the sphere nearly free: those that slide it along itself near them).
  CHECK(start.largest > 0.15);
  CHECK(start.mean > 0.05);
  CHECK(after.largest < 0.6 * start.largest);
  CHECK(after.mean < 0.6 * start.mean);
  // What the curves do determine: the network points end near the warped sphere (sampled ten
  // times more densely than the template), much nearer than after the affine start.
  const std::vector<Point_3> dense = sphere_points(20000);
  auto mean_gap = [&](const auto& map) {
    double sum = 0;
    for (const Point_3& q : network) {
      double best = std::numeric_limits<double>::infinity();
      for (const Point_3& p : dense) best = std::min(best, CGAL::squared_distance(q, map(p)));
      sum += std::sqrt(best) / static_cast<double>(network.size());
    }
    return sum;
  };
  const double gap_before = mean_gap(affine_start), gap_after = mean_gap(*warp);
  CHECK(gap_after < 0.4 * gap_before);
  CHECK(report.iterations > 1);
  CHECK(report.mean_distance_after < report.mean_distance_before);
  for (const Point_3& p : points) CHECK(warp->jacobian_determinant(p) > 0);
}

TEST_CASE("registration: a rigid motion and a uniform scaling of the template move the warped points with it",
          "[registration]") {
  const std::vector<Point_3> points = sphere_points(), network = circle_points();
  const auto pairs = crossing_pairs();
  const std::optional<meshfit::Quadratic_warp> warp = meshfit::register_quadratic_warp(points, network, pairs);
  REQUIRE(warp);
  // The template turned by 2.1 rad about (1, 2, 2) / 3 and scaled by 1e-3, then also moved by
  // 1e6 (the network and the pairs' targets stay): W'(M p) must be W(p), to rounding.
  const Vector_3 k(1.0 / 3, 2.0 / 3, 2.0 / 3);
  const double a = 2.1, s = 1e-3;
  for (const double shift : {0.0, 1e6}) {
    auto move = [&](const Point_3& p) {
      const Vector_3 v = p - CGAL::ORIGIN;
      const Vector_3 r = std::cos(a) * v + std::sin(a) * CGAL::cross_product(k, v) + (1 - std::cos(a)) * (k * v) * k;
      return CGAL::ORIGIN + s * r + Vector_3(shift, shift, shift);
    };
    std::vector<Point_3> moved;
    for (const Point_3& p : points) moved.push_back(move(p));
    std::vector<std::pair<Point_3, Point_3>> moved_pairs;
    for (const auto& pr : pairs) moved_pairs.emplace_back(move(pr.first), pr.second);
    const std::optional<meshfit::Quadratic_warp> other = meshfit::register_quadratic_warp(moved, network, moved_pairs);
    REQUIRE(other);
    double largest = 0;
    for (std::size_t i = 0; i < points.size(); ++i)
      largest = std::max(largest, std::sqrt(CGAL::squared_distance((*warp)(points[i]), (*other)(moved[i]))));
    // The warped template is about 3 across. Moved by 1e6, the template's coordinates carry
    // 1e-10 of rounding on a size of 1e-3: 1e-7 of it, which the fit carries through.
    INFO("shift " << shift);
    CHECK(largest < (shift == 0 ? 3e-9 : 3e-6));
  }
}

TEST_CASE("registration: pairs that mirror the template give no warp, nor do too few points or no pair",
          "[registration]") {
  const std::vector<Point_3> points = sphere_points(), network = circle_points();
  // The template seen in a mirror (x -> -x) with the same targets: the only maps through the
  // pairs turn space over.
  std::vector<Point_3> mirrored;
  for (const Point_3& p : points) mirrored.emplace_back(-p.x(), p.y(), p.z());
  std::vector<std::pair<Point_3, Point_3>> mirrored_pairs;
  for (const auto& pr : crossing_pairs()) mirrored_pairs.emplace_back(Point_3(-pr.first.x(), pr.first.y(), pr.first.z()), pr.second);
  meshfit::Registration_report report;
  CHECK(!meshfit::register_quadratic_warp(mirrored, network, mirrored_pairs, &report));
  CHECK(report.turns_over);
  CHECK(report.iterations > 0);
  CHECK(!meshfit::register_quadratic_warp(points, network, {}));
  CHECK(!meshfit::register_quadratic_warp({points[0], points[1], points[2]}, network, crossing_pairs()));
  CHECK(!meshfit::register_quadratic_warp(points, {network[0], network[1]}, crossing_pairs()));
}

}  // namespace meshfit_registration_test
