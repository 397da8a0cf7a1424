#include <meshfit/rbf.h>

#include "../src/rbf_evaluate.h"
#include "test_helpers.h"

#include <fstream>
#include <random>
#include <sstream>

namespace meshfit_rbf_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using meshfit::Point_3;
using meshfit::Rbf_interpolant;
using meshfit::Rbf_kernel;
using meshfit::Vector_3;

namespace {

std::vector<Point_3> random_points(std::size_t n, unsigned seed, double scale = 1.0, Vector_3 shift = {0, 0, 0}) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Point_3> p;
  for (std::size_t i = 0; i < n; ++i) p.push_back(Point_3(u(rng), u(rng), u(rng)) + Vector_3(0, 0, 0));
  for (auto& q : p) q = CGAL::ORIGIN + ((q - CGAL::ORIGIN) * scale + shift);
  return p;
}

double max_relative_error(const std::vector<Point_3>& a, const std::vector<Point_3>& b, double scale) {
  double e = 0;
  for (std::size_t i = 0; i < a.size(); ++i) e = std::max(e, std::sqrt(CGAL::squared_distance(a[i], b[i])) / scale);
  return e;
}

// A smooth non-affine map to interpolate.
Point_3 warp(const Point_3& p) {
  return Point_3(p.x() + 0.3 * std::sin(2 * p.y()), 1.2 * p.y() + 0.2 * p.z() * p.x(), p.z() - 0.1 * p.x() * p.x());
}

}  // namespace

TEST_CASE("rbf: the interpolant reproduces its centres", "[rbf]") {
  for (Rbf_kernel k : {Rbf_kernel::linear, Rbf_kernel::cubic}) {
    const auto c = random_points(300, 1);
    std::vector<Point_3> v;
    for (const auto& p : c) v.push_back(warp(p));
    meshfit::Rbf_fit_report r;
    const Rbf_interpolant E = Rbf_interpolant::fit(c, v, k, {}, &r);
    CHECK(r.centres == 300);
    CHECK(r.auxiliary_pairs == 0);
    CHECK(r.relative_residual < 1e-12);
    std::vector<Point_3> out;
    E.evaluate(c, out);
    CHECK(max_relative_error(out, v, 2.0) < 1e-12);
    // Single-point evaluation and one thread agree with the parallel blocked path.
    std::vector<Point_3> one;
    E.evaluate(c, one, 1);
    CHECK(max_relative_error(out, one, 2.0) < 1e-15);
    CHECK(std::sqrt(CGAL::squared_distance(E(c[17]), v[17])) < 1e-12);
  }
}

TEST_CASE("rbf: any affine map is reproduced exactly everywhere", "[rbf]") {
  const auto c = random_points(50, 2);
  auto A = [](const Point_3& p) {
    return Point_3(2 * p.x() - p.y() + 0.5 * p.z() + 3, 0.1 * p.x() + p.y() - 7, -p.x() + 0.3 * p.y() + 4 * p.z() + 1e3);
  };
  std::vector<Point_3> v;
  for (const auto& p : c) v.push_back(A(p));
  for (Rbf_kernel k : {Rbf_kernel::linear, Rbf_kernel::cubic}) {
    const Rbf_interpolant E = Rbf_interpolant::fit(c, v, k);
    const auto q = random_points(1000, 3, 3.0);
    std::vector<Point_3> out, expected;
    E.evaluate(q, out);
    for (const auto& p : q) expected.push_back(A(p));
    CHECK(max_relative_error(out, expected, 1e3) < 1e-12);
  }
}

