#include <meshfit/exceptions.h>
#include <meshfit/registration.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
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

// The network points' mean distance to the unit sphere carried by `map`, the sphere sampled ten
// times more densely than the template (20000 points).
template <typename Map>
double mean_gap(const Map& map, const std::vector<Point_3>& network) {
  static const std::vector<Point_3> dense = sphere_points(20000);
  double sum = 0;
  for (const Point_3& q : network) {
    double best = std::numeric_limits<double>::infinity();
    for (const Point_3& p : dense) best = std::min(best, CGAL::squared_distance(q, map(p)));
    sum += std::sqrt(best) / static_cast<double>(network.size());
  }
  return sum;
}

// A latitude-longitude sphere as a triangle mesh: `rings` circles of latitude strictly between
// the poles, `around` points on each, shifted by half a step so that no point lies on the planes
// x = 0 or y = 0 (the crossings ±x, ±y of the circles are no vertex), and the two poles.
struct Sphere_mesh {
  std::vector<Point_3> points;
  std::vector<std::array<std::size_t, 3>> triangles;
};
Sphere_mesh sphere_mesh(std::size_t rings = 30, std::size_t around = 64) {
  Sphere_mesh m;
  for (std::size_t r = 0; r < rings; ++r) {
    const double polar = pi * (static_cast<double>(r) + 1) / (static_cast<double>(rings) + 1);
    for (std::size_t k = 0; k < around; ++k) {
      const double a = 2 * pi * (static_cast<double>(k) + 0.5) / static_cast<double>(around);
      m.points.emplace_back(std::sin(polar) * std::cos(a), std::sin(polar) * std::sin(a), std::cos(polar));
    }
  }
  const std::size_t north = m.points.size(), south = north + 1;
  m.points.emplace_back(0, 0, 1);
  m.points.emplace_back(0, 0, -1);
  auto at = [&](std::size_t r, std::size_t k) { return r * around + k % around; };
  for (std::size_t k = 0; k < around; ++k) {
    m.triangles.push_back({north, at(0, k), at(0, k + 1)});
    m.triangles.push_back({south, at(rings - 1, k + 1), at(rings - 1, k)});
    for (std::size_t r = 0; r + 1 < rings; ++r) {
      m.triangles.push_back({at(r, k), at(r + 1, k), at(r + 1, k + 1)});
      m.triangles.push_back({at(r, k), at(r + 1, k + 1), at(r, k + 1)});
    }
  }
  return m;
}

}  // namespace

TEST_CASE("registration: a quadratic warp of a sphere is recovered from three of its great circles and six pairs",
          "[registration]") {
  const std::vector<Point_3> points = sphere_points();
  const std::vector<Point_3> network = circle_points();
  meshfit::Registration_report report;
  const std::optional<meshfit::Quadratic_warp> warp =
      meshfit::register_quadratic_warp(points, {}, network, crossing_pairs(), {}, &report);
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
  const double gap_before = mean_gap(affine_start, network), gap_after = mean_gap(*warp, network);
  CHECK(gap_after < 0.4 * gap_before);
  CHECK(report.iterations > 1);
  CHECK(report.mean_distance_after < report.mean_distance_before);
  for (const Point_3& p : points) CHECK(warp->jacobian_determinant(p) > 0);
}

TEST_CASE("registration: a rigid motion and a uniform scaling of the template move the warped points with it",
          "[registration]") {
  // Coherent Point Drift alone (no triangles), and with the closest-point fits of a sphere mesh.
  const bool with_triangles = GENERATE(false, true);
  const Sphere_mesh m = sphere_mesh();
  const std::vector<Point_3> points = with_triangles ? m.points : sphere_points(), network = circle_points();
  const std::vector<std::array<std::size_t, 3>> triangles = with_triangles ? m.triangles : std::vector<std::array<std::size_t, 3>>{};
  const auto pairs = crossing_pairs();
  meshfit::Registration_report report;
  const std::optional<meshfit::Quadratic_warp> warp =
      meshfit::register_quadratic_warp(points, triangles, network, pairs, {}, &report);
  REQUIRE(warp);
  // With triangles, the warp compared is a closest-point fit's.
  CHECK(report.method == (with_triangles ? meshfit::Registration_method::closest_point
                                         : meshfit::Registration_method::coherent_point_drift));
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
    const std::optional<meshfit::Quadratic_warp> other = meshfit::register_quadratic_warp(moved, triangles, network, moved_pairs);
    REQUIRE(other);
    double largest = 0;
    for (std::size_t i = 0; i < points.size(); ++i)
      largest = std::max(largest, std::sqrt(CGAL::squared_distance((*warp)(points[i]), (*other)(moved[i]))));
    // The warped template is about 3 across. Moved by 1e6, the template's coordinates carry
    // 1e-10 of rounding on a size of 1e-3: 1e-7 of it, which the fit carries through.
    INFO("shift " << shift << (with_triangles ? ", with triangles" : ""));
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
  CHECK(!meshfit::register_quadratic_warp(mirrored, {}, network, mirrored_pairs, {}, &report));
  CHECK(report.turns_over);
  CHECK(report.iterations > 0);
  CHECK(!meshfit::register_quadratic_warp(points, {}, network, {}));
  CHECK(!meshfit::register_quadratic_warp({points[0], points[1], points[2]}, {}, network, crossing_pairs()));
  CHECK(!meshfit::register_quadratic_warp(points, {}, {network[0], network[1]}, crossing_pairs()));
}

