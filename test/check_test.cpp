#include <meshfit/check.h>

#include "malformed_catalogue.h"
#include "test_helpers.h"

namespace meshfit_check_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using namespace meshfit_test;

TEST_CASE("check: the embedded example is valid and summarised", "[check][example]") {
  const std::string dir = MESHFIT_EXAMPLE_DATA_DIR;
  const meshfit::Check_summary s = meshfit::check_inputs(dir + "/template.off", dir + "/curves.polylines.txt",
                                                         dir + "/pairs.txt");
  CHECK(s.mesh.vertices == 2562);
  CHECK(s.mesh.faces == 5120);
  CHECK(s.mesh.edges == 7680);
  CHECK(s.mesh.boundaries == 0);
  CHECK(s.mesh.genus == 0);
  CHECK(s.feature_points == 10);
  CHECK(s.closed_polylines == 4);
  CHECK(s.correspondences == 8);
  CHECK(s.network_components == 1);
  CHECK(s.problems.empty());
}

TEST_CASE("check: topology of open, holed and higher-genus meshes", "[check]") {
  CHECK(meshfit::summarize_mesh(grid(4)).boundaries == 1);
  CHECK(meshfit::summarize_mesh(grid(4)).genus == 0);
  CHECK(meshfit::summarize_mesh(octahedron()).genus == 0);

  // A torus: an n×m grid with both directions wrapped.
  meshfit::Mesh_data torus;
  const std::size_t n = 8, m = 6;
  for (std::size_t j = 0; j < m; ++j)
    for (std::size_t i = 0; i < n; ++i) {
      const double u = 2 * CGAL_PI * i / n, v = 2 * CGAL_PI * j / m;
      torus.points.emplace_back((3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v));
    }
  auto id = [&](std::size_t i, std::size_t j) { return (j % m) * n + (i % n); };
  for (std::size_t j = 0; j < m; ++j)
    for (std::size_t i = 0; i < n; ++i) {
      torus.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      torus.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  const auto s = meshfit::summarize_mesh(torus);
  CHECK(s.genus == 1);
  CHECK(s.boundaries == 0);
  CHECK(s.components == 1);

  // Two components: an octahedron and a disc with one isolated vertex.
  meshfit::Mesh_data two = octahedron();
  const meshfit::Mesh_data g = grid(2);
  const std::size_t off = two.points.size();
  two.points.insert(two.points.end(), g.points.begin(), g.points.end());
  for (auto t : g.triangles) two.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
  two.points.emplace_back(9, 9, 9);
  const auto s2 = meshfit::summarize_mesh(two);
  CHECK(s2.components == 2);
  CHECK(s2.boundaries == 1);
  CHECK(s2.isolated_vertices == 1);
}

TEST_CASE("check: degenerate faces and isolated vertices are reported, not rejected", "[check]") {
  Temp_dir dir;
  const std::string ok = dir.write("ok.off",
                                   "OFF\n7 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n7 7 7\n"
                                   "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n");
  meshfit::Mesh_read_report r;
  meshfit::read_mesh_data(ok, &r);
  CHECK(r.isolated_vertices == std::vector<std::size_t>{6});
  const std::string deg = dir.write("deg.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n2 0 0\n0 1 0\n3 0 1 2\n3 0 3 1\n");
  meshfit::read_mesh_data(deg, &r);
  CHECK(r.degenerate_faces == std::vector<std::size_t>{0});
}

TEST_CASE("check: the smallest angle of a mesh, in degrees", "[check]") {
  meshfit::Mesh_data m;
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, std::sqrt(3.0) / 2, 0}};
  m.triangles = {{0, 1, 3}};
  CHECK(meshfit::minimum_angle_degrees(m) == Approx(60));
  m.triangles.push_back({0, 1, 2});
  CHECK(meshfit::minimum_angle_degrees(m) == Approx(45));
  m.points.push_back({0, 0, 0});  // a zero-length edge
  m.triangles.push_back({0, 4, 1});
  CHECK(meshfit::minimum_angle_degrees(m) == 0);
}

}  // namespace meshfit_check_test