TEST_CASE("rbf: results are invariant under translation by 1e8 and scaling by 1e-6", "[rbf]") {
  const auto c = random_points(200, 4);
  const auto q = random_points(500, 5);
  std::vector<Point_3> v;
  for (const auto& p : c) v.push_back(warp(p));
  std::vector<Point_3> base;
  Rbf_interpolant::fit(c, v).evaluate(q, base);
  for (const auto& [scale, shift] : {std::pair<double, double>{1.0, 1e8}, {1e-6, 0.0}, {1e-6, 1e-3}}) {
    auto T = [&](const Point_3& p) { return CGAL::ORIGIN + ((p - CGAL::ORIGIN) * scale + Vector_3(shift, -shift, shift)); };
    std::vector<Point_3> tc, tv, tq, out;
    for (const auto& p : c) tc.push_back(T(p));
    for (const auto& p : v) tv.push_back(T(p));
    for (const auto& p : q) tq.push_back(T(p));
    Rbf_interpolant::fit(tc, tv).evaluate(tq, out);
    std::vector<Point_3> back;
    for (const auto& p : out) back.push_back(CGAL::ORIGIN + ((p - CGAL::ORIGIN) - Vector_3(shift, -shift, shift)) / scale);
    INFO("scale " << scale << " shift " << shift);
    // Translating by 1e8 leaves ~1e-8 of absolute precision in the coordinates themselves.
    CHECK(max_relative_error(back, base, 2.0) < (shift >= 1e8 ? 1e-7 : 1e-9));
  }
}

TEST_CASE("rbf: the affine part's determinant tells a rotation from a mirror", "[rbf]") {
  const std::vector<Point_3> c = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {0.3, 0.8, 0.1}};
  auto rotate = [](const Point_3& p, double a) {  // about z by a, then about x by a / 2
    const double x = std::cos(a) * p.x() - std::sin(a) * p.y(), y = std::sin(a) * p.x() + std::cos(a) * p.y();
    const double b = a / 2;
    return Point_3(x, std::cos(b) * y - std::sin(b) * p.z(), std::sin(b) * y + std::cos(b) * p.z());
  };
  for (double a : {0.0, 1.0, 2.0, 3.14159265358979, 4.0, 6.0}) {
    std::vector<Point_3> v, mirrored;
    for (const auto& p : c) {
      v.push_back(rotate(p, a));
      mirrored.push_back(Point_3(-v.back().x(), v.back().y(), v.back().z()));
    }
    INFO("angle " << a);
    const Rbf_interpolant E = Rbf_interpolant::fit(c, v);
    CHECK(E.affine_determinant() > 0);
    CHECK(std::sqrt(CGAL::squared_distance(E.affine_part(c[4]), v[4])) < 1e-9);  // the map is a rotation
    CHECK(Rbf_interpolant::fit(c, mirrored).affine_determinant() < 0);
  }
}

TEST_CASE("rbf: on an open patch the pairs' layout, not their heights, gives the orientation", "[rbf]") {
  // A bowl (z = 0.4 (x² + y²)) onto an upside-down bowl with the same layout along the surface:
  // the heights correlate negatively, so the best affine map of the points mirrors; the patch
  // faces +z and its layout keeps its orientation, so the map must not.
  std::vector<Point_3> c, v;
  for (double x : {-1.0, 0.0, 1.0})
    for (double y : {-1.0, 0.0, 1.0}) {
      const double r2 = x * x + y * y;
      c.emplace_back(x, y, 0.4 * r2);
      v.emplace_back(1.2 * x, 0.9 * y, -0.3 * r2);
    }
  const std::vector<Vector_3> facing(c.size(), Vector_3(0, 0, 1));
  CHECK(Rbf_interpolant::fit(c, v, Rbf_kernel::linear, facing).affine_determinant() < 0);
  meshfit::Rbf_fit_report r;
  const Rbf_interpolant E = Rbf_interpolant::fit(c, v, Rbf_kernel::linear, facing, &r, 0, true);
  CHECK(E.affine_determinant() > 0);
  CHECK(r.auxiliary_pairs == c.size());
  for (std::size_t i = 0; i < c.size(); ++i) CHECK(std::sqrt(CGAL::squared_distance(E(c[i]), v[i])) < 1e-9);
  // The side the patch faces goes to +z: a point above the centre lands above its image.
  CHECK(E(Point_3(0, 0, 0.3)).z() > E(Point_3(0, 0, 0)).z());
}

