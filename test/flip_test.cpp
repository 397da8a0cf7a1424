#include <meshfit/flip.h>

#include "test_helpers.h"

#include <random>

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
