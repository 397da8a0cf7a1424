#include <meshfit/check.h>
#include <meshfit/correspondence.h>
#include <meshfit/curve_network.h>
#include <meshfit/io.h>

#include <CGAL/Polyhedron_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/graph_traits_Polyhedron_3.h>
#include <CGAL/boost/graph/properties_Polyhedron_3.h>

#include "malformed_catalogue.h"
#include "test_helpers.h"

#include <algorithm>
#include <filesystem>
#include <sstream>

namespace meshfit_io_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using namespace meshfit_test;
using meshfit::Mesh_data;
using meshfit::Mesh_format;

namespace {

Mesh_data parse(const std::string& content, Mesh_format f, meshfit::Mesh_read_report* r = nullptr) {
  return meshfit::parse_mesh_data(content, f, "mem", r);
}

std::string to_text(const Mesh_data& m, Mesh_format f,
                    meshfit::Ply_encoding e = meshfit::Ply_encoding::ascii) {
  std::ostringstream os;
  meshfit::write_mesh_data(os, f, m, e);
  return os.str();
}

void require_same(const Mesh_data& a, const Mesh_data& b) {
  REQUIRE(a.points.size() == b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) CHECK(a.points[i] == b.points[i]);
  CHECK(a.triangles == b.triangles);
  CHECK(a.face_patch == b.face_patch);
  CHECK(a.curve_edges == b.curve_edges);
}

}  // namespace

TEST_CASE("io: every malformed input of the catalogue names its line or byte", "[io][malformed]") {
  const auto cases = malformed_catalogue();
  REQUIRE(cases.size() >= 30);
  for (const Malformed_case& c : cases) {
    SECTION(c.name) {
      Temp_dir dir;
      const std::string path = dir.write("input" + c.extension, c.content);
      const std::string curves = dir.write("curves.polylines.txt", valid_curves());
      auto read = [&] {
        switch (c.kind) {
          case Input_kind::template_mesh: meshfit::read_mesh_data(path); break;
          case Input_kind::curves: meshfit::read_curve_network(path); break;
          case Input_kind::correspondences: {
            const auto network = meshfit::read_curve_network(curves);
            const auto pairs = meshfit::read_correspondences(path, network);
            meshfit::validate_correspondences(pairs, parse(valid_template_off(), Mesh_format::off).points, network);
          }
        }
      };
      try {
        read();
        FAIL("no meshfit::Invalid_input for '" << c.name << "'");
      } catch (const meshfit::Invalid_input& e) {
        INFO(c.name << ": " << e.what());
        CHECK(e.where().file == path);
        CHECK(e.where().line == c.line);
        if (c.byte_offset != SIZE_MAX) CHECK(e.where().byte_offset == c.byte_offset);
        CHECK(std::string(e.what()).find(c.fragment) != std::string::npos);
        CHECK(std::string(e.what()).find('\n') == std::string::npos);
      }
    }
  }
}

TEST_CASE("io: OFF with CRLF, a byte-order mark, tabs and comments parses", "[io]") {
  const std::string text =
      "\xEF\xBB\xBFOFF\r\n# a comment\r\n\t3  1\t0 \r\n0 0 0\r\n1\t0 0  # trailing\r\n0 1 0\r\n\r\n3 0 1 2\r\n";
  // A trailing comment after values is not OFF; the BOM, CRLF, blank lines and tabs are.
  require_invalid([&] { parse(text, Mesh_format::off); }, 5, "vertex attribute");
  const std::string ok = "\xEF\xBB\xBFOFF\r\n# a comment\r\n\t3  1\t0 \r\n0 0 0\r\n1\t0 0\r\n0 1 0\r\n\r\n3 0 1 2\r\n";
  const Mesh_data m = parse(ok, Mesh_format::off);
  CHECK(m.points.size() == 3);
  REQUIRE(m.triangles.size() == 1);
  CHECK(m.triangles[0] == std::array<std::size_t, 3>{0, 1, 2});
}

TEST_CASE("io: COFF colours, counts on the header line and old Mac line ends parse", "[io]") {
  const Mesh_data m = parse("COFF 3 1 0\r0 0 0 255 0 0 255\r1 0 0 0 255 0 255\r0 1 0 0 0 255 255\r3 0 1 2 0.5 0.5 0.5\r",
                            Mesh_format::off);
  CHECK(m.points.size() == 3);
  CHECK(m.triangles.size() == 1);
}

TEST_CASE("io: polygons are triangulated keeping their orientation", "[io]") {
  // An L-shaped hexagon (non-convex: a fan from vertex 0 would fold) and a quad beside it.
  meshfit::Mesh_read_report r;
  const Mesh_data m = parse(
      "OFF\n8 2 0\n0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n3 0 0\n3 1 0\n6 0 1 2 3 4 5\n4 1 6 7 2\n",
      Mesh_format::off, &r);
  CHECK(r.polygons_read == 2);
  CHECK(r.polygons_triangulated == 2);
  REQUIRE(m.triangles.size() == 4 + 2);
  double area = 0;
  for (const auto& t : m.triangles) {
    const auto n = CGAL::cross_product(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]);
    CHECK(n.z() > 0);  // same orientation as the polygons (counter-clockwise seen from +z)
    area += n.z() / 2;
  }
  CHECK(area == Approx(3.0 + 1.0));
  CHECK(r.degenerate_faces.empty());
}

