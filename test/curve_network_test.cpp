#include <meshfit/curve_network.h>

#include "test_helpers.h"

#include <cmath>
#include <random>

namespace meshfit_curve_network_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using meshfit::Curve_network;
using meshfit::Point_3;
using meshfit::Vector_3;
using namespace meshfit_test;

TEST_CASE("curve network: coincident points across polylines are merged", "[curve_network]") {
  // Two closed squares sharing an edge (with points off by 1e-12, well under 1e-9 × diagonal),
  // plus an open spoke from a corner.
  const double eps = 1e-12;
  const std::vector<Curve_network::Polyline> polylines = {
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}},
      {{1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1 + eps, 1, 0}, {1, eps, 0}},
      {{2, 1, 0}, {2, 1, 1}}};
  const Curve_network net(polylines);
  CHECK(net.number_of_vertices() == 7);
  // 4 + 4 + 1 segments, of which the shared edge (1,0,0)-(1,1,0) counts once.
  CHECK(net.number_of_segments() == 8);
  CHECK(net.number_of_repeated_segments() == 1);
  CHECK(net.degree(1) == 3);
  CHECK(net.degree(2) == 3);
  CHECK(net.feature_points() == std::vector<std::size_t>{1, 2, 5});
  CHECK(net.is_feature_point(5));  // (2,1,0): square corner plus spoke
  CHECK(net.endpoints().size() == 1);
  CHECK(net.number_of_closed_polylines() == 2);
  CHECK(net.number_of_components() == 1);
  CHECK(net.number_of_independent_cycles() == 2);
  // The first point seen is the vertex's position.
  CHECK(net.point(2) == Point_3(1, 1, 0));
  REQUIRE(net.find_vertex(Point_3(1 + eps, 1 - eps, 0)));
  CHECK(*net.find_vertex(Point_3(1 + eps, 1 - eps, 0)) == 2);
  CHECK_FALSE(net.find_vertex(Point_3(1 + 1e-6, 1, 0)));
  CHECK_FALSE(net.find_vertex(Point_3(1e300, 0, 0)));
}

TEST_CASE("curve network: curves run between feature points and endpoints", "[curve_network]") {
  // A figure eight: two loops through one feature point, plus a free closed loop and an open arc.
  const std::vector<Curve_network::Polyline> polylines = {
      {{0, 0, 0}, {1, 1, 0}, {2, 0, 0}, {1, -1, 0}, {0, 0, 0}, {-1, 1, 0}, {-2, 0, 0}, {-1, -1, 0}, {0, 0, 0}},
      {{0, 0, 5}, {1, 0, 5}, {1, 1, 5}, {0, 0, 5}},
      {{5, 5, 5}, {6, 5, 5}, {7, 6, 5}}};
  const Curve_network net(polylines);
  CHECK(net.feature_points() == std::vector<std::size_t>{0});
  CHECK(net.degree(0) == 4);
  CHECK(net.number_of_components() == 3);
  CHECK(net.component(0) == 0);
  CHECK(net.component(net.number_of_vertices() - 1) == 2);
  CHECK(net.number_of_independent_cycles() == 3);
  REQUIRE(net.curves().size() == 4);
  std::size_t closed = 0, segments = 0;
  for (const auto& c : net.curves()) {
    closed += c.closed;
    segments += c.vertices.size() - 1;
  }
  CHECK(closed == 3);
  CHECK(segments == net.number_of_segments());
  // The loops of the eight start and end at the feature point.
  CHECK(net.curves()[0].vertices.front() == 0);
  CHECK(net.curves()[0].vertices.back() == 0);
}

TEST_CASE("curve network: the merge tolerance is relative to the bounding box", "[curve_network]") {
  // Scaled by 1e-6 or translated by 1e8, the same points merge the same way.
  const std::pair<double, double> transforms[] = {{1.0, 0.0}, {1e-6, 0.0}, {1.0, 1e8}};
  for (const auto& [scale, shift] : transforms) {
    auto P = [&](double x, double y, double z) {
      return Point_3(shift + scale * x, shift + scale * y, shift + scale * z);
    };
    const Curve_network net({{P(0, 0, 0), P(1, 0, 0)}, {P(1, 1e-10, 0), P(1, 1, 0)}, {P(1, 1, 1e-6), P(0, 0, 0)}});
    INFO("scale " << scale << " shift " << shift);
    CHECK(net.number_of_vertices() == 4);
    CHECK(net.degree(1) == 2);
  }
  const Curve_network loose({{{0, 0, 0}, {1, 0, 0}}, {{1, 1e-4, 0}, {1, 1, 0}}}, 1e-3);
  CHECK(loose.number_of_vertices() == 3);
  CHECK_THROWS_AS(Curve_network({{{0, 0, 0}, {1, 0, 0}}}, 0.5), meshfit::Invalid_input);
}

TEST_CASE("curve network: degenerate networks are rejected", "[curve_network]") {
  require_invalid([] { Curve_network(std::vector<Curve_network::Polyline>{}); }, 0, "empty");
  require_invalid([] { Curve_network({{{1, 1, 1}, {1, 1, 1}}}); }, 0, "all coincide");
  require_invalid([] { Curve_network({{{0, 0, 0}}}); }, 0, "at least 2");
}