TEST_CASE("rbf: degenerate pair sets give their documented outcomes", "[rbf]") {
  using meshfit_test::require_invalid;
  const std::vector<Point_3> square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 0}};
  std::vector<Point_3> lifted;
  for (const auto& p : square) lifted.push_back(Point_3(2 * p.x(), p.y() + 1, 0.2 * p.x()));

  SECTION("coplanar centres get auxiliary pairs along the normals") {
    meshfit::Rbf_fit_report r;
    const Rbf_interpolant E = Rbf_interpolant::fit(square, lifted, Rbf_kernel::linear,
                                                   std::vector<Vector_3>(5, Vector_3(0, 0, 1)), &r);
    CHECK(r.auxiliary_pairs == 5);
    for (std::size_t i = 0; i < square.size(); ++i) CHECK(std::sqrt(CGAL::squared_distance(E(square[i]), lifted[i])) < 1e-12);
    // Off the plane, a point moves as the plane does, offset along the values' own normal e
    // (the normal of the plane z = 0.1 x, turned so that the map keeps its orientation), scaled
    // from the centres' size (h_c) to the values' (h_v).
    const Point_3 above = E(Point_3(0.5, 0.5, 0.1));
    const double hc = 0.1 * std::sqrt(2.0), hv = 0.1 * std::sqrt(4 + 1 + 0.04);
    const Vector_3 e = Vector_3(-0.1, 0, 1) / std::sqrt(1.01);
    const Point_3 expected = Point_3(1, 1.5, 0.1) + (0.1 * hv / hc) * e;
    CHECK(std::sqrt(CGAL::squared_distance(above, expected)) < 1e-9);
    CHECK(E.affine_determinant() > 0);
  }
  SECTION("coplanar pairs give the same interpolant whatever the placement of the centres") {
    // The square turned by 180 degrees about an oblique axis, then moved and scaled: E' o T = E.
    const Vector_3 axis = Vector_3(0.3, 1, 0.2) / std::sqrt(0.09 + 1 + 0.04);
    auto turn = [&](const Vector_3& v) { return 2 * (v * axis) * axis - v; };  // rotation by pi
    auto T = [&](const Point_3& p) { return Point_3(1e3, -7, 2) + 1e-2 * turn(p - CGAL::ORIGIN); };
    std::vector<Point_3> moved;
    for (const auto& p : square) moved.push_back(T(p));
    const Rbf_interpolant E = Rbf_interpolant::fit(square, lifted, Rbf_kernel::linear,
                                                   std::vector<Vector_3>(5, Vector_3(0, 0, 1)));
    const Rbf_interpolant F = Rbf_interpolant::fit(moved, lifted, Rbf_kernel::linear,
                                                   std::vector<Vector_3>(5, turn(Vector_3(0, 0, 1))));
    for (const Point_3& p : {Point_3(0.5, 0.5, 0.1), Point_3(0.2, 0.9, -0.3), Point_3(2, -1, 0.5)})
      CHECK(std::sqrt(CGAL::squared_distance(E(p), F(T(p)))) < 1e-9);
    CHECK(F.affine_determinant() > 0);
  }
  SECTION("coplanar centres without normals use the plane's normal") {
    meshfit::Rbf_fit_report r;
    Rbf_interpolant::fit(square, lifted, Rbf_kernel::linear, {}, &r);
    CHECK(r.auxiliary_pairs == 5);
  }
  SECTION("normals lying in the plane fall back to the plane's normal") {
    meshfit::Rbf_fit_report r;
    const Rbf_interpolant E = Rbf_interpolant::fit(square, lifted, Rbf_kernel::linear,
                                                   std::vector<Vector_3>(5, Vector_3(1, 0, 0)), &r);
    CHECK(r.auxiliary_pairs == 5);
    CHECK(std::sqrt(CGAL::squared_distance(E(square[2]), lifted[2])) < 1e-12);
  }
  SECTION("nearly coplanar centres are treated as coplanar") {
    auto almost = square;
    almost[4] = Point_3(0.5, 0.5, 1e-13);
    meshfit::Rbf_fit_report r;
    Rbf_interpolant::fit(almost, lifted, Rbf_kernel::linear, {}, &r);
    CHECK(r.auxiliary_pairs == 5);
  }
  SECTION("collinear centres are rejected") {
    require_invalid([] { Rbf_interpolant::fit({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}}, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}); },
                    0, "collinear");
  }
  SECTION("three pairs are too few") {
    require_invalid([] { Rbf_interpolant::fit({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}); },
                    0, "at least 4");
  }
  SECTION("duplicates: identical pairs are dropped, conflicting ones rejected") {
    std::vector<Point_3> c = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}};
    std::vector<Point_3> v = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}, {2, 0, 0}};
    meshfit::Rbf_fit_report r;
    Rbf_interpolant::fit(c, v, Rbf_kernel::linear, {}, &r);
    CHECK(r.repeated_pairs == 1);
    CHECK(r.centres == 4);
    v[4] = Point_3(3, 0, 0);
    require_invalid([&] { Rbf_interpolant::fit(c, v); }, 0, "pairs 1 and 4 have the same centre but different values");
  }
  SECTION("non-finite values are rejected") {
    std::vector<Point_3> c = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    std::vector<Point_3> v = c;
    v[2] = Point_3(std::nan(""), 0, 0);
    require_invalid([&] { Rbf_interpolant::fit(c, v); }, 0, "pair 2 has a non-finite coordinate");
  }
}

