#include <meshfit/displacement.h>
#include <meshfit/exceptions.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace meshfit_displacement_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using meshfit::Vector_3;
using meshfit::Vertex_adjacency;

namespace {

// The n × n grid graph (4-neighbours), vertex (i, j) = j n + i.
Vertex_adjacency grid_graph(std::size_t n) {
  Vertex_adjacency a;
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t i = 0; i < n; ++i) {
      if (i > 0) a.neighbours.push_back(j * n + i - 1);
      if (i + 1 < n) a.neighbours.push_back(j * n + i + 1);
      if (j > 0) a.neighbours.push_back((j - 1) * n + i);
      if (j + 1 < n) a.neighbours.push_back((j + 1) * n + i);
      a.offsets.push_back(a.neighbours.size());
    }
  return a;
}

}  // namespace

TEST_CASE("displacement: a constant displacement of the held vertices moves every vertex by it", "[displacement]") {
  const std::size_t n = 9;
  const Vertex_adjacency a = grid_graph(n);
  std::vector<bool> held(n * n, false);
  std::vector<Vector_3> given(n * n, Vector_3(0, 0, 0));
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k : {i, (n - 1) * n + i, i * n, i * n + n - 1}) held[k] = true, given[k] = Vector_3(1, -2, 0.5);
  for (int order : {1, 2}) {
    meshfit::Displacement_report r;
    const auto d = meshfit::interpolate_displacements(a, held, given, order, &r);
    CHECK(r.free_vertices == (n - 2) * (n - 2));
    for (const Vector_3& v : d) CHECK(std::sqrt((v - Vector_3(1, -2, 0.5)).squared_length()) < 1e-12);
  }
}

TEST_CASE("displacement: the membrane solution on a path is the linear interpolation and obeys the maximum principle",
          "[displacement]") {
  // A path 0 - 1 - … - 10 with its ends held.
  Vertex_adjacency a;
  const std::size_t n = 11;
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) a.neighbours.push_back(i - 1);
    if (i + 1 < n) a.neighbours.push_back(i + 1);
    a.offsets.push_back(a.neighbours.size());
  }
  std::vector<bool> held(n, false);
  held[0] = held[n - 1] = true;
  std::vector<Vector_3> given(n, Vector_3(0, 0, 0));
  given[n - 1] = Vector_3(10, 0, -5);
  const auto d = meshfit::interpolate_displacements(a, held, given, 1);
  for (std::size_t i = 0; i < n; ++i) {
    CHECK(d[i].x() == Approx(double(i)).margin(1e-12));
    CHECK(d[i].z() == Approx(-0.5 * double(i)).margin(1e-12));
  }
  // On a grid with scattered held values the membrane solution stays within their range.
  const Vertex_adjacency g = grid_graph(12);
  std::vector<bool> h(144, false);
  std::vector<Vector_3> v(144, Vector_3(0, 0, 0));
  const std::size_t spots[] = {0, 17, 50, 77, 100, 143};
  const double values[] = {3, -1, 2, 0.5, -2, 1};
  for (int k = 0; k < 6; ++k) h[spots[k]] = true, v[spots[k]] = Vector_3(values[k], 0, 0);
  const auto m = meshfit::interpolate_displacements(g, h, v, 1);
  for (const Vector_3& x : m) {
    CHECK(x.x() <= 3 + 1e-12);
    CHECK(x.x() >= -2 - 1e-12);
  }
}

TEST_CASE("displacement: a part with no held vertex keeps a zero displacement, bad input is refused", "[displacement]") {
  // Two separate edges: 0 - 1 held at one end, 2 - 3 with nothing held.
  Vertex_adjacency a;
  a.neighbours = {1, 0, 3, 2};
  a.offsets = {0, 1, 2, 3, 4};
  std::vector<bool> held = {true, false, false, false};
  std::vector<Vector_3> given(4, Vector_3(0, 0, 0));
  given[0] = Vector_3(0, 1, 0);
  meshfit::Displacement_report r;
  const auto d = meshfit::interpolate_displacements(a, held, given, 2, &r);
  CHECK(r.unconstrained_free_vertices == 2);
  CHECK(d[1].y() == Approx(1));
  CHECK(d[2] == Vector_3(0, 0, 0));
  CHECK(d[3] == Vector_3(0, 0, 0));
  CHECK_THROWS_AS(meshfit::interpolate_displacements(a, {true}, given, 2), meshfit::Invalid_input);
  CHECK_THROWS_AS(meshfit::interpolate_displacements(a, held, given, 3), meshfit::Invalid_input);
  given[0] = Vector_3(std::nan(""), 0, 0);
  CHECK_THROWS_AS(meshfit::interpolate_displacements(a, held, given, 2), meshfit::Invalid_input);
}

