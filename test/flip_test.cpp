#include <meshfit/flip.h>
#include <meshfit/predicates.h>

#include "test_helpers.h"

#include <CGAL/Exact_rational.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <iomanip>
#include <random>

namespace meshfit_flip_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using meshfit::Flip_state;
using meshfit::Point_3;
using meshfit::Triangle_points;

namespace {

Flip_state counter(const Triangle_points& b, const Triangle_points& a) { return meshfit::flip_counter(b, a).state(); }

}  // namespace

TEST_CASE("flip: the counter agrees with the exact orientation test on random motions", "[flip]") {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1, 1);
  std::size_t flipped = 0, kept = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Triangle_points b, a;
    for (auto& p : b) p = Point_3(u(rng), u(rng), 0.3 * u(rng));
    const double scale = trial % 3 == 0 ? 0.1 : 1.5;
    for (int k = 0; k < 3; ++k) a[k] = b[k] + scale * meshfit::Vector_3(u(rng), u(rng), u(rng));
    const Flip_state expected = meshfit::orientation_flip_test(b, a);
    REQUIRE(counter(b, a) == expected);
    flipped += expected == Flip_state::flipped;
    kept += expected == Flip_state::kept;
  }
  // Both outcomes are well represented.
  CHECK(flipped > 3000);
  CHECK(kept > 3000);
}

TEST_CASE("flip: the counter agrees on degenerate motions on an integer grid", "[flip]") {
  // Coordinates on a coarse grid make collinear, coincident and on-the-line cases frequent.
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> g(-2, 2);
  std::size_t degenerate = 0;
  for (int trial = 0; trial < 50000; ++trial) {
    Triangle_points b, a;
    for (auto& p : b) p = Point_3(g(rng), g(rng), g(rng) * 0.5);
    for (int k = 0; k < 3; ++k) a[k] = trial % 4 == 0 ? b[k] : Point_3(g(rng), g(rng), g(rng));
    if (trial % 5 == 0) a[trial % 3] = b[trial % 3];  // zero-length motions
    const Flip_state expected = meshfit::orientation_flip_test(b, a);
    INFO("trial " << trial);
    REQUIRE(counter(b, a) == expected);
    degenerate += expected == Flip_state::degenerate;
  }
  CHECK(degenerate > 1000);
}

TEST_CASE("flip: named cases", "[flip]") {
  const Triangle_points b{Point_3(0, 0, 0), Point_3(1, 0, 0), Point_3(0, 1, 0)};
  SECTION("no motion keeps the face") { CHECK(counter(b, b) == Flip_state::kept); }
  SECTION("a vertex crossing its opposite edge flips the face") {
    CHECK(counter(b, {Point_3(1, 1, 0), b[1], b[2]}) == Flip_state::flipped);
    CHECK(meshfit::flip_counter(b, {Point_3(1, 1, 0), b[1], b[2]}).crossings == 1);
  }
  SECTION("a vertex moving exactly onto the opposite edge collapses the face") {
    CHECK(counter(b, {Point_3(0.5, 0.5, 0), b[1], b[2]}) == Flip_state::degenerate);
  }
  SECTION("a face collapsing to a segment is degenerate") {
    CHECK(counter(b, {Point_3(0, 0, 1), Point_3(1, 1, 1), Point_3(2, 2, 1)}) == Flip_state::degenerate);
  }
  SECTION("a pure translation flips nothing, though one vertex crosses the old opposite edge line") {
    const meshfit::Vector_3 t(10, 10, 3);
    CHECK(counter(b, {b[0] + t, b[1] + t, b[2] + t}) == Flip_state::kept);
  }
  SECTION("a mirror image flips; motion along the normal does not") {
    CHECK(counter(b, {b[0], Point_3(-1, 0, 0), b[2]}) == Flip_state::flipped);
    CHECK(counter(b, {Point_3(0, 0, 5), Point_3(1, 0, -5), Point_3(0, 1, 2)}) == Flip_state::kept);
  }
  SECTION("a degenerate face before the motion has no plane") {
    const Triangle_points flat{Point_3(0, 0, 0), Point_3(1, 1, 1), Point_3(2, 2, 2)};
    CHECK(counter(flat, flat) == Flip_state::degenerate);
  }
  SECTION("the normal-angle baseline needs a tolerance the counter does not") {
    // A 100° rotation about an edge: the projected face is reversed; the baseline says so only
    // when its tolerance is below 100°.
    const double c = std::cos(100 * CGAL_PI / 180), s = std::sin(100 * CGAL_PI / 180);
    const Triangle_points a{b[0], b[1], Point_3(0, c, s)};
    CHECK(counter(b, a) == Flip_state::flipped);
    CHECK(meshfit::normal_angle_flip_test(b, a, CGAL_PI / 2) == Flip_state::flipped);
    CHECK(meshfit::normal_angle_flip_test(b, a, 2.0) == Flip_state::kept);
  }
}