TEST_CASE("io: large and star-shaped polygons are triangulated without folding", "[io]") {
  for (std::size_t k : {40u, 300u, 3000u}) {
    SECTION(std::to_string(k) + " corners") {
      // A star: radius alternating between 1 and 0.4, so half the corners are reflex.
      std::string off = "OFF\n" + std::to_string(k) + " 1 0\n";
      for (std::size_t i = 0; i < k; ++i) {
        const double a = 2 * CGAL_PI * double(i) / double(k), r = (i % 2) ? 0.4 : 1.0;
        off += std::to_string(r * std::cos(a)) + " " + std::to_string(r * std::sin(a)) + " 0\n";
      }
      off += std::to_string(k);
      for (std::size_t i = 0; i < k; ++i) off += " " + std::to_string(i);
      off += "\n";
      const Mesh_data m = parse(off, Mesh_format::off);
      REQUIRE(m.triangles.size() == k - 2);
      using P2 = meshfit::Kernel::Point_2;
      auto xy = [&](std::size_t v) { return P2(m.points[v].x(), m.points[v].y()); };
      std::size_t folded = 0;
      for (const auto& t : m.triangles) folded += CGAL::orientation(xy(t[0]), xy(t[1]), xy(t[2])) != CGAL::LEFT_TURN;
      CHECK(folded == 0);
      CHECK(meshfit::summarize_mesh(m).boundaries == 1);
    }
  }
}

TEST_CASE("io: OBJ with texture and normal indices, negative indices and groups parses", "[io]") {
  const Mesh_data m = parse(
      "mtllib x.mtl\no thing\nv 0 0 0\nv 1 0 0\nv 0 1 0 0.5 0.5 0.5\nvt 0 0\nvn 0 0 1\n"
      "g region_3\ns off\nusemtl a\nf 1/1/1 2/1/1 3//1\ng region_7\nv 1 1 0\nf -3 -1 -2\nl 1 2\n",
      Mesh_format::obj);
  CHECK(m.points.size() == 4);
  REQUIRE(m.triangles.size() == 2);
  CHECK(m.triangles[1] == std::array<std::size_t, 3>{1, 3, 2});
  CHECK(m.face_patch == std::vector<int>{3, 7});
  CHECK(m.curve_edges == std::vector<std::array<std::size_t, 2>>{{0, 1}});
}

TEST_CASE("io: binary PLY little- and big-endian, and ASCII PLY with extra properties", "[io]") {
  const Mesh_data le = parse(binary_ply_tetra(false, false), Mesh_format::ply);
  CHECK(le.points.size() == 4);
  CHECK(le.triangles.size() == 4);

  std::string be = "ply\nformat binary_big_endian 1.0\ncomment c\nelement vertex 3\nproperty double x\n"
                   "property double y\nproperty double z\nelement face 1\n"
                   "property list uchar uint vertex_indices\nend_header\n";
  auto put_be = [&be](const void* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) be += static_cast<const char*>(p)[n - 1 - i];
  };
  const double pts[3][3] = {{0, 0, 0}, {1.5, 0, 0}, {0, 2.5, 0}};
  for (const auto& q : pts)
    for (double c : q) put_be(&c, 8);
  be += '\3';
  for (std::uint32_t i : {0u, 1u, 2u}) put_be(&i, 4);
  const Mesh_data b = parse(be, Mesh_format::ply);
  REQUIRE(b.points.size() == 3);
  CHECK(b.points[2] == meshfit::Point_3(0, 2.5, 0));

  const Mesh_data a = parse(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nelement face 1\nproperty list uchar int vertex_index\nproperty int patch_id\n"
      "element material 1\nproperty list uchar float values\nend_header\n"
      "0 0 0 255\n1 0 0 0\n0 1 0 12\n3 0 1 2 5\n2 0.5 0.25\n",
      Mesh_format::ply);
  CHECK(a.triangles.size() == 1);
  CHECK(a.face_patch == std::vector<int>{5});

  // -1 is a face in no region; below it an id would not read back as written (the writers give
  // every negative id as "no region"; found by fuzz_ply).
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_index\nproperty int patch_id\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n";
  CHECK(parse(header + "3 0 1 2 -1\n", Mesh_format::ply).face_patch == std::vector<int>{-1});
  CHECK_THROWS_WITH(parse(header + "3 0 1 2 -2\n", Mesh_format::ply),
                    Catch::Contains("patch_id -2: a region index is 0 or more, or -1 for a face in no region"));
}