TEST_CASE("displacement: fit_displacements meets its targets when soft, tends to their mean when stiff", "[displacement]") {
  const std::size_t n = 8;
  const Vertex_adjacency a = grid_graph(n);
  using meshfit::Soft_displacement;
  // A constant target at every vertex: a constant field has no thin-plate energy, whatever the stiffness.
  std::vector<Soft_displacement> all;
  for (std::size_t i = 0; i < n * n; ++i) all.push_back({{i, i, i}, {1, 0, 0}, Vector_3(0.5, -1, 2), 1});
  for (double stiffness : {1e-3, 1.0, 1e3})
    for (const Vector_3& v : meshfit::fit_displacements(a, all, stiffness))
      CHECK(std::sqrt((v - Vector_3(0.5, -1, 2)).squared_length()) < 1e-6);
  // Two targets at the corners (0, 0) and (7, 7), one of them at the middle of an edge.
  const std::vector<Soft_displacement> two = {{{0, 1, 0}, {0.5, 0.5, 0}, Vector_3(1, 0, 0), 1},
                                              {{n * n - 1, n * n - 1, n * n - 1}, {1, 0, 0}, Vector_3(-1, 0, 4), 1}};
  const auto soft = meshfit::fit_displacements(a, two, 1e-8);
  CHECK(std::sqrt((0.5 * (soft[0] + soft[1]) - Vector_3(1, 0, 0)).squared_length()) < 1e-4);
  CHECK(std::sqrt((soft[n * n - 1] - Vector_3(-1, 0, 4)).squared_length()) < 1e-4);
  // Very stiff: nearly constant, the least-squares constant of the two targets (their mean).
  for (const Vector_3& v : meshfit::fit_displacements(a, two, 1e8))
    CHECK(std::sqrt((v - Vector_3(0, 0, 2)).squared_length()) < 1e-3);
}

TEST_CASE("displacement: fit_displacements leaves unconstrained parts still and refuses bad input", "[displacement]") {
  Vertex_adjacency a;  // two separate edges 0 - 1 and 2 - 3
  a.neighbours = {1, 0, 3, 2};
  a.offsets = {0, 1, 2, 3, 4};
  using meshfit::Soft_displacement;
  std::vector<Soft_displacement> c = {{{0, 0, 0}, {1, 0, 0}, Vector_3(0, 1, 0), 1}};
  const auto d = meshfit::fit_displacements(a, c, 1);
  CHECK(d[0].y() == Approx(1).margin(1e-6));
  CHECK(d[1].y() == Approx(1).margin(1e-6));
  CHECK(std::sqrt(d[2].squared_length()) < 1e-12);
  CHECK(std::sqrt(d[3].squared_length()) < 1e-12);
  CHECK_THROWS_AS(meshfit::fit_displacements(a, c, 0), meshfit::Invalid_input);
  CHECK_THROWS_AS(meshfit::fit_displacements(a, c, std::nan("")), meshfit::Invalid_input);
  // With significant digits, not std::to_string's "-0.000000".
  CHECK_THROWS_WITH(meshfit::fit_displacements(a, c, -1e-9), Catch::Contains("not -1e-09"));
  c.push_back({{0, 4, 1}, {0.2, 0.3, 0.5}, Vector_3(0, 0, 0), 1});
  CHECK_THROWS_AS(meshfit::fit_displacements(a, c, 1), meshfit::Invalid_input);
  c.back() = {{0, 1, 1}, {0.2, 0.3, 0.5}, Vector_3(std::nan(""), 0, 0), 1};
  CHECK_THROWS_AS(meshfit::fit_displacements(a, c, 1), meshfit::Invalid_input);
  c.back() = {{0, 1, 1}, {0.2, 0.3, 0.5}, Vector_3(0, 0, 0), -1};
  CHECK_THROWS_AS(meshfit::fit_displacements(a, c, 1), meshfit::Invalid_input);
}

