#include <meshfit/exceptions.h>
#include <meshfit/untangle.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

namespace meshfit_untangle_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using meshfit::Point_3;
using meshfit::Vector_3;

namespace {

using Faces = std::vector<std::array<std::size_t, 3>>;

// The n × n grid of the unit square, two triangles per cell, counter-clockwise seen from +z.
struct Grid {
  std::size_t n;
  std::vector<Point_3> points;
  Faces faces;
  std::vector<bool> free;
  explicit Grid(std::size_t size) : n(size) {
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t i = 0; i < n; ++i) {
        points.emplace_back(static_cast<double>(i) / static_cast<double>(n - 1), static_cast<double>(j) / static_cast<double>(n - 1), 0);
        free.push_back(i > 0 && j > 0 && i + 1 < n && j + 1 < n);
      }
    for (std::size_t j = 0; j + 1 < n; ++j)
      for (std::size_t i = 0; i + 1 < n; ++i) {
        const std::size_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
        faces.push_back({a, b, d});
        faces.push_back({a, d, c});
      }
  }
};

// Signed area of a face seen along `normal` (the test's own arithmetic).
double signed_area(const std::vector<Point_3>& p, const std::array<std::size_t, 3>& f, const Vector_3& normal) {
  return CGAL::cross_product(p[f[1]] - p[f[0]], p[f[2]] - p[f[0]]) * normal / 2;
}

// Scrambles the free vertices: each moves by up to `amount` in x and y.
void scramble(std::vector<Point_3>& p, const std::vector<bool>& free, double amount, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amount, amount);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (free[i]) p[i] = Point_3(p[i].x() + u(rng), p[i].y() + u(rng), p[i].z());
}

}  // namespace

TEST_CASE("untangle: a scrambled planar grid with a fixed border comes out with every face positive", "[untangle]") {
  Grid g(12);
  std::vector<Point_3> p = g.points;
  scramble(p, g.free, 0.3, 7);  // about three cells: most faces inverted or crossing
  const Vector_3 up(0, 0, 1);
  std::size_t inverted = 0;
  for (const auto& f : g.faces) inverted += signed_area(p, f, up) <= 0 ? 1 : 0;
  REQUIRE(inverted > 30);

  meshfit::Untangle_report r;
  const std::vector<Point_3> out = meshfit::untangle_faces(p, g.faces, std::vector<Vector_3>(g.faces.size(), up), g.free,
                                                           std::vector<Vector_3>(p.size(), up), 1.0, &r);
  CHECK(r.free_vertices == 100);
  CHECK(r.inverted_before == inverted);
  CHECK(r.inverted_after == 0);
  double smallest = 1, total = 0;
  for (const auto& f : g.faces) {
    smallest = std::min(smallest, signed_area(out, f, up));
    total += signed_area(out, f, up);
  }
  CHECK(smallest > 0);
  CHECK(std::abs(total - 1) < 1e-9);  // positive faces with a fixed border tile the square
  for (std::size_t i = 0; i < p.size(); ++i) {
    CHECK(out[i].z() == 0);  // free vertices move in their plane
    if (!g.free[i]) CHECK(out[i] == p[i]);
  }
}

TEST_CASE("untangle: on a curved patch faces come out positive against the surface normals", "[untangle]") {
  // The grid lifted onto the unit sphere around the north pole, tangled along the surface.
  Grid g(10);
  std::vector<Point_3> p;
  for (const Point_3& q : g.points) {
    const Vector_3 v(q.x() - 0.5, q.y() - 0.5, 1.2);
    p.push_back(CGAL::ORIGIN + v / std::sqrt(v.squared_length()));
  }
  std::vector<Point_3> tangled = p;
  scramble(tangled, g.free, 0.12, 3);
  std::vector<Vector_3> vertex_normal, face_normal;
  for (const Point_3& q : tangled) vertex_normal.push_back(q - CGAL::ORIGIN);
  for (const auto& f : g.faces) face_normal.push_back(CGAL::centroid(p[f[0]], p[f[1]], p[f[2]]) - CGAL::ORIGIN);
  std::size_t inverted = 0;
  for (std::size_t k = 0; k < g.faces.size(); ++k) inverted += signed_area(tangled, g.faces[k], face_normal[k]) <= 0;
  REQUIRE(inverted > 10);

  const auto out = meshfit::untangle_faces(tangled, g.faces, face_normal, g.free, vertex_normal);
  for (std::size_t k = 0; k < g.faces.size(); ++k) CHECK(signed_area(out, g.faces[k], face_normal[k]) > 0);
  // Each vertex moved in the plane orthogonal to its normal.
  for (std::size_t i = 0; i < p.size(); ++i) CHECK(std::abs((out[i] - tangled[i]) * vertex_normal[i]) < 1e-12);
}