TEST_CASE("io: STL binary and ASCII are welded into shared vertices", "[io]") {
  const Mesh_data oct = octahedron();
  const std::string ascii = to_text(oct, Mesh_format::stl);
  const Mesh_data a = parse(ascii, Mesh_format::stl);
  CHECK(a.points.size() == 6);
  CHECK(a.triangles.size() == 8);
  CHECK(meshfit::summarize_mesh(a).boundaries == 0);

  std::string bin(80, 'x');
  append_le<std::uint32_t>(bin, 8);
  for (const auto& t : oct.triangles) {
    for (int k = 0; k < 3; ++k) append_le<float>(bin, 0.f);
    for (std::size_t v : t)
      for (int k = 0; k < 3; ++k) append_le<float>(bin, static_cast<float>(oct.points[v][k]));
    append_le<std::uint16_t>(bin, 0);
  }
  const Mesh_data b = parse(bin, Mesh_format::stl);
  CHECK(b.points.size() == 6);
  CHECK(b.triangles.size() == 8);
  CHECK(meshfit::summarize_mesh(b).genus == 0);
}

TEST_CASE("io: write then read gives the same mesh, regions and curve edges", "[io][roundtrip]") {
  Mesh_data m = grid(6);
  // Irrational coordinates: the text must carry all 17 digits.
  for (auto& p : m.points) p = meshfit::Point_3(p.x() / 3.0, p.y() * std::sqrt(2.0), 1e-7 * p.x() * p.y());
  for (std::size_t f = 0; f < m.triangles.size(); ++f) m.face_patch.push_back(static_cast<int>(f % 5 == 0 ? 2 : f / 30));
  m.curve_edges = {{0, 1}, {1, 2}, {8, 9}};
  Temp_dir dir;
  for (const char* name : {"m.obj", "m.ply", "m_bin.ply"}) {
    SECTION(name) {
      meshfit::Write_options o;
      o.curves_in_mesh = true;  // (by default the curve edges go to a file of their own: io_interop_test.cpp)
      if (std::string(name) == "m_bin.ply") o.ply_encoding = meshfit::Ply_encoding::binary_little_endian;
      const std::string path = dir.file(name);
      meshfit::write_mesh_data(path, m, o);
      Mesh_data back = meshfit::read_mesh_data(path);
      if (std::string(name) == "m.obj") {
        // OBJ groups the faces by region: the same faces with the same regions, reordered.
        auto by_region = [](Mesh_data d) {
          std::vector<std::pair<int, std::array<std::size_t, 3>>> faces;
          for (std::size_t f = 0; f < d.triangles.size(); ++f) faces.emplace_back(d.face_patch[f], d.triangles[f]);
          std::stable_sort(faces.begin(), faces.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
          for (std::size_t f = 0; f < faces.size(); ++f) d.face_patch[f] = faces[f].first, d.triangles[f] = faces[f].second;
          return d;
        };
        CHECK(std::is_sorted(back.face_patch.begin(), back.face_patch.end()));
        back = by_region(back);
        require_same(back, by_region(m));
      } else {
        require_same(back, m);
      }
    }
  }
  SECTION("off keeps geometry only") {
    meshfit::write_mesh_data(dir.file("m.off"), m);
    const Mesh_data back = meshfit::read_mesh_data(dir.file("m.off"));
    Mesh_data geometry = m;
    geometry.face_patch.clear();
    geometry.curve_edges.clear();
    require_same(back, geometry);
  }
}

TEST_CASE("io: writing is atomic and never overwrites an input", "[io]") {
  Temp_dir dir;
  const std::string input = dir.write("in.off", valid_template_off());
  const Mesh_data m = meshfit::read_mesh_data(input);
  meshfit::Write_options o;
  o.protected_paths = {input};
  require_invalid([&] { meshfit::write_mesh_data(input, m, o); }, 0, "refusing to overwrite an input");
  // Another spelling of the same path is refused as well.
  require_invalid([&] { meshfit::write_mesh_data(dir.file("./sub/../in.off"), m, o); }, 0, "refusing");
  CHECK(read_text(input) == valid_template_off());

  // A mesh that cannot be written leaves nothing behind, not even the temporary file.
  Mesh_data bad = m;
  bad.triangles.push_back({0, 1, 99});
  CHECK_THROWS_AS(meshfit::write_mesh_data(dir.file("out.obj"), bad), meshfit::Invalid_input);
  std::size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.file(""))) { (void)e; ++files; }
  CHECK(files == 1);
  require_invalid([&] { meshfit::write_mesh_data(dir.file("no/such/dir/out.off"), m); }, 0, "does not exist");
  require_invalid([&] { meshfit::write_mesh_data(dir.file("out.xyz"), m); }, 0, "unknown mesh format");
}