// The band of deform_fine_on_surface's step 3: on the grid graph the vertices k edges away are
// those at Manhattan distance k, the oracle here.
TEST_CASE("displacement: vertices_within_reach reaches max(rings, ceil(fade |d| / edge)) edges from each held vertex",
          "[displacement]") {
  const std::size_t n = 30;
  const Vertex_adjacency a = grid_graph(n);
  std::vector<bool> held(n * n, false);
  std::vector<Vector_3> given(n * n, Vector_3(0, 0, 0));
  struct Held {
    std::size_t i, j;
    Vector_3 d;
    std::size_t reach;
  };
  // Edge 2, fade 10: motion 0.1 reaches max(4, 1) = 4; 1.5 reaches 8 (6 and 8 in x and z); 0 reaches 4.
  const std::vector<Held> hs{{5, 5, Vector_3(0.1, 0, 0), 4}, {20, 20, Vector_3(0.9, 0, 1.2), 8}, {2, 27, Vector_3(0, 0, 0), 4}};
  for (const Held& h : hs) held[h.j * n + h.i] = true, given[h.j * n + h.i] = h.d;
  const std::vector<bool> in = meshfit::vertices_within_reach(a, held, given, 2.0, 4, 10.0);
  std::size_t reached = 0;
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t i = 0; i < n; ++i) {
      bool expected = false;
      for (const Held& h : hs)
        expected = expected || (i > h.i ? i - h.i : h.i - i) + (j > h.j ? j - h.j : h.j - j) <= h.reach;
      CHECK(in[j * n + i] == expected);
      reached += expected;
    }
  CHECK(reached == 41 + 145 + 33);  // diamonds of radius 4 and 8, the third cut by the grid's edges

  // No rings: a still vertex reaches itself only, a moving one at least its neighbours. A motion
  // that is not finite reaches every vertex.
  const std::vector<bool> alone =
      meshfit::vertices_within_reach(a, held, std::vector<Vector_3>(n * n, Vector_3(0, 0, 0)), 1e9, 0, 10.0);
  CHECK(std::count(alone.begin(), alone.end(), true) == 3);
  const std::vector<bool> near = meshfit::vertices_within_reach(a, held, given, 1e9, 0, 10.0);
  CHECK(std::count(near.begin(), near.end(), true) == 5 + 5 + 1);
  given[5 * n + 5] = Vector_3(std::nan(""), 0, 0);
  const std::vector<bool> all = meshfit::vertices_within_reach(a, held, given, 2.0, 4, 10.0);
  CHECK(std::count(all.begin(), all.end(), true) == static_cast<std::ptrdiff_t>(n * n));

  CHECK_THROWS_AS(meshfit::vertices_within_reach(a, held, given, 0.0, 4, 10.0), meshfit::Invalid_input);
  CHECK_THROWS_AS(meshfit::vertices_within_reach(a, std::vector<bool>(3), given, 1.0, 4, 10.0), meshfit::Invalid_input);
}

namespace {

// A triangulated n × n grid (each square cut along its rising diagonal: 6 neighbours inside) on
// the plane through `origin` spanned by the orthonormal u, v, with spacing h; its points.
Vertex_adjacency triangulated_grid(std::size_t n, const meshfit::Point_3& origin, const Vector_3& u, const Vector_3& v,
                                   double h, std::vector<meshfit::Point_3>& points) {
  Vertex_adjacency a;
  points.clear();
  const int m = static_cast<int>(n);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      for (const auto& [di, dj] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}, {1, 1}, {-1, -1}}) {
        const int x = i + di, y = j + dj;
        if (x >= 0 && x < m && y >= 0 && y < m) a.neighbours.push_back(static_cast<std::size_t>(y * m + x));
      }
      a.offsets.push_back(a.neighbours.size());
      points.push_back(origin + (h * i) * u + (h * j) * v);
    }
  return a;
}

}  // namespace

