// meshfit's outputs read by CGAL's own readers, and CGAL's PLY output read by meshfit (issue 14):
// the oracle is CGAL::IO, not meshfit's reader.
#include "test_helpers.h"

#include <meshfit/correspondence.h>
#include <meshfit/curve_network.h>
#include <meshfit/io.h>

#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh/IO/PLY.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>

#include <fstream>
#include <map>
#include <set>

namespace meshfit_io_interop_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using namespace meshfit_test;
using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;

namespace {

// A 4×4 grid in four regions (quadrants) whose two middle lines are the curve edges.
meshfit::Mesh_data quadrants() {
  meshfit::Mesh_data m = grid(4);
  for (const auto& t : m.triangles) {
    const meshfit::Point_3 c = CGAL::centroid(m.points[t[0]], m.points[t[1]], m.points[t[2]]);
    m.face_patch.push_back((c.x() > 2 ? 1 : 0) + (c.y() > 2 ? 2 : 0));
  }
  auto id = [](std::size_t i, std::size_t j) { return j * 5 + i; };
  for (std::size_t k = 0; k < 4; ++k) {
    m.curve_edges.push_back({id(2, k), id(2, k + 1)});
    m.curve_edges.push_back({id(k, 2), id(k + 1, 2)});
  }
  return m;
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("io interop: a .ply meshfit writes has no edge element, and CGAL reads its patch_id per face", "[io][interop]") {
  Temp_dir dir;
  const meshfit::Mesh_data m = quadrants();
  const std::string path = dir.file("q.ply");
  meshfit::write_mesh_data(path, m);
  const std::string text = read_text(path);
  CHECK(text.find("element edge") == std::string::npos);

  Mesh sm;
  REQUIRE(CGAL::IO::read_polygon_mesh(path, sm));
  CHECK(sm.number_of_vertices() == m.points.size());
  CHECK(sm.number_of_faces() == m.triangles.size());

  Mesh with_properties;
  std::ifstream in(path, std::ios::binary);
  REQUIRE(CGAL::IO::read_PLY(in, with_properties));
  const auto patch = with_properties.property_map<Mesh::Face_index, int>("f:patch_id");
  REQUIRE(patch.second);
  std::size_t f = 0;
  for (auto face : with_properties.faces()) CHECK(patch.first[face] == m.face_patch[f++]);
  std::set<int> regions;
  for (auto face : with_properties.faces()) regions.insert(patch.first[face]);
  CHECK(regions == std::set<int>{0, 1, 2, 3});
}

TEST_CASE("io interop: with curves_in_mesh the .ply's edge element carries int curve, which CGAL reads", "[io][interop]") {
  Temp_dir dir;
  const meshfit::Mesh_data m = quadrants();
  const std::string path = dir.file("q.ply");
  meshfit::Write_options options;
  options.curves_in_mesh = true;
  for (const auto encoding : {meshfit::Ply_encoding::ascii, meshfit::Ply_encoding::binary_little_endian}) {
    options.ply_encoding = encoding;
    meshfit::write_mesh_data(path, m, options);
    Mesh sm;
    std::ifstream in(path, std::ios::binary);
    REQUIRE(CGAL::IO::read_PLY(in, sm));
    const auto curve = sm.property_map<Mesh::Edge_index, int>("e:curve");
    REQUIRE(curve.second);
    std::set<std::pair<std::size_t, std::size_t>> flagged, expected;
    for (auto e : sm.edges())
      if (curve.first[e] == 1) {
        const std::size_t a = sm.vertex(e, 0), b = sm.vertex(e, 1);
        flagged.insert({std::min(a, b), std::max(a, b)});
      }
    for (const auto& e : m.curve_edges) expected.insert({std::min(e[0], e[1]), std::max(e[0], e[1])});
    CHECK(flagged == expected);
    // And meshfit reads the same curve edges back.
    CHECK(meshfit::read_mesh_data(path).curve_edges.size() == m.curve_edges.size());
  }
}

TEST_CASE("io interop: an .obj meshfit writes reads in CGAL's read_polygon_mesh, l lines only on request", "[io][interop]") {
  Temp_dir dir;
  const meshfit::Mesh_data m = quadrants();
  const std::string path = dir.file("q.obj");
  meshfit::write_mesh_data(path, m);
  const std::string text = read_text(path);
  CHECK(count_of(text, "\nl ") == 0);
  CHECK(count_of(text, "\ng region_") == 4);
  Mesh sm;
  REQUIRE(CGAL::IO::read_polygon_mesh(path, sm));
  CHECK(sm.number_of_faces() == m.triangles.size());
  CHECK(meshfit::read_mesh_data(path).face_patch.size() == m.triangles.size());

  meshfit::Write_options options;
  options.curves_in_mesh = true;
  meshfit::write_mesh_data(path, m, options);
  CHECK(count_of(read_text(path), "\nl ") == m.curve_edges.size());
  CHECK(meshfit::read_mesh_data(path).curve_edges.size() == m.curve_edges.size());
}

TEST_CASE("io interop: curve edges beside the output are chains that read back as the curve network", "[io][interop]") {
  Temp_dir dir;
  const meshfit::Mesh_data m = quadrants();
  CHECK(meshfit::curve_edges_path(dir.file("q.ply")) == dir.file("q.ply") + ".curves.polylines.txt");
  // Two lines crossing at the centre: four chains from the centre (degree 4) to the boundary.
  const auto chains = meshfit::curve_edge_chains(m);
  CHECK(chains.size() == 4);
  std::size_t edges = 0;
  for (const auto& c : chains) edges += c.size() - 1;
  CHECK(edges == m.curve_edges.size());
  const std::string path = meshfit::curve_edges_path(dir.file("q.ply"));
  meshfit::write_curve_edges(path, m);
  const meshfit::Curve_network network = meshfit::read_curve_network(path);
  CHECK(network.number_of_segments() == m.curve_edges.size());
  CHECK(network.number_of_vertices() == 9);
  CHECK(network.feature_points().size() == 1);
  // A closed loop is one chain that repeats its first vertex.
  meshfit::Mesh_data loop = grid(2);
  loop.curve_edges = {{0, 1}, {1, 2}, {2, 5}, {5, 8}, {8, 7}, {7, 6}, {6, 3}, {3, 0}};
  const auto loops = meshfit::curve_edge_chains(loop);
  REQUIRE(loops.size() == 1);
  CHECK(loops[0].size() == 9);
  CHECK(loops[0].front() == loops[0].back());
}

TEST_CASE("io interop: a PLY CGAL wrote lists every edge, only edges flagged curve are curve edges", "[io][interop]") {
  Temp_dir dir;
  Mesh sm;
  const meshfit::Mesh_data m = quadrants();
  meshfit::build_triangle_mesh(m, sm);
  // Any edge property makes CGAL's write_PLY list every edge of the mesh.
  auto weight = sm.add_property_map<Mesh::Edge_index, double>("e:weight", 0.5).first;
  (void)weight;
  {
    std::ofstream out(dir.file("all.ply"));
    REQUIRE(CGAL::IO::write_PLY(out, sm));
  }
  REQUIRE(read_text(dir.file("all.ply")).find("element edge " + std::to_string(sm.number_of_edges())) !=
          std::string::npos);
  meshfit::Mesh_read_report report;
  const meshfit::Mesh_data all = meshfit::read_mesh_data(dir.file("all.ply"), &report);
  CHECK(all.curve_edges.empty());
  CHECK(report.unflagged_edges_ignored == sm.number_of_edges());

  // With an int e:curve map, CGAL writes `property int curve`: those edges are the curve edges.
  auto curve = sm.add_property_map<Mesh::Edge_index, int>("e:curve", 0).first;
  std::size_t flagged = 0;
  for (const auto& e : m.curve_edges) {
    curve[sm.edge(sm.halfedge(Mesh::Vertex_index(std::uint32_t(e[0])), Mesh::Vertex_index(std::uint32_t(e[1]))))] = 1;
    ++flagged;
  }
  {
    std::ofstream out(dir.file("flagged.ply"));
    REQUIRE(CGAL::IO::write_PLY(out, sm));
  }
  const meshfit::Mesh_data back = meshfit::read_mesh_data(dir.file("flagged.ply"), &report);
  CHECK(back.curve_edges.size() == flagged);
  CHECK(report.unflagged_edges_ignored == sm.number_of_edges() - flagged);
  // The same file read as a curve network: only the flagged edges.
  const meshfit::Curve_network network = meshfit::read_curve_network(dir.file("flagged.ply"));
  CHECK(network.number_of_segments() == flagged);
  meshfit_test::require_invalid([&] { meshfit::read_curve_network(dir.file("all.ply")); }, 0,
                                "carry no curve flag");
}

TEST_CASE("io interop: curves from OBJ l lines, and strict errors with file and line", "[io][interop][curve_network]") {
  Temp_dir dir;
  const std::string obj = dir.write("c.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                             "l 1 2 3\nl 3 4 1\n");
  const meshfit::Curve_network network = meshfit::read_curve_network(obj);
  CHECK(network.number_of_vertices() == 4);
  CHECK(network.number_of_segments() == 4);
  CHECK(network.number_of_independent_cycles() == 1);
  const std::string bad = dir.write("bad.obj", "v 0 0 0\nv 1 0 0\nl 1 2\nl 2 7\n");
  meshfit_test::require_invalid([&] { meshfit::read_curve_network(bad); }, 4, "vertex");
  const std::string none = dir.write("none.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  meshfit_test::require_invalid([&] { meshfit::read_curve_network(none); }, 0, "no curve edges");
}

TEST_CASE("io interop: pairs by network vertex index '@k', mixed with coordinates, strict errors", "[io][correspondence]") {
  Temp_dir dir;
  const meshfit::Curve_network network =
      meshfit::parse_curve_network("4 0 0 0 1 0 0 0 1 0 0 0 0\n2 0 0 0 0 0 1\n", "c.polylines.txt");
  REQUIRE(network.number_of_vertices() == 4);
  const auto pairs = meshfit::parse_correspondences("0 @0\n1 1 0 0\n# comment\n2 @2\n4 @3\n", "p.txt", network);
  REQUIRE(pairs.size() == 4);
  CHECK(pairs[0].network_vertex == 0);
  CHECK(pairs[1].network_vertex == 1);
  CHECK(pairs[2].network_vertex == 2);
  CHECK(network.point(pairs[3].network_vertex) == meshfit::Point_3(0, 0, 1));
  meshfit_test::require_invalid([&] { meshfit::parse_correspondences("0 @0\n1 @4\n", "p.txt", network); }, 2,
                                "network vertex @4 does not exist");
  meshfit_test::require_invalid([&] { meshfit::parse_correspondences("0 @x\n", "p.txt", network); }, 1,
                                "network vertex index");
  meshfit_test::require_invalid([&] { meshfit::parse_correspondences("0 @1\n1 1 0 0\n", "p.txt", network); }, 2,
                                "already paired on line 1");
  meshfit_test::require_invalid([&] { meshfit::parse_correspondences("0 1\n", "p.txt", network); }, 1,
                                "'template_vertex @network_vertex'");
}

TEST_CASE("io interop: .vtp and .vtk hold regions and curve flags as cell data, lines before polygons", "[io][interop]") {
  Temp_dir dir;
  const meshfit::Mesh_data m = quadrants();
  meshfit::write_mesh_data(dir.file("q.vtp"), m);
  const std::string vtp = read_text(dir.file("q.vtp"));
  CHECK(vtp.find("NumberOfLines=\"8\"") != std::string::npos);
  CHECK(vtp.find("NumberOfPolys=\"32\"") != std::string::npos);
  CHECK(vtp.find("Name=\"region\"") != std::string::npos);
  CHECK(vtp.find("Name=\"curve\"") != std::string::npos);
  meshfit::write_mesh_data(dir.file("q.vtk"), m);
  const std::string vtk = read_text(dir.file("q.vtk"));
  CHECK(vtk.find("CELLS 40 152") != std::string::npos);
  CHECK(vtk.find("CELL_TYPES 40\n3\n") != std::string::npos);
  CHECK(vtk.find("CELL_DATA 40") != std::string::npos);
  // Not a template format: reading one is refused, naming the file.
  meshfit_test::require_invalid([&] { meshfit::read_mesh_data(dir.file("q.vtp")); }, 0, "output format only");
}

TEST_CASE("io interop: a PLY edge element without a curve flag is skipped whatever it holds, a bad flag is an error", "[io][interop]") {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                           "element face 1\nproperty list uchar int vertex_indices\n";
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  meshfit::Mesh_read_report report;
  const meshfit::Mesh_data m = meshfit::parse_mesh_data(
      head + "element edge 2\nproperty list uchar int vertex_indices\nend_header\n" + body + "2 0 1\n2 1 2\n",
      meshfit::Mesh_format::ply, "e.ply", &report);
  CHECK(m.curve_edges.empty());
  CHECK(report.unflagged_edges_ignored == 2);
  const meshfit::Mesh_data flagged = meshfit::parse_mesh_data(
      head + "element edge 2\nproperty int vertex1\nproperty int vertex2\nproperty uchar curve\nend_header\n" + body +
          "0 1 1\n1 2 0\n",
      meshfit::Mesh_format::ply, "f.ply", &report);
  CHECK(flagged.curve_edges == std::vector<std::array<std::size_t, 2>>{{0, 1}});
  CHECK(report.unflagged_edges_ignored == 1);
  meshfit_test::require_invalid(
      [&] {
        meshfit::parse_mesh_data(head + "element edge 1\nproperty int vertex1\nproperty int vertex2\nproperty float curve\n"
                                        "end_header\n" + body + "0 1 1\n",
                                 meshfit::Mesh_format::ply, "g.ply");
      },
      12, "curve");
  meshfit_test::require_invalid(
      [&] {
        meshfit::parse_mesh_data(head + "element edge 1\nproperty int vertex1\nproperty int curve\nend_header\n" + body +
                                     "0 1\n",
                                 meshfit::Mesh_format::ply, "h.ply");
      },
      9, "vertex1 and vertex2");
}

}  // namespace meshfit_io_interop_test