TEST_CASE("curve network: the example network has its ten feature points", "[curve_network][example]") {
  const Curve_network net = meshfit::read_curve_network(MESHFIT_EXAMPLE_DATA_DIR "/curves.polylines.txt");
  CHECK(net.polylines().size() == 4);
  CHECK(net.number_of_closed_polylines() == 4);
  CHECK(net.feature_points().size() == 10);
  for (std::size_t v : net.feature_points()) CHECK(net.degree(v) == 4);
  CHECK(net.endpoints().empty());
  CHECK(net.number_of_components() == 1);
  // Every feature point splits the loops: 4 loops cut at 10 points, each point on two loops.
  CHECK(net.curves().size() == 20);
  Temp_dir dir;
  meshfit::write_curve_network(dir.file("c.polylines.txt"), net);
  const Curve_network back = meshfit::read_curve_network(dir.file("c.polylines.txt"));
  CHECK(back.number_of_vertices() == net.number_of_vertices());
  CHECK(back.number_of_segments() == net.number_of_segments());
  CHECK(back.feature_points().size() == 10);
}

TEST_CASE("curve network: merging agrees with a brute-force merge on clustered points", "[curve_network]") {
  // Points in tight clusters (spread about the tolerance, some exactly at it), in random order
  // across polylines. The oracle takes the points in input order and joins each to the nearest
  // vertex made by an earlier point within the tolerance (distance <= tolerance; ties to the
  // lowest vertex), else makes a vertex: the documented rule, checked pair by pair.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::vector<Point_3> centres;
  for (int i = 0; i < 60; ++i) centres.emplace_back(10 * unit(rng), 10 * unit(rng), 10 * unit(rng));
  // Keep the box fixed whatever the clusters are: its diagonal sets the tolerance.
  const std::vector<Point_3> corners{{-11, -11, -11}, {11, 11, 11}};
  const double tolerance = 1e-4 * std::sqrt(3 * 22.0 * 22.0);
  std::uniform_int_distribution<std::size_t> pick(0, centres.size() - 1);
  std::vector<Curve_network::Polyline> polylines{{corners[0], corners[1]}};
  for (int line = 0; line < 40; ++line) {
    Curve_network::Polyline pl;
    for (int k = 0; k < 12; ++k) {
      const Point_3& c = centres[pick(rng)];
      const double r = tolerance * (k % 5 == 0 ? 1.0 : 0.7 * std::abs(unit(rng)) * 2);
      Vector_3 d(unit(rng), unit(rng), unit(rng));
      d = d / std::sqrt(d.squared_length());
      Point_3 p = c + r * d;
      if (k % 7 == 3) p = Point_3(c.x() + tolerance, c.y(), c.z());  // exactly at the tolerance from c
      if (!pl.empty() && CGAL::squared_distance(pl.back(), p) <= 4 * tolerance * tolerance) continue;
      pl.push_back(p);
    }
    if (pl.size() >= 2) polylines.push_back(pl);
  }
  std::vector<Point_3> vertices;
  std::vector<std::size_t> expected;
  const double t = 1e-4 * std::sqrt(CGAL::squared_distance(corners[0], corners[1]));
  for (const auto& pl : polylines)
    for (const Point_3& p : pl) {
      std::size_t best = vertices.size();
      double best_d2 = t * t;
      for (std::size_t v = 0; v < vertices.size(); ++v) {
        const double d2 = CGAL::squared_distance(p, vertices[v]);
        if (d2 < best_d2 || (d2 == best_d2 && best == vertices.size())) best_d2 = d2, best = v;
      }
      if (best == vertices.size()) vertices.push_back(p);
      expected.push_back(best);
    }
  std::vector<std::size_t> got;
  try {
    const Curve_network net(polylines, 1e-4);
    for (const auto& ids : net.polylines()) got.insert(got.end(), ids.begin(), ids.end());
    CHECK(net.number_of_vertices() == vertices.size());
    CHECK(net.points() == vertices);
    // find_vertex afterwards: every input point finds the vertex it was merged into, or one as near.
    std::size_t i = 0;
    for (const auto& pl : polylines)
      for (const Point_3& p : pl) {
        const auto v = net.find_vertex(p);
        REQUIRE(v);
        CHECK(CGAL::squared_distance(p, vertices[*v]) <= CGAL::squared_distance(p, vertices[expected[i++]]));
      }
  } catch (const meshfit::Invalid_input& e) {
    // Two consecutive points merged into one vertex make a zero-length segment: the oracle agrees.
    bool zero = false;
    for (std::size_t i = 0, k = 0; k < polylines.size(); i += polylines[k].size(), ++k)
      for (std::size_t j = 0; j + 1 < polylines[k].size(); ++j) zero = zero || expected[i + j] == expected[i + j + 1];
    CHECK(zero);
    return;
  }
  CHECK(got == expected);
  CHECK(vertices.size() > 60);  // the clusters were not all merged into one vertex each
  CHECK(vertices.size() < got.size());  // and some points were merged
}

}  // namespace meshfit_curve_network_test