// The oracle: a linear function evaluated at the nodes' points and interpolated, against its value.
TEST_CASE("displacement: a coarse space sums to one, reproduces linear fields along the surface and follows placement",
          "[displacement]") {
  const std::size_t n = 40;
  const Vector_3 u = Vector_3(2, 1, 2) / 3, v = Vector_3(-1, 2, 0) / std::sqrt(5.0);
  std::vector<meshfit::Point_3> p;
  const Vertex_adjacency a = triangulated_grid(n, meshfit::Point_3(3, -1, 2), u, v, 0.1, p);
  const Vector_3 normal = CGAL::cross_product(u, v);
  const meshfit::Coarse_space cs = meshfit::coarse_space(a, p, std::vector<Vector_3>(p.size(), normal), 2);
  CHECK(cs.nodes == cs.seed.size());
  CHECK(cs.nodes > p.size() / 40);
  CHECK(cs.nodes < p.size() / 10);  // aggregates of two rings: about 19 vertices each inside
  auto g = [&](const meshfit::Point_3& x) { return 1.5 * x.x() - 2 * x.y() + 0.25 * x.z() + 7; };
  double worst_sum = 0, worst_linear = 0;
  std::size_t widest = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    double sum = 0, value = 0;
    for (std::size_t k = cs.offsets[i]; k < cs.offsets[i + 1]; ++k) {
      sum += cs.weight[k];
      value += cs.weight[k] * g(p[cs.seed[cs.node[k]]]);
      // A vertex interpolates nodes near it: up to two aggregates away (2 rings each).
      CHECK(std::sqrt(CGAL::squared_distance(p[i], p[cs.seed[cs.node[k]]])) < 15 * 0.1);
    }
    widest = std::max(widest, cs.offsets[i + 1] - cs.offsets[i]);
    worst_sum = std::max(worst_sum, std::abs(sum - 1));
    worst_linear = std::max(worst_linear, std::abs(value - g(p[i])));
  }
  CHECK(worst_sum < 1e-12);
  CHECK(worst_linear < 1e-11);
  CHECK(widest <= 25);
  CHECK(cs.node.size() <= 12 * p.size());
  // Turned, scaled by 1000 and moved: the same space (the weights to 1e-9).
  const CGAL::Aff_transformation_3<meshfit::Kernel> turn(0, -1, 0, 1, 0, 0, 0, 0, 1);
  std::vector<meshfit::Point_3> q;
  for (const auto& x : p) q.push_back(meshfit::Point_3(1e6, -5e5, 2e5) + 1000 * (turn(x) - CGAL::ORIGIN));
  const meshfit::Coarse_space moved = meshfit::coarse_space(a, q, std::vector<Vector_3>(q.size(), turn(normal)), 2);
  // (A node at exactly its reach may weigh 0 or 1e-40 on a vertex, depending on rounding.)
  REQUIRE(moved.seed == cs.seed);
  double worst_moved = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    std::map<std::size_t, double> row;
    for (std::size_t k = cs.offsets[i]; k < cs.offsets[i + 1]; ++k) row[cs.node[k]] += cs.weight[k];
    for (std::size_t k = moved.offsets[i]; k < moved.offsets[i + 1]; ++k) row[moved.node[k]] -= moved.weight[k];
    for (const auto& [node, difference] : row) worst_moved = std::max(worst_moved, std::abs(difference));
  }
  CHECK(worst_moved < 1e-9);
  // Bad input.
  CHECK_THROWS_AS(meshfit::coarse_space(a, p, std::vector<Vector_3>(3, normal), 2), meshfit::Invalid_input);
  CHECK_THROWS_AS(meshfit::coarse_space(a, p, std::vector<Vector_3>(p.size(), normal), 0), meshfit::Invalid_input);
  const Vertex_adjacency small = grid_graph(4);
  CHECK_THROWS_AS(meshfit::fit_displacements(small, {}, 1, &cs), meshfit::Invalid_input);
  meshfit::Coarse_space bad = cs;
  bad.node[7] = cs.nodes;
  CHECK_THROWS_WITH(meshfit::fit_displacements(a, {}, 1, &bad), Catch::Contains("entry 7 out of"));
  bad = cs, bad.weight[3] = std::nan("");
  CHECK_THROWS_AS(meshfit::fit_displacements(a, {}, 1, &bad), meshfit::Invalid_input);
  bad = cs, bad.offsets[5] = bad.offsets[6] + 1;
  CHECK_THROWS_WITH(meshfit::fit_displacements(a, {}, 1, &bad), Catch::Contains("rows do not match"));
}

