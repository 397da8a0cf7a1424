#include <meshfit/correspondence.h>

#include "malformed_catalogue.h"
#include "test_helpers.h"

namespace meshfit_correspondence_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using namespace meshfit_test;

namespace {
const meshfit::Curve_network& network() {
  static const meshfit::Curve_network n = meshfit::parse_curve_network(valid_curves(), "curves");
  return n;
}
std::vector<meshfit::Point_3> template_points() {
  return meshfit::parse_mesh_data(valid_template_off(), meshfit::Mesh_format::off, "t").points;
}
}  // namespace

TEST_CASE("correspondence: pairs resolve to network vertices within the tolerance", "[correspondence]") {
  const auto pairs = meshfit::parse_correspondences(
      "# comment\n\n0 0 0 0\n1 1.0000000000001 0 0\n2\t0 1 0\r\n4 0 0 1e0\n", "p", network());
  REQUIRE(pairs.size() == 4);
  CHECK(pairs[1].template_vertex == 1);
  CHECK(network().point(pairs[1].network_vertex) == meshfit::Point_3(1, 0, 0));
  CHECK(pairs[2].where.line == 5);
  CHECK_NOTHROW(meshfit::validate_correspondences(pairs, template_points(), network()));
}

TEST_CASE("correspondence: too few, coplanar or repeated pairs are rejected", "[correspondence]") {
  auto check = [](const char* text, std::size_t line, const char* fragment) {
    require_invalid([&] {
      const auto pairs = meshfit::parse_correspondences(text, "p", network());
      meshfit::validate_correspondences(pairs, template_points(), network());
    }, line, fragment);
  };
  check("0 0 0 0\n1 1 0 0\n2 0 1 0\n", 0, "at least 4 correspondences");
  // Template vertices 0..3 of the octahedron lie in the plane z = 0.
  check("0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n", 0, "template vertices of the 4 correspondences are all coplanar");
  check("0 0 0 0\n1 1 0 0\n2 0 1 0\n4 0 1 0\n", 4, "network vertex 2 is already paired on line 3");
}

TEST_CASE("correspondence: network points all coplanar are rejected", "[correspondence]") {
  const meshfit::Curve_network flat = meshfit::parse_curve_network("5 0 0 0 1 0 0 1 1 0 0 1 0 0 0 0\n", "c");
  require_invalid([&] {
    const auto pairs = meshfit::parse_correspondences("0 0 0 0\n1 1 0 0\n2 1 1 0\n4 0 1 0\n", "p", flat);
    meshfit::validate_correspondences(pairs, template_points(), flat);
  }, 0, "network points of the 4 correspondences are all coplanar");
}

TEST_CASE("correspondence: pairs coplanar on both sides are accepted (auxiliary pairs)", "[correspondence]") {
  const meshfit::Curve_network flat = meshfit::parse_curve_network("5 0 0 0 1 0 0 1 1 0 0 1 0 0 0 0\n", "c");
  // Template vertices 0..3 lie in z = 0, and so do these network points.
  const auto pairs = meshfit::parse_correspondences("0 0 0 0\n1 1 0 0\n2 1 1 0\n3 0 1 0\n", "p", flat);
  CHECK_NOTHROW(meshfit::validate_correspondences(pairs, template_points(), flat, true));
}

TEST_CASE("correspondence: write then read gives the same pairs", "[correspondence]") {
  Temp_dir dir;
  const auto pairs = meshfit::parse_correspondences(valid_pairs(), "p", network());
  meshfit::write_correspondences(dir.file("p.txt"), pairs, network());
  CHECK(meshfit::read_correspondences(dir.file("p.txt"), network()) == pairs);
}

}  // namespace meshfit_correspondence_test