TEST_CASE("io: reading into Surface_mesh and Polyhedron_3 keeps vertex order, regions and curve edges",
          "[io][generic]") {
  Mesh_data m = grid(3);
  m.face_patch.assign(m.triangles.size(), 0);
  for (std::size_t f = 9; f < m.triangles.size(); ++f) m.face_patch[f] = 1;
  m.curve_edges = {{4, 5}, {5, 6}};

  SECTION("Surface_mesh") {
    using SM = CGAL::Surface_mesh<meshfit::Point_3>;
    SM sm;
    auto patch = sm.add_property_map<SM::Face_index, int>("f:patch", -1).first;
    auto constrained = sm.add_property_map<SM::Edge_index, bool>("e:c", false).first;
    meshfit::build_triangle_mesh(m, sm, CGAL::parameters::face_patch_map(patch).edge_is_constrained_map(constrained));
    CHECK(sm.number_of_vertices() == m.points.size());
    for (auto v : sm.vertices()) CHECK(sm.point(v) == m.points[v.idx()]);
    const Mesh_data back =
        meshfit::to_mesh_data(sm, CGAL::parameters::face_patch_map(patch).edge_is_constrained_map(constrained));
    CHECK(back.points.size() == m.points.size());
    CHECK(back.triangles == m.triangles);
    CHECK(back.face_patch == m.face_patch);
    CHECK(back.curve_edges.size() == 2);
  }
  SECTION("Polyhedron_3") {
    using P = CGAL::Polyhedron_3<meshfit::Kernel>;
    P poly;
    meshfit::build_triangle_mesh(m, poly);
    CHECK(poly.size_of_vertices() == m.points.size());
    CHECK(poly.size_of_facets() == m.triangles.size());
    const Mesh_data back = meshfit::to_mesh_data(poly);
    for (std::size_t i = 0; i < m.points.size(); ++i) CHECK(back.points[i] == m.points[i]);
    CHECK(meshfit::summarize_mesh(back).boundaries == 1);
  }
}

#ifdef MESHFIT_CGAL_DATA_DIR
TEST_CASE("io: CGAL's sample meshes read with the expected topology", "[io][real]") {
  struct Expect { const char* file; std::size_t vertices, faces, boundaries, genus; };
  // Counts from the files' headers. Each is one closed component, so genus = (2 - V + E - F) / 2
  // with E = 3F/2: the elephant (V - F/2 = -4) has genus 3, the camel and the cow genus 0.
  const Expect expected[] = {{"elephant.off", 2775, 5558, 0, 3},
                             {"camel.off", 9770, 19536, 0, 0},
                             {"cow.off", 2904, 5804, 0, 0},
                             {"elephant-with-holes.off", 0, 0, 0, 0}};
  for (const Expect& e : expected) {
    SECTION(e.file) {
      meshfit::Mesh_read_report r;
      const Mesh_data m = meshfit::read_mesh_data(std::string(MESHFIT_CGAL_DATA_DIR) + "/" + e.file, &r);
      const meshfit::Mesh_summary s = meshfit::summarize_mesh(m);
      if (e.vertices == 0) {  // the holed elephant: just open
        CHECK(s.boundaries > 0);
        CHECK(s.faces == m.triangles.size());
        return;
      }
      CHECK(s.vertices == e.vertices);
      CHECK(s.faces == e.faces);
      CHECK(s.boundaries == e.boundaries);
      CHECK(s.genus == e.genus);
      CHECK(s.components == 1);
      CHECK(s.edges == 3 * s.faces / 2);
    }
  }
}
#endif

// ---- ASE templates ------------------------------------------------------------------------------

namespace {

const std::string ase_octahedron_path = MESHFIT_TEST_DATA_DIR "/octahedron.ase";

std::vector<std::string> lines_of_file(const std::string& path) {
  std::istringstream in(read_text(path));
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += l + "\n";
  return s;
}

// The 1-based line of `lines` that starts (after blanks) with `start`, the `nth` such (0-based).
std::size_t line_starting(const std::vector<std::string>& lines, const std::string& start, int nth = 0) {
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::size_t b = lines[i].find_first_not_of(" \t");
    if (b != std::string::npos && lines[i].compare(b, start.size(), start) == 0 && nth-- == 0) return i + 1;
  }
  FAIL("no line starts with " << start);
  return 0;
}

}  // namespace

TEST_CASE("io: an ASE octahedron reads to 6 vertices and 8 faces with its coordinates", "[io][ase]") {
  meshfit::Mesh_read_report r;
  const Mesh_data m = meshfit::read_mesh_data(ase_octahedron_path, &r);
  CHECK(r.format == Mesh_format::ase);
  CHECK(meshfit::mesh_format_of("T.ASE") == Mesh_format::ase);
  // The file's coordinates and faces, written independently here: the octahedron of radius 1.5
  // centred at (0, 0, 0.25).
  const std::vector<meshfit::Point_3> expected{{1.5, 0, 0.25}, {-1.5, 0, 0.25}, {0, 1.5, 0.25},
                                               {0, -1.5, 0.25}, {0, 0, 1.75}, {0, 0, -1.25}};
  REQUIRE(m.points.size() == 6);
  for (std::size_t i = 0; i < 6; ++i) CHECK(m.points[i] == expected[i]);
  REQUIRE(m.triangles.size() == 8);
  CHECK(m.triangles == octahedron().triangles);
  CHECK(m.face_patch.empty());
  CHECK(m.curve_edges.empty());
  // The file has a *MESH_NORMALS block: read past, reported.
  CHECK(r.dropped_attributes == std::vector<std::string>{"normals (*MESH_NORMALS)"});
  // As a CGAL mesh: closed, genus 0.
  CGAL::Surface_mesh<meshfit::Point_3> sm;
  meshfit::read_triangle_mesh(ase_octahedron_path, sm);
  CHECK(sm.number_of_vertices() == 6);
  CHECK(sm.number_of_faces() == 8);
  CHECK(CGAL::is_closed(sm));
  // An output format it is not.
  Temp_dir dir;
  require_invalid([&] { meshfit::write_mesh_data(dir.file("o.ase"), m); }, 0, "input format only");
}