// The oracle: the whole mesh's solve of the same least-squares problem. The two differ most at
// the grid's border, beyond the targets, where the thin-plate field is least determined.
TEST_CASE("displacement: fit_displacements in a coarse space comes close to the whole mesh's solve", "[displacement]") {
  const std::size_t n = 60;
  std::vector<meshfit::Point_3> p;
  const Vertex_adjacency a = triangulated_grid(n, meshfit::Point_3(0, 0, 0), Vector_3(1, 0, 0), Vector_3(0, 1, 0), 1, p);
  const meshfit::Coarse_space cs = meshfit::coarse_space(a, p, std::vector<Vector_3>(p.size(), Vector_3(0, 0, 1)), 2);
  // A smooth field asked for along five lines of the grid (as curves would), a target at the
  // middle of every third edge along them.
  auto field = [](const meshfit::Point_3& x) {
    return Vector_3(std::sin(x.x() / 15), std::cos(x.y() / 12), 0.0005 * x.x() * x.y());
  };
  using meshfit::Soft_displacement;
  std::vector<Soft_displacement> c;
  for (std::size_t line : {5, 17, 30, 42, 54})
    for (std::size_t i = 0; i + 1 < n; i += 3) {
      const std::size_t k = line * n + i;
      c.push_back({{k, k + 1, k}, {0.5, 0.5, 0}, field(CGAL::midpoint(p[k], p[k + 1])), 1});
    }
  auto largest_miss = [&](const std::vector<Vector_3>& d) {
    double miss = 0;
    for (const Soft_displacement& s : c)
      miss = std::max(miss, std::sqrt((0.5 * (d[s.corners[0]] + d[s.corners[1]]) - s.target).squared_length()));
    return miss;
  };
  for (double stiffness : {10.0, 0.1}) {
    const auto fine = meshfit::fit_displacements(a, c, stiffness);
    const auto coarse = meshfit::fit_displacements(a, c, stiffness, &cs);
    double largest = 0, inner = 0, squares = 0, off_squares = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double off = std::sqrt((coarse[i] - fine[i]).squared_length());
      largest = std::max(largest, std::sqrt(fine[i].squared_length()));
      squares += fine[i].squared_length(), off_squares += off * off;
      if (i % n >= 10 && i % n < n - 10 && i / n >= 10 && i / n < n - 10) inner = std::max(inner, off);
    }
    const double miss = largest_miss(coarse), fine_miss = largest_miss(fine);
    INFO("stiffness " << stiffness << ": largest " << largest << ", off by " << inner << " inside, "
                      << std::sqrt(off_squares / squares) << " in mean square; misses " << miss << " (whole: " << fine_miss << ")");
    CHECK(std::sqrt(off_squares / squares) < 0.06);
    CHECK(inner < 0.1 * largest);
    CHECK(miss < fine_miss + 0.1 * largest);
  }
}

// The oracle: x² − y² is harmonic on the triangulated grid (its uniform Laplacian is 0 at every
// inner vertex), so held on the border it comes back inside: the thin-plate energy's border rows
// run along the border, among held vertices. A border row across the border (the one-sided
// Laplacian) would measure the field's slope there and bend it.
TEST_CASE("displacement: a harmonic field given on an open grid's border comes back inside", "[displacement]") {
  const int m = 15;
  std::vector<meshfit::Point_3> p;
  Vertex_adjacency a = triangulated_grid(m, meshfit::Point_3(0, 0, 0), Vector_3(1, 0, 0), Vector_3(0, 1, 0), 1.0, p);
  auto on_side = [&](std::size_t i) { return p[i].x() == 0 || p[i].y() == 0 || p[i].x() == m - 1 || p[i].y() == m - 1; };
  for (std::size_t i = 0; i + 1 < a.offsets.size(); ++i)
    for (std::size_t k = a.offsets[i]; k < a.offsets[i + 1]; ++k) {
      const meshfit::Point_3& q = p[a.neighbours[k]];
      // A border edge: both ends on one side of the square.
      a.border_edge.push_back((p[i].x() == q.x() && (q.x() == 0 || q.x() == m - 1)) ||
                              (p[i].y() == q.y() && (q.y() == 0 || q.y() == m - 1)));
    }
  auto f = [&](std::size_t i) { return Vector_3(0, 0, (p[i].x() - 7) * (p[i].x() - 7) - (p[i].y() - 3) * (p[i].y() - 3)); };
  std::vector<bool> held(p.size(), false);
  std::vector<Vector_3> given(p.size(), Vector_3(0, 0, 0));
  for (std::size_t i = 0; i < p.size(); ++i)
    if (on_side(i)) held[i] = true, given[i] = f(i);
  auto worst = [&](const std::vector<Vector_3>& d) {
    double e = 0;
    for (std::size_t i = 0; i < p.size(); ++i) e = std::max(e, std::sqrt((d[i] - f(i)).squared_length()));
    return e;
  };
  CHECK(worst(meshfit::interpolate_displacements(a, held, given, 2)) < 1e-9);
  // Without the border flags every row is a whole Laplacian, the border's one-sided: far off.
  Vertex_adjacency closed_rows = a;
  closed_rows.border_edge.clear();
  CHECK(worst(meshfit::interpolate_displacements(closed_rows, held, given, 2)) > 1);
  // Flags that do not match the neighbours are refused.
  a.border_edge.pop_back();
  CHECK_THROWS_AS(meshfit::interpolate_displacements(a, held, given, 2), meshfit::Invalid_input);
}

}  // namespace meshfit_displacement_test