TEST_CASE("registration: with the template's triangles, pairs at the template vertices nearest the crossings and their "
          "tolerances, closest-point fits bring the sphere nearer the known warp",
          "[registration]") {
  const Sphere_mesh m = sphere_mesh();
  const std::vector<Point_3> network = circle_points();
  // The pairs a user would give: the template vertex nearest each crossing, paired with the
  // crossing's image; the tolerance, the mean length of the vertex's edges.
  std::vector<std::pair<Point_3, Point_3>> pairs;
  std::vector<double> tolerance;
  for (const auto& [crossing, image] : crossing_pairs()) {
    std::size_t nearest = 0;
    for (std::size_t i = 1; i < m.points.size(); ++i)
      if (CGAL::squared_distance(m.points[i], crossing) < CGAL::squared_distance(m.points[nearest], crossing)) nearest = i;
    pairs.emplace_back(m.points[nearest], image);
    double length = 0, edges = 0;
    for (const auto& t : m.triangles)
      for (int c = 0; c < 3; ++c)
        if (t[c] == nearest) {
          length += std::sqrt(CGAL::squared_distance(m.points[t[c]], m.points[t[(c + 1) % 3]]));
          edges += 1;
        }
    tolerance.push_back(length / edges);
  }
  meshfit::Registration_report drift, both;
  const std::optional<meshfit::Quadratic_warp> drift_only =
      meshfit::register_quadratic_warp(m.points, {}, network, pairs, tolerance, &drift);
  const std::optional<meshfit::Quadratic_warp> warp =
      meshfit::register_quadratic_warp(m.points, m.triangles, network, pairs, tolerance, &both);
  REQUIRE(drift_only);
  REQUIRE(warp);
  CHECK(drift.candidates == 1);
  CHECK(drift.closest_point_iterations == 0);
  CHECK(both.candidates == 5);
  CHECK(both.candidates_turning_over == 0);
  CHECK(both.closest_point_iterations > 0);
  CHECK(both.method == meshfit::Registration_method::closest_point);
  // Against the known warp, over the template's points: the sphere can slide along itself near
  // three circles, so neither fit finds the warp, and the closest-point fit is a little nearer.
  const Errors start = affine_start_errors(m.points), by_drift = errors(*drift_only, m.points), after = errors(*warp, m.points);
  // What the curves determine: the network points' mean distance to the warped sphere (sampled
  // ten times more densely than the template).
  const double gap_drift = mean_gap(*drift_only, network), gap_after = mean_gap(*warp, network);
  INFO("affine start " << start.largest << " / " << start.mean << ", drift " << by_drift.largest << " / " << by_drift.mean
                       << ", returned " << after.largest << " / " << after.mean << "; gap: drift " << gap_drift
                       << ", returned " << gap_after);
  CHECK(after.mean < by_drift.mean);
  CHECK(after.largest < by_drift.largest);
  // Measured: 0.0577 against 0.0627 mean, 0.162 against 0.183 largest; gaps 0.0101 against 0.0107.
  CHECK(gap_after < gap_drift);
  CHECK(both.mean_distance_after < both.mean_distance_before);
  // Every pair within its tolerance, as the fit returned was chosen for.
  CHECK(both.candidates_keeping_pairs > 0);
  for (std::size_t k = 0; k < pairs.size(); ++k)
    CHECK(std::sqrt(CGAL::squared_distance((*warp)(pairs[k].first), pairs[k].second)) <=
          tolerance[k] * std::cbrt(warp->jacobian_determinant(pairs[k].first)));
}

TEST_CASE("registration: a triangle corner out of range and a tolerance count other than the pairs' are refused",
          "[registration]") {
  const Sphere_mesh m = sphere_mesh(4, 8);
  const std::vector<Point_3> network = circle_points();
  std::vector<std::array<std::size_t, 3>> bad = m.triangles;
  bad.back()[2] = m.points.size();
  CHECK_THROWS_AS(meshfit::register_quadratic_warp(m.points, bad, network, crossing_pairs()), meshfit::Invalid_input);
  CHECK_THROWS_AS(meshfit::register_quadratic_warp(m.points, m.triangles, network, crossing_pairs(), {1.0, 2.0}),
                  meshfit::Invalid_input);
}

}  // namespace meshfit_registration_test