TEST_CASE("io: ASE objects are merged, each object's face indices offset by the vertices before it", "[io][ase]") {
  std::vector<std::string> lines = lines_of_file(ase_octahedron_path);
  // A second object: the same octahedron moved by +10 in x (its *MESH_VERTEX lines rewritten).
  const std::size_t begin = line_starting(lines, "*GEOMOBJECT") - 1;
  std::vector<std::string> second(lines.begin() + static_cast<std::ptrdiff_t>(begin), lines.end());
  for (std::string& l : second)
    if (l.find("*MESH_VERTEX ") != std::string::npos) {
      std::istringstream in(l);
      std::string key;
      int i = 0;
      double x = 0, y = 0, z = 0;
      in >> key >> i >> x >> y >> z;
      l = "*MESH_VERTEX " + std::to_string(i) + " " + std::to_string(x + 10) + " " + std::to_string(y) + " " +
          std::to_string(z);
    }
  lines.insert(lines.end(), second.begin(), second.end());
  const Mesh_data m = parse(joined(lines), Mesh_format::ase);
  REQUIRE(m.points.size() == 12);
  REQUIRE(m.triangles.size() == 16);
  const Mesh_data one = meshfit::read_mesh_data(ase_octahedron_path);
  for (std::size_t i = 0; i < 6; ++i) {
    CHECK(m.points[i] == one.points[i]);
    CHECK(m.points[6 + i] == meshfit::Point_3(one.points[i].x() + 10, one.points[i].y(), one.points[i].z()));
  }
  for (std::size_t f = 0; f < 8; ++f) {
    CHECK(m.triangles[f] == one.triangles[f]);
    CHECK(m.triangles[8 + f] ==
          std::array<std::size_t, 3>{one.triangles[f][0] + 6, one.triangles[f][1] + 6, one.triangles[f][2] + 6});
  }
}

TEST_CASE("io: every malformed ASE names its file, line and problem", "[io][ase][malformed]") {
  const std::vector<std::string> good = lines_of_file(ase_octahedron_path);
  REQUIRE(parse(joined(good), Mesh_format::ase).triangles.size() == 8);  // the cases below break a valid file
  const std::size_t numvertex = line_starting(good, "*MESH_NUMVERTEX");
  const std::size_t numfaces = line_starting(good, "*MESH_NUMFACES");
  const std::size_t vertex2 = line_starting(good, "*MESH_VERTEX ", 2);
  const std::size_t face3 = line_starting(good, "*MESH_FACE ", 3);
  const std::size_t vertex_list = line_starting(good, "*MESH_VERTEX_LIST");
  const std::size_t face_list = line_starting(good, "*MESH_FACE_LIST");
  const std::size_t geomobject = line_starting(good, "*GEOMOBJECT");
  const std::size_t mesh = line_starting(good, "*MESH {");
  auto with = [&](std::size_t line, const std::string& text) {
    std::vector<std::string> l = good;
    l[line - 1] = text;
    return l;
  };
  auto check = [&](const std::vector<std::string>& lines, std::size_t line, const std::string& fragment) {
    INFO("expected line " << line << ": " << fragment);
    require_invalid([&] { parse(joined(lines), Mesh_format::ase); }, line, fragment);
  };
  SECTION("more vertices declared than listed: the end of the list") {
    check(with(numvertex, "*MESH_NUMVERTEX 7"), vertex_list + 7, "has 6 vertices but *MESH_NUMVERTEX (line " +
                                                                      std::to_string(numvertex) + ") declares 7");
  }
  SECTION("fewer faces declared than listed: the first face too many") {
    check(with(numfaces, "*MESH_NUMFACES 7"), face_list + 8, "face index 7 is out of range");
  }
  SECTION("more faces declared than listed") {
    check(with(numfaces, "*MESH_NUMFACES 9"), face_list + 9, "has 8 faces but *MESH_NUMFACES");
  }
  SECTION("a corner out of range") {
    check(with(face3, "*MESH_FACE 3: A: 3 B: 6 C: 4"), face3, "corner B of face 3: vertex 6 is out of range");
  }
  SECTION("a non-numeric coordinate") {
    check(with(vertex2, "*MESH_VERTEX 2 0.0 one 0.25"), vertex2, "expected a number for y coordinate, found 'one'");
  }
  SECTION("a non-numeric corner") {
    check(with(face3, "*MESH_FACE 3: A: 3 B: x C: 4"), face3, "expected a non-negative integer for vertex index");
  }
  SECTION("vertices out of order") {
    check(with(vertex2, "*MESH_VERTEX 3 0 1.5 0.25"), vertex2, "expected vertex 2, found vertex 3");
  }
  SECTION("a vertex line with a value missing") {
    check(with(vertex2, "*MESH_VERTEX 2 0 1.5"), vertex2, "expected '*MESH_VERTEX i x y z'");
  }
  SECTION("a face without its B corner") {
    check(with(face3, "*MESH_FACE 3: A: 3 C: 4"), face3, "expected '*MESH_FACE i: A: a B: b C: c'");
  }
  SECTION("the face list missing") {
    std::vector<std::string> l = good;
    l.erase(l.begin() + static_cast<std::ptrdiff_t>(face_list - 1), l.begin() + static_cast<std::ptrdiff_t>(face_list + 9));
    check(l, line_starting(l, "*MESH_NORMALS") + 4, "the *MESH (opened at line " + std::to_string(mesh) +
                                                         ") has no *MESH_FACE_LIST (it declares 8 faces)");
  }
  SECTION("the vertex list before its count") {
    std::vector<std::string> l = good;
    std::swap(l[numvertex - 1], l[numfaces - 1]);
    l.erase(l.begin() + static_cast<std::ptrdiff_t>(numfaces - 1));  // (the count, now on numfaces's line)
    check(l, vertex_list - 1, "*MESH_VERTEX_LIST before *MESH_NUMVERTEX");
  }
  SECTION("a block not closed") {
    std::vector<std::string> l = good;
    l.pop_back();
    check(l, geomobject, "'*GEOMOBJECT' opened here is not closed");
  }
  SECTION("no header") {
    std::vector<std::string> l(good.begin() + 1, good.end());
    check(l, 1, "expected the ASE header *3DSMAX_ASCIIEXPORT");
  }
  SECTION("no mesh at all") {
    check({"*3DSMAX_ASCIIEXPORT 200", "*SCENE {", "}"}, 3, "no *GEOMOBJECT with a *MESH");
  }
  SECTION("the file is named") {
    Temp_dir dir;
    const std::string path = dir.write("broken.ase", joined(with(vertex2, "*MESH_VERTEX 2 0 x 0.25")));
    try {
      meshfit::read_mesh_data(path);
      FAIL("no error");
    } catch (const meshfit::Invalid_input& e) {
      CHECK(e.where().file == path);
      CHECK(std::string(e.what()).find(path + ":" + std::to_string(vertex2)) != std::string::npos);
    }
  }
}