namespace meshfit_displacement_test {

using meshfit::Point_3;
using Triangles = std::vector<std::array<std::size_t, 3>>;

namespace {

// A triangulated patch: (nx + 1) × (ny + 1) points, each cell cut along one diagonal, with the
// adjacency its triangles give (neighbours in ascending order).
struct Patch {
  std::vector<Point_3> points;
  Triangles triangles;
  Vertex_adjacency adjacency;
};

Vertex_adjacency adjacency_of(std::size_t n, const Triangles& triangles) {
  std::vector<std::vector<std::size_t>> around(n);
  for (const auto& t : triangles)
    for (std::size_t k = 0; k < 3; ++k) around[t[k]].push_back(t[(k + 1) % 3]), around[t[(k + 1) % 3]].push_back(t[k]);
  Vertex_adjacency a;
  for (auto& v : around) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    a.neighbours.insert(a.neighbours.end(), v.begin(), v.end());
    a.offsets.push_back(a.neighbours.size());
  }
  return a;
}

// Points at f(i, j) for 0 ≤ i ≤ nx, 0 ≤ j ≤ ny.
template <typename F>
Patch patch(std::size_t nx, std::size_t ny, F f) {
  Patch p;
  for (std::size_t j = 0; j <= ny; ++j)
    for (std::size_t i = 0; i <= nx; ++i) p.points.push_back(f(double(i), double(j)));
  auto at = [&](std::size_t i, std::size_t j) { return j * (nx + 1) + i; };
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      p.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      p.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  p.adjacency = adjacency_of(p.points.size(), p.triangles);
  return p;
}

// The weight of edge i-j in a's rows.
double weight_of(const Vertex_adjacency& a, std::size_t i, std::size_t j) {
  for (std::size_t m = a.offsets[i]; m < a.offsets[i + 1]; ++m)
    if (a.neighbours[m] == j) return a.weight[m];
  return std::nan("");
}

}  // namespace