TEST_CASE("rbf: agrees with SciPy's RBFInterpolator to 1e-9", "[rbf][reference]") {
  // test/data/rbf_reference.txt is written by test/data/make_rbf_reference.py (SciPy).
  std::ifstream in(MESHFIT_TEST_DATA_DIR "/rbf_reference.txt");
  REQUIRE(in);
  std::string line, word;
  std::vector<Point_3> c, v;
  auto next_data = [&]() {
    while (std::getline(in, line))
      if (!line.empty() && line[0] != '#') return true;
    return false;
  };
  // A data line "x y z X Y Z": a point and its value.
  auto read_pair = [&](std::vector<Point_3>& first, std::vector<Point_3>& second) {
    REQUIRE(next_data());
    std::istringstream s(line);
    double a[6];
    for (double& x : a) s >> x;
    REQUIRE(s);
    first.emplace_back(a[0], a[1], a[2]);
    second.emplace_back(a[3], a[4], a[5]);
  };
  REQUIRE(next_data());
  std::size_t n = 0;
  std::istringstream(line) >> word >> n;
  REQUIRE(word == "centres");
  for (std::size_t i = 0; i < n; ++i) read_pair(c, v);
  std::size_t kernels = 0;
  while (next_data()) {
    std::size_t m = 0;
    std::string name;
    std::istringstream(line) >> word >> name >> m;
    REQUIRE(word == "kernel");
    const Rbf_interpolant E = Rbf_interpolant::fit(c, v, name == "cubic" ? Rbf_kernel::cubic : Rbf_kernel::linear);
    std::vector<Point_3> q, expected, out;
    for (std::size_t i = 0; i < m; ++i) read_pair(q, expected);
    E.evaluate(q, out);
    double scale = 0;
    for (const auto& p : expected) scale = std::max({scale, std::abs(p.x()), std::abs(p.y()), std::abs(p.z())});
    INFO("kernel " << name);
    CHECK(max_relative_error(out, expected, scale) < 1e-9);
    ++kernels;
  }
  CHECK(kernels == 2);
}

TEST_CASE("rbf: the fast kernel agrees with the portable one", "[rbf]") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  const std::size_t n = 333, m = 250;  // not multiples of the vector width
  std::vector<double> c[3], w[3], p[3], fast[3], slow[3];
  for (int d = 0; d < 3; ++d) {
    for (std::size_t j = 0; j < n; ++j) { c[d].push_back(u(rng)); w[d].push_back(u(rng)); }
    for (std::size_t i = 0; i < m; ++i) p[d].push_back(u(rng));
    p[d][7] = c[d][5];  // a point exactly on a centre: r = 0
    fast[d].assign(m, 0);
    slow[d].assign(m, 0);
  }
  for (Rbf_kernel k : {Rbf_kernel::linear, Rbf_kernel::cubic}) {
    const meshfit::internal::Rbf_arrays a{k, c[0].data(), c[1].data(), c[2].data(), w[0].data(), w[1].data(), w[2].data(), n};
    meshfit::internal::rbf_sum_block(a, p[0].data(), p[1].data(), p[2].data(), m, fast[0].data(), fast[1].data(), fast[2].data());
    meshfit::internal::rbf_sum_block_portable(a, p[0].data(), p[1].data(), p[2].data(), m, slow[0].data(), slow[1].data(), slow[2].data());
    double err = 0;
    for (int d = 0; d < 3; ++d)
      for (std::size_t i = 0; i < m; ++i) {
        REQUIRE(std::isfinite(fast[d][i]));
        err = std::max(err, std::abs(fast[d][i] - slow[d][i]));
      }
    CHECK(err < 1e-12);
  }
}

}  // namespace meshfit_rbf_test
