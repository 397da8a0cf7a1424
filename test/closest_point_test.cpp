#include <meshfit/correspondence.h>

#include "test_helpers.h"

#include <random>

namespace meshfit_closest_point_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using meshfit::Closest_point_assignment;
using meshfit::Curve_network;
using meshfit::Point_3;

TEST_CASE("closest point: matches brute force on random sets", "[correspondence][closest]") {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Point_3> tpl;
  for (int i = 0; i < 2000; ++i) tpl.emplace_back(u(rng), u(rng), u(rng));
  std::vector<Curve_network::Polyline> lines(1);
  for (int i = 0; i < 60; ++i) lines[0].emplace_back(u(rng), u(rng), u(rng));
  const Curve_network net(lines);
  const auto a = meshfit::closest_point_correspondences(tpl, net);
  for (std::size_t v = 0; v < net.number_of_vertices(); ++v) {
    std::size_t best = 0;
    for (std::size_t t = 1; t < tpl.size(); ++t)
      if (CGAL::compare_distance_to_point(net.point(v), tpl[t], tpl[best]) == CGAL::SMALLER) best = t;
    const bool lost = std::binary_search(a.losers.begin(), a.losers.end(), v);
    if (!lost) CHECK(a.template_of[v] == best);
  }
  CHECK(a.losers.empty());  // 60 points among 2000: no two share a nearest vertex here
}

TEST_CASE("closest point: feature points win conflicts, then the nearer, then the lower index", "[correspondence][closest]") {
  // Template vertices far apart; network vertices clustered around template vertex 0.
  const std::vector<Point_3> tpl = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}};
  // A star of three segments through (0.3,0,0): that point is a feature point but farther from
  // template vertex 0 than (0.1,0,0) and (0,0.1,0).
  const Curve_network net({{{0.3, 0, 0}, {0.1, 0, 0}}, {{0.3, 0, 0}, {0, 0.1, 0}}, {{0.3, 0, 0}, {0.3, 0.05, 0}}});
  REQUIRE(net.is_feature_point(0));
  const auto drop = meshfit::closest_point_correspondences(tpl, net);
  CHECK(drop.template_of[0] == 0);
  CHECK(drop.losers == std::vector<std::size_t>{1, 2, 3});

  // Without the feature point, (0.1,0,0) and (0,0.1,0) tie exactly: the lower index wins.
  const Curve_network pair({{{0.1, 0, 0}, {0, 0.1, 0}}});
  const auto tie = meshfit::closest_point_correspondences(tpl, pair);
  CHECK(tie.template_of[0] == 0);
  CHECK(tie.losers == std::vector<std::size_t>{1});

  // With the next-nearest rule every network vertex gets a vertex while some are free.
  const auto next = meshfit::closest_point_correspondences(tpl, net, {}, meshfit::Loser_rule::next_nearest);
  CHECK(next.losers.empty());
  std::vector<std::size_t> used(next.template_of);
  std::sort(used.begin(), used.end());
  CHECK(std::adjacent_find(used.begin(), used.end()) == used.end());
}

TEST_CASE("closest point: fixed pairs keep their vertices", "[correspondence][closest]") {
  const std::vector<Point_3> tpl = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}};
  const Curve_network net({{{0.1, 0, 0}, {9, 0, 0}}});
  meshfit::Correspondence fixed;
  fixed.template_vertex = 0;
  fixed.network_vertex = 1;  // (9,0,0) pinned to vertex 0 although vertex 1 is nearer
  const auto a = meshfit::closest_point_correspondences(tpl, net, {fixed});
  CHECK(a.template_of[1] == 0);
  CHECK(a.template_of[0] != 0);
}

}  // namespace meshfit_closest_point_test