TEST_CASE("displacement: cotangent weights are 1 on equilateral triangles and follow the angles elsewhere",
          "[displacement]") {
  // Equilateral lattice: row j shifted by −j/2, height √3/2 (the cells' diagonals of length 1). Every inner edge sees two 60° angles:
  // (√3/2)(cot 60° + cot 60°) = 1, and an inner vertex's six faces have the mean area: mass 6
  // (the vertices compared are two rings in, away from the smaller border areas that lower the mean).
  const double h = std::sqrt(3.0) / 2;
  Patch lattice = patch(10, 10, [&](double i, double j) { return Point_3(i - 0.5 * j, h * j, 0); });
  meshfit::set_cotangent_weights(lattice.adjacency, lattice.points, lattice.triangles);
  const std::size_t inner = 5 * 11 + 5;
  for (std::size_t m = lattice.adjacency.offsets[inner]; m < lattice.adjacency.offsets[inner + 1]; ++m)
    CHECK(lattice.adjacency.weight[m] == Approx(1).epsilon(1e-12));
  CHECK(lattice.adjacency.offsets[inner + 1] - lattice.adjacency.offsets[inner] == 6);
  // 6 A_i / Ā with A_i = 2 (√3/4) and Ā the mean over all vertices, counted here by hand.
  double total = 0;
  for (const auto& t : lattice.triangles) (void)t, total += std::sqrt(3.0) / 4;
  CHECK(lattice.adjacency.mass[inner] == Approx(6 * (std::sqrt(3.0) / 2) / (total / 121)).epsilon(1e-12));

  // Right isosceles cells cut along a diagonal: an axis edge inside sees two 45° angles,
  // (√3/2)(1 + 1) = √3; the diagonal sees two right angles, cot 90° = 0, raised to the floor 0.05.
  // The same weights for the patch turned, moved and scaled by 1e4.
  Patch square = patch(6, 6, [](double i, double j) { return Point_3(i, j, 0); });
  const double c = std::cos(0.7), s = std::sin(0.7);
  Patch moved = patch(6, 6, [&](double i, double j) {
    return Point_3(1e6 + 1e4 * (c * i - s * j), -3e5 + 1e4 * (s * i + c * j), 2e5);
  });
  meshfit::set_cotangent_weights(square.adjacency, square.points, square.triangles);
  meshfit::set_cotangent_weights(moved.adjacency, moved.points, moved.triangles);
  const std::size_t v = 3 * 7 + 3;
  CHECK(weight_of(square.adjacency, v, v + 1) == Approx(std::sqrt(3.0)).epsilon(1e-12));
  CHECK(weight_of(square.adjacency, v, v + 7) == Approx(std::sqrt(3.0)).epsilon(1e-12));
  CHECK(weight_of(square.adjacency, v, v + 8) == Approx(0.05).epsilon(1e-12));
  for (std::size_t m = 0; m < square.adjacency.weight.size(); ++m)
    CHECK(moved.adjacency.weight[m] == Approx(square.adjacency.weight[m]).epsilon(1e-6));
  for (std::size_t i = 0; i < square.points.size(); ++i)
    CHECK(moved.adjacency.mass[i] == Approx(square.adjacency.mass[i]).epsilon(1e-6));

  // A vertex on no face (an unused vertex of a template) changes no other vertex's weight or
  // mass: the same lattice with one more point, far away, in no triangle.
  Patch extra = lattice;
  extra.points.push_back(Point_3(1e20, 0, 0));
  extra.adjacency = adjacency_of(extra.points.size(), extra.triangles);
  meshfit::set_cotangent_weights(extra.adjacency, extra.points, extra.triangles);
  CHECK(std::equal(lattice.adjacency.weight.begin(), lattice.adjacency.weight.end(), extra.adjacency.weight.begin()));
  CHECK(std::equal(lattice.adjacency.mass.begin(), lattice.adjacency.mass.end(), extra.adjacency.mass.begin()));

  // A triangle whose edge is not in the adjacency, and points of another count, are refused.
  Vertex_adjacency path;
  path.neighbours = {1, 0, 2, 1};
  path.offsets = {0, 1, 3, 4};
  CHECK_THROWS_WITH(meshfit::set_cotangent_weights(path, {Point_3(0, 0, 0), Point_3(1, 0, 0), Point_3(0, 1, 0)}, {{0, 1, 2}}), Catch::Contains("triangle 0 has the edge"));
  CHECK_THROWS_WITH(meshfit::set_cotangent_weights(path, {Point_3(0, 0, 0), Point_3(1, 0, 0), Point_3(0, 1, 0)}, {{0, 1, 2}}), Catch::Contains("which is not in the adjacency"));
  CHECK_THROWS_WITH(meshfit::set_cotangent_weights(path, {Point_3(0, 0, 0)}, {}), Catch::Contains("1 points for 3 vertices"));
}