TEST_CASE("untangle: the result follows a translation and a scaling of the input", "[untangle]") {
  Grid g(8);
  std::vector<Point_3> p = g.points;
  scramble(p, g.free, 0.25, 11);
  const Vector_3 up(0, 0, 1);
  const std::vector<Vector_3> fn(g.faces.size(), up), vn(p.size(), up);
  const auto out = meshfit::untangle_faces(p, g.faces, fn, g.free, vn);
  for (double scale : {1e-4, 1e4})
    for (const Vector_3& shift : {Vector_3(0, 0, 0), Vector_3(1e6, -2e6, 3e6)}) {
      std::vector<Point_3> q;
      for (const Point_3& x : p) q.push_back(CGAL::ORIGIN + (x - CGAL::ORIGIN) * scale + shift);
      const auto moved = meshfit::untangle_faces(q, g.faces, fn, g.free, vn);
      for (std::size_t i = 0; i < p.size(); ++i) {
        const Point_3 back = CGAL::ORIGIN + ((moved[i] - shift) - CGAL::ORIGIN) / scale;
        CHECK(std::sqrt(CGAL::squared_distance(back, out[i])) < 1e-5);
      }
    }
}

TEST_CASE("untangle: a free vertex inside a polygon it cannot see whole stays finite and is reported", "[untangle]") {
  // A free vertex joined to the corners of a U-shaped octagon, which has no point that sees it
  // whole (its two inner walls face away from each other): some fan triangle is inverted
  // wherever the vertex is.
  std::vector<Point_3> p{{0, 0, 0}, {3, 0, 0}, {3, 3, 0}, {2, 3, 0}, {2, 1, 0}, {1, 1, 0}, {1, 3, 0}, {0, 3, 0}, {1.5, 0.5, 0}};
  Faces faces;
  for (std::size_t k = 0; k < 8; ++k) faces.push_back({k, (k + 1) % 8, 8});
  std::vector<bool> free(p.size(), false);
  free[8] = true;
  const Vector_3 up(0, 0, 1);
  meshfit::Untangle_report r;
  const auto out = meshfit::untangle_faces(p, faces, std::vector<Vector_3>(faces.size(), up), free,
                                           std::vector<Vector_3>(p.size(), up), 1.0, &r);
  std::size_t inverted = 0;
  for (const auto& f : faces) inverted += signed_area(out, f, up) <= 0;
  CHECK(inverted > 0);
  CHECK(r.inverted_after == inverted);
  CHECK(std::isfinite(out[8].x()));
  CHECK(std::isfinite(out[8].y()));
}

TEST_CASE("untangle: mismatched sizes, zero normals and a negative fairness are refused", "[untangle]") {
  Grid g(3);
  const std::vector<Vector_3> fn(g.faces.size(), Vector_3(0, 0, 1)), vn(g.points.size(), Vector_3(0, 0, 1));
  CHECK_THROWS_AS(meshfit::untangle_faces(g.points, g.faces, fn, std::vector<bool>(2, true), vn), meshfit::Invalid_input);
  std::vector<Vector_3> zero = fn;
  zero[0] = Vector_3(0, 0, 0);  // every face has the centre, the only free vertex, as a corner
  CHECK_THROWS_AS(meshfit::untangle_faces(g.points, g.faces, zero, g.free, vn), meshfit::Invalid_input);
  zero = vn;
  zero[4] = Vector_3(0, 0, 0);  // the centre's own normal
  CHECK_THROWS_AS(meshfit::untangle_faces(g.points, g.faces, fn, g.free, zero), meshfit::Invalid_input);
  CHECK_THROWS_AS(meshfit::untangle_faces(g.points, g.faces, fn, g.free, vn, -1.0), meshfit::Invalid_input);
}

}  // namespace meshfit_untangle_test