// ---- attributes read and not carried ------------------------------------------------------------

TEST_CASE("io: the readers keep per-vertex texture coordinates, normals and colours, and list the attributes they drop",
          "[io][attributes]") {
  meshfit::Mesh_read_report r;
  SECTION("OBJ texture coordinates and normals, one per vertex: kept") {
    const Mesh_data m = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0.5\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n",
                              Mesh_format::obj, &r);
    CHECK(r.dropped_attributes.empty());
    CHECK(m.vertex_uvs == std::vector<std::array<double, 2>>{{0, 0}, {1, 0.5}, {0, 1}});
    CHECK(m.vertex_normals == std::vector<std::array<double, 3>>{{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
    CHECK(m.vertex_colors.empty());
  }
  SECTION("OBJ relative and v//vn indices") {
    const Mesh_data m = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 1 0 0\nvn 0 1 0\nf 1//-2 2//-1 3//-1\n", Mesh_format::obj, &r);
    CHECK(r.dropped_attributes.empty());
    CHECK(m.vertex_normals == std::vector<std::array<double, 3>>{{1, 0, 0}, {0, 1, 0}, {0, 1, 0}});
    CHECK(m.vertex_uvs.empty());
  }
  SECTION("OBJ texture seam (a vertex with two vt): dropped, said why") {
    const Mesh_data m = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nvt 0.5 0.5\n"
                              "f 1/1 2/2 3/3\nf 2/5 4/4 3/3\n",
                              Mesh_format::obj, &r);
    CHECK(r.dropped_attributes == std::vector<std::string>{"texture coordinates (vt), not one per vertex"});
    CHECK(m.vertex_uvs.empty());
  }
  SECTION("OBJ vt index past the last one") {
    require_invalid([] { parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/2\n", Mesh_format::obj); }, 5,
                    "texture coordinate index 2 refers past the last one");
  }
  SECTION("OBJ vertex colours: kept when every vertex has one") {
    Mesh_data m = parse("v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 0.5\nf 1 2 3\n", Mesh_format::obj, &r);
    CHECK(r.dropped_attributes.empty());
    CHECK(m.vertex_colors == std::vector<std::array<double, 4>>{{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 0.5, 1}});
    m = parse("v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", Mesh_format::obj, &r);
    CHECK(r.dropped_attributes == std::vector<std::string>{"vertex colours (v x y z r g b), not on every vertex"});
    CHECK(m.vertex_colors.empty());
  }
  SECTION("PLY normals, colours and texture coordinates: kept; other properties dropped") {
    const Mesh_data m =
        parse("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "property float nx\nproperty float ny\nproperty float nz\nproperty uchar red\nproperty uchar green\n"
              "property uchar blue\nproperty float s\nproperty float t\nproperty float quality\n"
              "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
              "0 0 0 0 0 1 255 0 0 0 0 1\n1 0 0 0 0 1 0 255 0 1 0 1\n0 1 0 0 0 1 0 0 51 0 1 1\n3 0 1 2\n",
              Mesh_format::ply, &r);
    CHECK(r.dropped_attributes == std::vector<std::string>{"other vertex properties (quality)"});
    CHECK(m.vertex_normals == std::vector<std::array<double, 3>>{{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
    CHECK(m.vertex_colors == std::vector<std::array<double, 4>>{{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 0.2, 1}});
    CHECK(m.vertex_uvs == std::vector<std::array<double, 2>>{{0, 0}, {1, 0}, {0, 1}});
  }
  SECTION("PLY incomplete sets (u without v, nx ny without nz): dropped") {
    const Mesh_data m =
        parse("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "property float u\nproperty float nx\nproperty float ny\n"
              "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
              "0 0 0 0 0 1\n1 0 0 1 0 1\n0 1 0 0 0 1\n3 0 1 2\n",
              Mesh_format::ply, &r);
    CHECK(r.dropped_attributes == std::vector<std::string>{"vertex normals (nx ny)", "texture coordinates (u)"});
    CHECK(m.vertex_uvs.empty());
    CHECK(m.vertex_normals.empty());
  }
  SECTION("written and read back: OBJ and PLY (ASCII and binary) keep them exactly; colours as bytes") {
    Mesh_data m = octahedron();
    for (std::size_t i = 0; i < m.points.size(); ++i) {
      m.vertex_uvs.push_back({0.1 * double(i), 1.0 / 3 + double(i)});
      m.vertex_normals.push_back({m.points[i].x(), m.points[i].y(), m.points[i].z()});
      m.vertex_colors.push_back({double(i) / 5, 1 - double(i) / 5, 0.2, 1});
    }
    for (const Mesh_format f : {Mesh_format::obj, Mesh_format::ply}) {
      const Mesh_data back = parse(to_text(m, f), f, &r);
      CHECK(r.dropped_attributes.empty());
      CHECK(back.vertex_uvs == m.vertex_uvs);
      CHECK(back.vertex_normals == m.vertex_normals);
      REQUIRE(back.vertex_colors.size() == m.vertex_colors.size());
      for (std::size_t i = 0; i < m.vertex_colors.size(); ++i)
        for (int k = 0; k < 4; ++k)
          CHECK(std::abs(back.vertex_colors[i][k] - m.vertex_colors[i][k]) <= (f == Mesh_format::ply ? 0.5 / 255 + 1e-12 : 0));
    }
    std::ostringstream binary;
    meshfit::write_mesh_data(binary, Mesh_format::ply, m, meshfit::Ply_encoding::binary_little_endian);
    const Mesh_data back = parse(binary.str(), Mesh_format::ply, &r);
    CHECK(back.vertex_uvs == m.vertex_uvs);
    CHECK(back.vertex_normals == m.vertex_normals);
    CHECK(back.vertex_colors.size() == m.vertex_colors.size());
  }
  SECTION("COFF, NOFF, STOFF") {
    parse("COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n3 0 1 2\n", Mesh_format::off, &r);
    CHECK(r.dropped_attributes == std::vector<std::string>{"vertex colours (COFF)"});
    parse("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n", Mesh_format::off, &r);
    CHECK(r.dropped_attributes == std::vector<std::string>{"vertex normals (NOFF)"});
    parse("STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n", Mesh_format::off, &r);
    CHECK(r.dropped_attributes == std::vector<std::string>{"texture coordinates (STOFF)"});
  }
  SECTION("plain files: none") {
    parse(valid_template_off(), Mesh_format::off, &r);
    CHECK(r.dropped_attributes.empty());
    parse(to_text(octahedron(), Mesh_format::obj), Mesh_format::obj, &r);
    CHECK(r.dropped_attributes.empty());
    Mesh_data m = octahedron();
    m.face_patch = {0, 0, 0, 0, 1, 1, 1, 1};
    parse(to_text(m, Mesh_format::ply), Mesh_format::ply, &r);  // patch_id is carried
    CHECK(r.dropped_attributes.empty());
  }
}

// ---- one mesh per region ------------------------------------------------------------------------

TEST_CASE("io: split_by_region gives each region its faces and the vertices they use, in order", "[io][split]") {
  Mesh_data m = grid(3);  // 16 vertices, 18 triangles
  // Regions 2, 0, 5 in stripes of rows (row j has triangles 6j .. 6j+5); region 5 also takes one
  // triangle of row 0.
  m.face_patch.assign(m.triangles.size(), 0);
  for (std::size_t t = 0; t < 18; ++t) m.face_patch[t] = t < 6 ? 2 : t < 12 ? 0 : 5;
  m.face_patch[1] = 5;
  const std::vector<meshfit::Region_mesh> regions = meshfit::split_by_region(m);
  REQUIRE(regions.size() == 3);
  CHECK(regions[0].region == 0);
  CHECK(regions[1].region == 2);
  CHECK(regions[2].region == 5);
  std::size_t faces = 0;
  std::vector<int> seen(m.triangles.size(), 0);
  for (const meshfit::Region_mesh& r : regions) {
    faces += r.mesh.triangles.size();
    REQUIRE(r.face_in_full.size() == r.mesh.triangles.size());
    REQUIRE(r.vertex_in_full.size() == r.mesh.points.size());
    CHECK(std::is_sorted(r.vertex_in_full.begin(), r.vertex_in_full.end()));
    CHECK(std::adjacent_find(r.vertex_in_full.begin(), r.vertex_in_full.end()) == r.vertex_in_full.end());
    CHECK(r.mesh.face_patch == std::vector<int>(r.mesh.triangles.size(), r.region));
    std::vector<bool> used(r.mesh.points.size(), false);
    for (std::size_t f = 0; f < r.mesh.triangles.size(); ++f) {
      const std::size_t full = r.face_in_full[f];
      ++seen[full];
      CHECK(m.face_patch[full] == r.region);
      for (int k = 0; k < 3; ++k) {
        const std::size_t local = r.mesh.triangles[f][k];
        REQUIRE(local < r.mesh.points.size());
        used[local] = true;
        CHECK(r.vertex_in_full[local] == m.triangles[full][k]);
        CHECK(r.mesh.points[local] == m.points[m.triangles[full][k]]);
      }
    }
    CHECK(std::count(used.begin(), used.end(), false) == 0);  // only the vertices its faces use
  }
  CHECK(faces == m.triangles.size());
  CHECK(std::count(seen.begin(), seen.end(), 1) == static_cast<std::ptrdiff_t>(m.triangles.size()));
  // Region 2 is row 0 without triangle 1 (0, 5, 4): vertex 4 is in none of its faces.
  CHECK(regions[1].vertex_in_full == std::vector<std::size_t>{0, 1, 2, 3, 5, 6, 7});
  // Without regions: one region 0 holding everything.
  const auto whole = meshfit::split_by_region(grid(2));
  REQUIRE(whole.size() == 1);
  CHECK(whole[0].region == 0);
  CHECK(whole[0].mesh.triangles == grid(2).triangles);
  // Vertex attributes go with the vertices: each local vertex has its full vertex's values.
  Mesh_data a = m;
  for (std::size_t v = 0; v < a.points.size(); ++v) {
    const double x = static_cast<double>(v);
    a.vertex_uvs.push_back({x / 16, 1 - x / 16});
    a.vertex_normals.push_back({0, x, 1});
    a.vertex_colors.push_back({x / 32, 0.5, 1, 1});
  }
  for (const meshfit::Region_mesh& r : meshfit::split_by_region(a)) {
    REQUIRE(r.mesh.vertex_uvs.size() == r.mesh.points.size());
    REQUIRE(r.mesh.vertex_normals.size() == r.mesh.points.size());
    REQUIRE(r.mesh.vertex_colors.size() == r.mesh.points.size());
    for (std::size_t i = 0; i < r.mesh.points.size(); ++i) {
      CHECK(r.mesh.vertex_uvs[i] == a.vertex_uvs[r.vertex_in_full[i]]);
      CHECK(r.mesh.vertex_normals[i] == a.vertex_normals[r.vertex_in_full[i]]);
      CHECK(r.mesh.vertex_colors[i] == a.vertex_colors[r.vertex_in_full[i]]);
    }
  }
  CHECK(regions[0].mesh.vertex_uvs.empty());  // none in, none out
  CHECK(meshfit::region_file_name(3, Mesh_format::ply) == "region_3.ply");
  CHECK(meshfit::region_file_name(-1, Mesh_format::obj) == "region_-1.obj");
}

TEST_CASE("io: the region directory is checked before writing and region files are written atomically", "[io][split]") {
  Temp_dir dir;
  Mesh_data m = octahedron();
  m.face_patch = {0, 0, 0, 0, 1, 1, 1, 1};
  const std::string file = dir.write("a-file", "x");
  require_invalid([&] { meshfit::check_region_directory(file, Mesh_format::ply, {}); }, 0, "is not a directory");
  require_invalid([&] { meshfit::write_region_meshes(file, m, Mesh_format::ply); }, 0, "is not a directory");
  CHECK(read_text(file) == "x");
  require_invalid([&] { meshfit::check_region_directory(dir.file("no/such"), Mesh_format::ply, {}); }, 0,
                  "neither does its parent");
  // An input where a region file would go is refused, whatever the regions turn out to be.
  std::filesystem::create_directory(dir.file("regions"));
  const std::string in12 = dir.write("regions/region_12.obj", "v 0 0 0\n");
  require_invalid([&] { meshfit::check_region_directory(dir.file("regions"), Mesh_format::obj, {in12}); }, 0,
                  "refusing to overwrite");
  meshfit::check_region_directory(dir.file("regions"), Mesh_format::ply, {in12});  // another extension: fine
  meshfit::check_region_directory(dir.file("new"), Mesh_format::ply, {});         // created when writing
  CHECK_FALSE(std::filesystem::exists(dir.file("new")));
  const auto written = meshfit::write_region_meshes(dir.file("new"), m, Mesh_format::ply);
  REQUIRE(written.size() == 2);
  for (const auto& r : written) {
    const Mesh_data back = meshfit::read_mesh_data(dir.file("new/" + meshfit::region_file_name(r.region, Mesh_format::ply)));
    CHECK(back.triangles == r.mesh.triangles);
    CHECK(back.face_patch == r.mesh.face_patch);
    CHECK(back.points.size() == 5);  // four around the equator and one pole
  }
  // No temporary file left behind.
  std::size_t entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.file("new"))) entries += (void(e), 1);
  CHECK(entries == 2);
}

}  // namespace meshfit_io_test