TEST_CASE("displacement: normal_bending is 0 on a plane, about 2√3/R on a sphere, and scales like a curvature",
          "[displacement]") {
  Patch plane = patch(8, 8, [](double i, double j) { return Point_3(0.3 * i + 0.1 * j, 0.2 * j, 0.05 * i - 0.02 * j); });
  for (double b : meshfit::normal_bending(plane.points, plane.triangles)) CHECK(std::abs(b) < 1e-9);
  // A latitude-longitude band of a sphere of radius R, between 50° and 130° from the pole, normals
  // inwards (the triangles' order: the sign is not compared); the band's inner vertices (one ring
  // from its edges). Its cells are nearly rectangles, whose diagonals' weights (about 0) are
  // raised to the floor 0.05: that adds a few per cent here, within the 6 % allowed.
  for (double R : {1.0, 1e-3, 250.0}) {
    const std::size_t nu = 96, nv = 24;
    const double pi = std::acos(-1.0);
    Patch band = patch(nu, nv, [&](double i, double j) {
      const double phi = 2 * pi * i / double(nu), theta = (50 + 80 * j / double(nv)) * pi / 180;
      return Point_3(R * std::sin(theta) * std::cos(phi), R * std::sin(theta) * std::sin(phi), R * std::cos(theta));
    });
    const std::vector<double> b = meshfit::normal_bending(band.points, band.triangles);
    for (std::size_t j = 1; j < nv; ++j)
      for (std::size_t i = 1; i < nu; ++i) CHECK(std::abs(b[j * (nu + 1) + i]) * R == Approx(2 * std::sqrt(3.0)).epsilon(0.06));
  }
  CHECK_THROWS_WITH(meshfit::normal_bending({Point_3(0, 0, 0)}, {{0, 1, 2}}), Catch::Contains("triangle 0 has a corner out of 1 vertices"));
  CHECK_THROWS_WITH(meshfit::bent_laplacian({1.0}, plane.points, plane.triangles), Catch::Contains("1 bending values for 81 points"));
}

TEST_CASE("displacement: with a target Laplacian the thin-plate field reproduces any field whose Laplacian it is",
          "[displacement]") {
  // d* is arbitrary; t = K d* (written here from the weights, not by the library); the held
  // vertices get d*. The energy (K d − t)ᵀ M⁻¹ (K d − t) is 0 at d*, its only minimiser.
  Patch p = patch(9, 7, [](double i, double j) { return Point_3(i + 0.3 * std::sin(j), j + 0.2 * std::cos(i), 0.1 * i * j); });
  meshfit::set_cotangent_weights(p.adjacency, p.points, p.triangles);
  const std::size_t n = p.points.size();
  std::vector<Vector_3> wanted(n), target(n, Vector_3(0, 0, 0));
  for (std::size_t i = 0; i < n; ++i)
    wanted[i] = Vector_3(std::sin(0.7 * double(i)), std::cos(1.3 * double(i)), 0.01 * double(i * i % 17));
  for (std::size_t k = 0; k < n; ++k)
    for (std::size_t m = p.adjacency.offsets[k]; m < p.adjacency.offsets[k + 1]; ++m)
      target[k] = target[k] + p.adjacency.weight[m] * (wanted[k] - wanted[p.adjacency.neighbours[m]]);
  std::vector<bool> held(n, false);
  std::vector<Vector_3> given(n, Vector_3(0, 0, 0));
  for (std::size_t k : {0u, 9u, 40u, 79u}) held[k] = true, given[k] = wanted[k];
  const auto d = meshfit::interpolate_displacements(p.adjacency, held, given, 2, nullptr, &target);
  for (std::size_t i = 0; i < n; ++i) CHECK(std::sqrt((d[i] - wanted[i]).squared_length()) < 1e-8);
  // Without the target the field is the smooth one, not d*.
  const auto plain = meshfit::interpolate_displacements(p.adjacency, held, given, 2);
  double far = 0;
  for (std::size_t i = 0; i < n; ++i) far = std::max(far, std::sqrt((plain[i] - wanted[i]).squared_length()));
  CHECK(far > 0.5);
  // laplacian_of gives the same K x.
  std::vector<Point_3> at(n);
  for (std::size_t i = 0; i < n; ++i) at[i] = Point_3(0, 0, 0) + wanted[i];
  const auto lap = meshfit::laplacian_of(p.adjacency, at);
  for (std::size_t i = 0; i < n; ++i) CHECK(std::sqrt((lap[i] - target[i]).squared_length()) < 1e-12);
  // A target for the membrane energy, or of the wrong size, is refused.
  CHECK_THROWS_WITH(meshfit::interpolate_displacements(p.adjacency, held, given, 1, nullptr, &target), Catch::Contains("a target Laplacian needs order 2"));
  std::vector<Vector_3> short_target(3);
  CHECK_THROWS_WITH(meshfit::interpolate_displacements(p.adjacency, held, given, 2, nullptr, &short_target), Catch::Contains("(3 for 80)"));
}

}  // namespace meshfit_displacement_test