TEST_CASE("flip: orientation in a plane is exact near degeneracy (filter and exact fallback)", "[flip]") {
  // Points on a plane, rounded to doubles and nudged by a few ulps: the double evaluation is
  // unreliable here, so the floating-point filter must defer; compare with rational arithmetic.
  using Q = CGAL::Exact_rational;
  auto exact = [](const Triangle_points& t, const Point_3& a, const Point_3& b, const Point_3& c) {
    // (Q may be gmpxx's mpq_class: name the type, or `auto` keeps an expression of temporaries.)
    auto d = [](const Point_3& p, const Point_3& q, int k) -> Q { return Q(p[k]) - Q(q[k]); };
    Q e1[3], e2[3], u[3], v[3];
    for (int k = 0; k < 3; ++k) e1[k] = d(t[1], t[0], k), e2[k] = d(t[2], t[0], k), u[k] = d(b, a, k), v[k] = d(c, a, k);
    const Q n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const Q w[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return CGAL::sign(n[0] * w[0] + n[1] * w[1] + n[2] * w[2]);
  };
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> ulps(-3, 3);
  std::size_t zero = 0, positive = 0, negative = 0;
  for (int i = 0; i < 20000; ++i) {
    const Triangle_points plane{Point_3(u(rng), u(rng), u(rng)), Point_3(u(rng), u(rng), u(rng)),
                                Point_3(u(rng), u(rng), u(rng))};
    // a, b and c collinear in 3D up to rounding: their orientation in any plane is nearly zero.
    const Point_3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
    const double s = u(rng);
    auto nudge = [&](double x) {
      for (int k = ulps(rng); k != 0; k += k > 0 ? -1 : 1) x = std::nextafter(x, k > 0 ? 2.0 : -2.0);
      return x;
    };
    const Point_3 c(nudge(a.x() + s * (b.x() - a.x())), nudge(a.y() + s * (b.y() - a.y())),
                    nudge(a.z() + s * (b.z() - a.z())));
    const CGAL::Sign want = exact(plane, a, b, c);
    INFO(std::setprecision(17) << plane[0] << " | " << plane[1] << " | " << plane[2] << " | " << a << " | " << b << " | " << c);
    REQUIRE(meshfit::orientation_in_plane(plane, a, b, c) == want);
    REQUIRE(meshfit::internal::orientation_in_plane_unfiltered(plane, a, b, c) == want);
    (want == CGAL::ZERO ? zero : want == CGAL::POSITIVE ? positive : negative)++;
  }
  // Also far from degeneracy, where the filter decides alone.
  for (int i = 0; i < 20000; ++i) {
    const Triangle_points plane{Point_3(u(rng), u(rng), u(rng)), Point_3(u(rng), u(rng), u(rng)),
                                Point_3(u(rng), u(rng), u(rng))};
    const Point_3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    REQUIRE(meshfit::orientation_in_plane(plane, a, b, c) == exact(plane, a, b, c));
    REQUIRE(meshfit::internal::orientation_in_plane_unfiltered(plane, a, b, c) == exact(plane, a, b, c));
  }
  CHECK(positive > 1000);
  CHECK(negative > 1000);
}

TEST_CASE("predicates: edge_folds says whether two faces across an edge turn more than 90 degrees apart", "[flip]") {
  // Faces (0 1 2) and (1 0 3) share the edge 0-1 on the x axis; face (0 1 2) lies in the plane
  // z = 0 with corner 2 at +y. Corner 3 turns about the x axis by `angle` from -y (flat, 0) up
  // towards +y; the faces' normals are then `angle` apart. The oracle is that angle.
  for (const double degrees : {0.0, 30.0, 60.0, 85.0, 95.0, 120.0, 175.0}) {
    CGAL::Surface_mesh<Point_3> tm;
    const double a = degrees * 3.14159265358979323846 / 180;
    const auto v0 = tm.add_vertex(Point_3(0, 0, 0)), v1 = tm.add_vertex(Point_3(1, 0, 0));
    const auto v2 = tm.add_vertex(Point_3(0.5, 1, 0)), v3 = tm.add_vertex(Point_3(0.5, -std::cos(a), std::sin(a)));
    const auto f = tm.add_face(v0, v1, v2);
    REQUIRE(f != tm.null_face());
    REQUIRE(tm.add_face(v1, v0, v3) != tm.null_face());
    const auto h = tm.halfedge(v0, v1);
    REQUIRE(tm.face(h) == f);
    INFO(degrees << " degrees");
    CHECK(meshfit::edge_folds(tm, h, [&](auto v) { return tm.point(v); }) == (degrees > 90));
  }
}

}  // namespace meshfit_flip_test
