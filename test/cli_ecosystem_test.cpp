// The command as other programs and people meet it (issue 14): --help per command, --opt=value,
// suggestions, outputs checked before work, --report -, one schema for every report, curve files
// beside the outputs and fed back as inputs, pairs by network-vertex index, CGAL's PLY edge lists.
#include "test_helpers.h"

#include <meshfit/check.h>
#include <meshfit/correspondence.h>
#include <meshfit/curve_network.h>

#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh/IO/PLY.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

namespace meshfit_cli_ecosystem_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using namespace meshfit_test;
using Json = nlohmann::json;

namespace {

const std::string data = MESHFIT_EXAMPLE_DATA_DIR;
const std::string example_inputs = " --template " + q(data + "/template.off") + " --curves " +
                                   q(data + "/curves.polylines.txt") + " --correspondences " + q(data + "/pairs.txt");

Json read_json(const std::string& path) { return Json::parse(read_text(path)); }

std::vector<std::string> keys_of(const Json& j) {
  std::vector<std::string> k;
  for (auto it = j.begin(); it != j.end(); ++it) k.push_back(it.key());
  return k;
}

std::size_t lines_of(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

}  // namespace

TEST_CASE("cli ecosystem: every command answers --help with its own options and exit 0", "[cli][ecosystem]") {
  Temp_dir dir;
  const std::map<std::string, std::vector<std::string>> expected{
      {"fit", {"--correspondences", "--allow-defects", "--iterations", "--kernel", "--curves-in-mesh"}},
      {"deform", {"--correspondences", "--coarse-only", "--fine-level"}},
      {"partition", {"--curves", "--output", "--report"}},
      {"smooth", {"--curves", "--step", "--mc-iterations"}},
      {"check", {"--correspondences", "--merge-tolerance"}},
      {"view", {"--result", "--result-report"}}};
  for (const auto& [command, options] : expected) {
    const Run_result r = run(dir, command + " --help");
    INFO(command << ": " << r.err);
    CHECK(r.status == 0);
    CHECK(r.out.find("meshfit " + command) != std::string::npos);
    CHECK(r.out.find("--template") != std::string::npos);
    for (const std::string& o : options) CHECK(r.out.find(o) != std::string::npos);
    CHECK(run(dir, command + " -h").status == 0);
  }
  CHECK(run(dir, "smooth --help").out.find("--correspondences") == std::string::npos);
  const Run_result top = run(dir, "--help");
  CHECK(top.status == 0);
  for (const auto& kv : expected) CHECK(top.out.find(kv.first) != std::string::npos);
}

TEST_CASE("cli ecosystem: --opt=value works and typos get a suggestion", "[cli][ecosystem]") {
  Temp_dir dir;
  const Run_result eq = run(dir, "check --template=" + q(data + "/template.off") + " --curves=" +
                                     q(data + "/curves.polylines.txt") + " --correspondences=" + q(data + "/pairs.txt"));
  INFO(eq.err);
  CHECK(eq.status == 0);
  CHECK(eq.out.find("problems:              none") != std::string::npos);
  const Run_result typo = run(dir, "fit --templat t.off --curves c --correspondences p --output o.ply");
  CHECK(typo.status == 2);
  CHECK(typo.err.find("did you mean --template?") != std::string::npos);
  const Run_result typo_eq = run(dir, "smooth --template t.off --output o.ply --iteratons=5");
  CHECK(typo_eq.status == 2);
  CHECK(typo_eq.err.find("did you mean --iterations?") != std::string::npos);
  const Run_result command = run(dir, "smoth --template t.off");
  CHECK(command.status == 2);
  CHECK(command.err.find("did you mean smooth?") != std::string::npos);
  // An option given twice is a usage error, as before.
  CHECK(run(dir, "fit" + example_inputs + " --output o.ply --output p.ply").status == 2);
  // view's --result takes one value per occurrence, and a --result-report belongs to the --result before it.
  const std::string view = "view --quiet --template " + q(data + "/template.off") + " --curves " +
                           q(data + "/curves.polylines.txt") + " --output v.html";
  REQUIRE(run(dir, "fit --quiet" + example_inputs + " --output f.ply --report f.json").status == 0);
  CHECK(run(dir, view + " --result f.ply f.ply").status == 2);
  CHECK(run(dir, view + " --result-report f.json --result f.ply").status == 2);
  REQUIRE(run(dir, view + " --result f.ply --result=f.ply --result-report=f.json").status == 0);
  const std::string page = read_text(dir.file("v.html"));
  const std::size_t no_report = page.find("\"report_name\": null"), report = page.find("\"report_name\": \"f.json\"");
  CHECK(no_report != std::string::npos);
  CHECK(report != std::string::npos);
  CHECK(no_report < report);
}

TEST_CASE("cli ecosystem: output paths are checked before any work", "[cli][ecosystem]") {
  Temp_dir dir;
  const auto start = std::chrono::steady_clock::now();
  const Run_result no_dir = run(dir, "fit" + example_inputs + " --output " + q(dir.file("no/such/dir/o.ply")));
  CHECK(no_dir.status == 1);
  const Run_result no_report_dir =
      run(dir, "fit" + example_inputs + " --output " + q(dir.file("o.ply")) + " --report " + q(dir.file("no/r.json")));
  CHECK(no_report_dir.status == 1);
  // The curve file beside the output is an output too: a directory in its place is refused.
  std::filesystem::create_directory(dir.file("o.ply.curves.polylines.txt"));
  const Run_result sidecar = run(dir, "fit" + example_inputs + " --output " + q(dir.file("o.ply")));
  CHECK(sidecar.status == 1);
  CHECK(sidecar.err.find("o.ply.curves.polylines.txt") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir.file("o.ply")));
  // ... unless the curves go inside the mesh file.
  CHECK(run(dir, "fit --quiet --curves-in-mesh" + example_inputs + " --output " + q(dir.file("o.ply"))).status == 0);
  // None of the refusals ran the pipeline (each is a fraction of a second; the fit takes longer).
  CHECK(no_dir.err.find("meshfit: deform") == std::string::npos);
  CHECK(sidecar.err.find("meshfit: deform") == std::string::npos);
  (void)start;
}

TEST_CASE("cli ecosystem: --report - writes the report to stdout", "[cli][ecosystem]") {
  Temp_dir dir;
  const Run_result r = run(dir, "fit --quiet" + example_inputs + " --output " + q(dir.file("o.off")) + " --report -");
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK_FALSE(std::filesystem::exists(dir.file("-")));
  const Json j = Json::parse(r.out);
  CHECK(j["command"] == "fit");
  CHECK(j["completed"] == true);
  CHECK(j["counts"]["regions"] == 12);
  // On failure too (exit 3).
  const Run_result f = run(dir, "fit --quiet --fine-level thesis --max-rounds 1" + example_inputs + " --output " +
                                    q(dir.file("f.off")) + " --report -");
  CHECK(f.status == 3);
  const Json jf = Json::parse(f.out);
  CHECK(jf["completed"] == false);
  CHECK(jf["exit_status"] == 3);
  CHECK(jf["failure"].get<std::string>().find("verification") != std::string::npos);
}

TEST_CASE("cli ecosystem: every report has the same top-level keys, those of doc/report-schema.json", "[cli][ecosystem][report]") {
  Temp_dir dir;
  const Json schema = read_json(data + "/../../doc/report-schema.json");
  std::vector<std::string> required = schema["required"].get<std::vector<std::string>>();
  REQUIRE(!required.empty());
  CHECK(schema["properties"]["schema_version"]["const"] == 1);

  REQUIRE(run(dir, "deform --quiet" + example_inputs + " --output d.ply --report d.json").status == 0);
  REQUIRE(run(dir, "partition --quiet --template d.ply --curves " + q(data + "/curves.polylines.txt") +
                       " --output p.ply --report p.json").status == 0);
  REQUIRE(run(dir, "smooth --quiet --template p.ply --curves " + q(data + "/curves.polylines.txt") +
                       " --output s.ply --report s.json").status == 0);
  REQUIRE(run(dir, "fit --quiet" + example_inputs + " --output f.ply --report f.json").status == 0);
  // Failures: bad input after the paths were checked (exit 1), and the algorithm (exit 3).
  const std::string bad = dir.write("bad.polylines.txt", "3 0 0 0 1 0\n");
  CHECK(run(dir, "fit --quiet --template " + q(data + "/template.off") + " --curves " + q(bad) + " --correspondences " +
                     q(data + "/pairs.txt") + " --output x.ply --report x1.json").status == 1);
  CHECK(run(dir, "partition --quiet --template " + q(data + "/template.off") + " --curves " +
                     q(data + "/curves.polylines.txt") + " --output y.ply --report x3.json").status == 1);
  CHECK(run(dir, "deform --quiet --fine-level thesis --max-rounds 1" + example_inputs + " --output z.ply --report x4.json")
            .status == 3);
  // A usage error found after the paths were checked (a bad option value): exit 2, and the report.
  CHECK(run(dir, "deform --quiet --kernel gaussian" + example_inputs + " --output u.ply --report x2.json").status == 2);
  std::vector<std::string> first;
  for (const std::string name : {"d", "p", "s", "f", "x1", "x2", "x3", "x4"}) {
    INFO(name);
    const Json j = read_json(dir.file(name + ".json"));
    const std::vector<std::string> keys = keys_of(j);
    if (first.empty()) first = keys;
    CHECK(keys == first);
    CHECK(std::set<std::string>(keys.begin(), keys.end()) ==
          std::set<std::string>(required.begin(), required.end()));
    CHECK(j["schema"] == "meshfit-report");
    CHECK(j["schema_version"] == 1);
    const bool ok = name.size() == 1;
    CHECK(j["completed"] == ok);
    CHECK(j["failure"].is_null() == ok);
    CHECK(j["exit_status"] == (ok ? 0 : name == "x1" || name == "x3" ? 1 : name == "x2" ? 2 : 3));
  }
  // Full precision: the minimum angle of the report is the one recomputed from the output mesh to
  // the last bit (the writer's shortest round-trip decimals, parsed back).
  const Json f = read_json(dir.file("f.json"));
  CHECK(f["quality"]["minimum_angle_deg"].get<double>() ==
        meshfit::minimum_angle_degrees(meshfit::read_mesh_data(dir.file("f.ply"))));
  CHECK(f["outputs"]["curves"] == "f.ply.curves.polylines.txt");
  CHECK(f["details"]["verification"]["expected_regions"] == 12);
  // Every key of timings_s, counts, quality and details (and of the blocks in details) is named in
  // doc/report.md; the figure partition and fit share has one name in both (partition keeps the
  // deprecated vertices_moved beside it, as doc/report.md says).
  const std::string doc = read_text(data + "/../../doc/report.md");
  std::function<void(const Json&, const std::string&)> documented = [&](const Json& block, const std::string& where) {
    for (auto it = block.begin(); it != block.end(); ++it) {
      INFO(where << "." << it.key());
      CHECK(doc.find("`" + it.key() + "`") != std::string::npos);
      if (it->is_object()) documented(*it, where + "." + it.key());
    }
  };
  for (const std::string name : {"d", "p", "s", "f"}) {
    const Json j = read_json(dir.file(name + ".json"));
    for (const char* block : {"timings_s", "counts", "quality", "details"}) documented(j[block], name + "." + block);
  }
  const Json p = read_json(dir.file("p.json"));
  CHECK(p["counts"]["vertices_moved_onto_segments"] == p["counts"]["vertices_moved"]);
  CHECK(f["counts"].contains("vertices_moved_onto_segments"));
  CHECK_FALSE(f["counts"].contains("vertices_moved"));
  CHECK(doc.find("`vertices_moved`, **deprecated**") != std::string::npos);
  for (const std::string name : {"d", "f"}) {
    const Json fine = read_json(dir.file(name + ".json"))["details"]["fine_level"];
    for (const char* key : {"approach", "approach_constraints", "approach_scale", "approach_coarse_nodes", "approach_retried"}) {
      INFO(name << ": " << key);
      CHECK(fine.contains(key));
    }
    CHECK((fine["approach"] == "icp" || fine["approach"] == "nearest_vertices" || fine["approach"] == "none"));
  }
  // Strings are escaped: a failure naming a file with a quote and a backslash parses back.
  const std::string odd = dir.write("o\"dd\\name.polylines.txt", "3 0 0 0 1 0\n");
  CHECK(run(dir, "fit --quiet --template " + q(data + "/template.off") + " --curves " + q(odd) + " --correspondences " +
                     q(data + "/pairs.txt") + " --output x.ply --report odd.json").status == 1);
  const Json o = read_json(dir.file("odd.json"));
  CHECK(o["failure"].get<std::string>().find("o\"dd\\name.polylines.txt") != std::string::npos);
}

TEST_CASE("cli ecosystem: progress is a few lines when stderr is not a terminal", "[cli][ecosystem]") {
  Temp_dir dir;
  const Run_result r = run(dir, "fit" + example_inputs + " --output o.ply");
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(lines_of(r.err) <= 25);
  CHECK(r.err.find("iteration (2/100)") == std::string::npos);
  CHECK(r.err.find("\r") == std::string::npos);
  CHECK(r.err.find("meshfit: smooth: iteration") != std::string::npos);
  CHECK(r.err.find("wrote o.ply.curves.polylines.txt") != std::string::npos);
  CHECK(run(dir, "fit --quiet" + example_inputs + " --output o.ply").err.empty());
}

TEST_CASE("cli ecosystem: smooth on a PLY CGAL wrote (every edge listed) holds only flagged edges", "[cli][ecosystem][smooth]") {
  Temp_dir dir;
  REQUIRE(run(dir, "deform --quiet" + example_inputs + " --output d.off").status == 0);
  using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;
  Mesh sm;
  meshfit::read_triangle_mesh(dir.file("d.off"), sm);
  sm.add_property_map<Mesh::Edge_index, double>("e:weight", 1.0);
  {
    std::ofstream out(dir.file("cgal.ply"));
    REQUIRE(CGAL::IO::write_PLY(out, sm));
  }
  REQUIRE(read_text(dir.file("cgal.ply")).find("element edge " + std::to_string(sm.number_of_edges())) !=
          std::string::npos);
  const Run_result r = run(dir, "smooth --iterations 10 --template cgal.ply --output s.ply --report s.json");
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK(r.err.find("carry no curve flag") != std::string::npos);
  const meshfit::Mesh_data before = meshfit::read_mesh_data(dir.file("d.off"));
  const meshfit::Mesh_data after = meshfit::read_mesh_data(dir.file("s.ply"));
  REQUIRE(after.points.size() == before.points.size());
  std::size_t moved = 0;
  for (std::size_t i = 0; i < after.points.size(); ++i) moved += after.points[i] != before.points[i];
  CHECK(moved > before.points.size() / 2);
  const Json j = read_json(dir.file("s.json"));
  CHECK(j["counts"]["fixed_vertices"] == 0);  // a closed mesh: no boundary, no curve edge
  CHECK(j["counts"]["unflagged_edges_ignored"] == sm.number_of_edges());
  CHECK(j["warnings"].size() == 1);
}

TEST_CASE("cli ecosystem: meshfit's outputs fed back as curves, pairs by network vertex index", "[cli][ecosystem]") {
  Temp_dir dir;
  const std::string curves = q(data + "/curves.polylines.txt");
  REQUIRE(run(dir, "deform --quiet" + example_inputs + " --output d.ply").status == 0);
  REQUIRE(run(dir, "partition --quiet --template d.ply --curves " + curves + " --output p.ply --report p.json").status == 0);
  REQUIRE(run(dir, "partition --quiet --curves-in-mesh --template d.ply --curves " + curves + " --output pin.ply").status == 0);
  REQUIRE(run(dir, "partition --quiet --curves-in-mesh --template d.ply --curves " + curves + " --output pin.obj").status == 0);
  CHECK_FALSE(std::filesystem::exists(dir.file("pin.ply.curves.polylines.txt")));
  const Json reference = read_json(dir.file("p.json"));
  // The curve file beside p.ply, the flagged edges of pin.ply and the l lines of pin.obj are each
  // the partitioned mesh's curve edges: partitioning p.ply by them finds every segment an edge
  // already and the same 12 regions. (Partition may move vertices onto segments, so the curves
  // of its output are on its output, not on d.ply.)
  for (const std::string c : {"p.ply.curves.polylines.txt", "pin.ply", "pin.obj"}) {
    INFO(c);
    const Run_result r = run(dir, "partition --quiet --template p.ply --curves " + c + " --output again.ply --report again.json");
    INFO(r.err);
    REQUIRE(r.status == 0);
    const Json j = read_json(dir.file("again.json"));
    CHECK(j["counts"]["regions"] == 12);
    CHECK(j["counts"]["curve_edges"] == reference["counts"]["curve_edges"]);
    CHECK(j["counts"]["segments_already_edges"] == j["counts"]["segments"]);
    CHECK(j["counts"]["segments"] == reference["counts"]["curve_edges"]);
    CHECK(read_text(dir.file("again.ply")) == read_text(dir.file("p.ply")));
  }

  // smooth takes the curve edges beside its input as constraints: their vertices do not move.
  const Run_result sm = run(dir, "smooth --iterations 10 --template p.ply --output s.ply --report s.json");
  INFO(sm.err);
  REQUIRE(sm.status == 0);
  CHECK(sm.err.find("curve edges read from p.ply.curves.polylines.txt") != std::string::npos);
  const Json sj = read_json(dir.file("s.json"));
  CHECK(sj["inputs"]["curve_edges"] == "p.ply.curves.polylines.txt");
  CHECK(sj["counts"]["curve_edges"] == reference["counts"]["curve_edges"]);
  const meshfit::Mesh_data p_mesh = meshfit::read_mesh_data(dir.file("p.ply"));
  const meshfit::Mesh_data s_mesh = meshfit::read_mesh_data(dir.file("s.ply"));
  const meshfit::Curve_network p_curves = meshfit::read_curve_network(dir.file("p.ply.curves.polylines.txt"));
  std::size_t on_curves = 0, moved = 0;
  for (std::size_t i = 0; i < p_mesh.points.size(); ++i) {
    const bool fixed = p_curves.find_vertex(p_mesh.points[i]).has_value();
    on_curves += fixed;
    if (fixed) CHECK(s_mesh.points[i] == p_mesh.points[i]);
    else moved += s_mesh.points[i] != p_mesh.points[i];
  }
  CHECK(on_curves == p_curves.number_of_vertices());
  CHECK(moved > (p_mesh.points.size() - on_curves) / 2);

  // Pairs as `i @k`: the same fit as with coordinates.
  const meshfit::Curve_network network = meshfit::read_curve_network(data + "/curves.polylines.txt");
  std::string by_index = "# template vertex, network vertex by index\n";
  for (const auto& c : meshfit::read_correspondences(data + "/pairs.txt", network))
    by_index += std::to_string(c.template_vertex) + " @" + std::to_string(c.network_vertex) + "\n";
  dir.write("pairs-by-index.txt", by_index);
  REQUIRE(run(dir, "fit --quiet" + example_inputs + " --output a.ply").status == 0);
  REQUIRE(run(dir, "fit --quiet --template " + q(data + "/template.off") + " --curves " + curves +
                       " --correspondences pairs-by-index.txt --output b.ply").status == 0);
  CHECK(read_text(dir.file("a.ply")) == read_text(dir.file("b.ply")));
  dir.write("bad-index.txt", "0 @0\n1 @999\n");
  const Run_result bad = run(dir, "check --template " + q(data + "/template.off") + " --curves " + curves +
                                      " --correspondences bad-index.txt");
  CHECK(bad.status == 1);
  CHECK(bad.err.find("bad-index.txt:2: ") != std::string::npos);
  CHECK(bad.err.find("@999 does not exist") != std::string::npos);
}

TEST_CASE("cli ecosystem: on a terminal, progress is one line that rewrites itself, its percentage rising", "[cli][ecosystem]") {
  Temp_dir dir;
  if (std::system("command -v script > /dev/null 2>&1") != 0) {
    WARN("util-linux's script is missing: the terminal case is not run");
    return;
  }
  // script(1) gives the command a pseudo-terminal; what the terminal received lands in typescript.
  const std::string command = std::string("'") + MESHFIT_CLI + "' fit" + example_inputs + " --output o.ply";
  const std::string cmd = "cd '" + dir.file("") + "' && script -qec " + q(command) + " typescript > /dev/null 2>&1 < /dev/null";
  REQUIRE(std::system(cmd.c_str()) == 0);
  const std::string tty = read_text(dir.file("typescript"));
  std::vector<int> percents;
  for (std::size_t p = tty.find("\r\033[Kmeshfit fit "); p != std::string::npos; p = tty.find("\r\033[Kmeshfit fit ", p + 1))
    percents.push_back(std::stoi(tty.substr(p + 16, 3)));
  INFO(tty);
  CHECK(percents.size() >= 5);
  CHECK(std::is_sorted(percents.begin(), percents.end()));
  CHECK(!percents.empty());
  if (!percents.empty()) CHECK(percents.back() >= 90);
  CHECK(tty.find(" s  smooth: iteration") != std::string::npos);  // elapsed seconds, then the stage
  // The rewriting line ends before the summary, which is plain lines.
  CHECK(tty.find("\r\033[Kmeshfit: fit: ") != std::string::npos);
  CHECK(tty.find("meshfit: smooth: iteration (1/100)\n") == std::string::npos);
}

// ---- --split-regions DIR ------------------------------------------------------------------------

namespace {

using Face_key = std::array<double, 9>;

// A triangle by its corners' coordinates, turned to start at its smallest corner (orientation kept).
Face_key face_key(const meshfit::Point_3& a, const meshfit::Point_3& b, const meshfit::Point_3& c) {
  std::array<std::array<double, 3>, 3> p{{{a.x(), a.y(), a.z()}, {b.x(), b.y(), b.z()}, {c.x(), c.y(), c.z()}}};
  const std::size_t first = static_cast<std::size_t>(std::min_element(p.begin(), p.end()) - p.begin());
  Face_key k{};
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) k[3 * i + j] = p[(first + i) % 3][j];
  return k;
}

std::vector<Face_key> faces_by_position(const meshfit::Mesh_data& m, int region, bool all = false) {
  std::vector<Face_key> keys;
  for (std::size_t f = 0; f < m.triangles.size(); ++f)
    if (all || m.face_patch.at(f) == region) {
      const auto& t = m.triangles[f];
      keys.push_back(face_key(m.points[t[0]], m.points[t[1]], m.points[t[2]]));
    }
  std::sort(keys.begin(), keys.end());
  return keys;
}

// Checks DIR against the output `out`: one file per region holding exactly the output's faces of
// that region, regions.json's counts and vertex map.
void check_split(const Temp_dir& dir, const std::string& output, const std::string& split, const std::string& ext,
                 std::size_t expected_regions) {
  const meshfit::Mesh_data out = meshfit::read_mesh_data(dir.file(output));
  REQUIRE(out.face_patch.size() == out.triangles.size());
  const Json index = read_json(dir.file(split + "/regions.json"));
  CHECK(index["schema"] == "meshfit-regions");
  CHECK(index["mesh"] == output);
  CHECK(index["faces"] == out.triangles.size());
  CHECK(index["vertices"] == out.points.size());
  std::set<int> ids(out.face_patch.begin(), out.face_patch.end());
  REQUIRE(index["regions"].size() == ids.size());
  CHECK(ids.size() == expected_regions);
  std::size_t faces = 0, files = 0;
  for (const Json& r : index["regions"]) {
    const int k = r["region"].get<int>();
    INFO("region " << k);
    CHECK(ids.count(k) == 1);
    const std::string file = r["file"].get<std::string>();
    CHECK(file == "region_" + std::to_string(k) + "." + ext);
    const meshfit::Mesh_data part = meshfit::read_mesh_data(dir.file(split + "/" + file));
    ++files;
    faces += r["faces"].get<std::size_t>();
    CHECK(r["faces"] == part.triangles.size());
    CHECK(r["vertices"] == part.points.size());
    // Exactly the output's faces whose region is k, by vertex positions.
    CHECK(faces_by_position(part, k, true) == faces_by_position(out, k));
    // The map: local vertex i is output vertex map[i], in increasing order, and the region's
    // faces use exactly those vertices.
    const std::vector<std::size_t> map = r["vertex_in_mesh"].get<std::vector<std::size_t>>();
    REQUIRE(map.size() == part.points.size());
    CHECK(std::is_sorted(map.begin(), map.end()));
    std::set<std::size_t> used;
    for (std::size_t f = 0; f < out.triangles.size(); ++f)
      if (out.face_patch[f] == k) used.insert(out.triangles[f].begin(), out.triangles[f].end());
    CHECK(std::vector<std::size_t>(used.begin(), used.end()) == map);
    for (std::size_t i = 0; i < map.size(); ++i) {
      REQUIRE(map[i] < out.points.size());
      CHECK(part.points[i] == out.points[map[i]]);
    }
  }
  CHECK(faces == out.triangles.size());
  std::size_t entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.file(split))) entries += (void(e), 1);
  CHECK(entries == files + 1);  // the region files and regions.json, no temporary file
}

}  // namespace

TEST_CASE("cli ecosystem: --split-regions writes one mesh per region and an index that maps back", "[cli][ecosystem][split]") {
  Temp_dir dir;
  for (const std::string ext : {"ply", "obj"}) {
    SECTION(ext) {
      const std::string output = "fit." + ext;
      const Run_result r = run(dir, "fit" + example_inputs + " --output " + output + " --split-regions parts --report r.json");
      INFO(r.err);
      REQUIRE(r.status == 0);
      CHECK(r.err.find("12 region meshes") != std::string::npos);
      check_split(dir, output, "parts", ext, 12);
      const Json report = read_json(dir.file("r.json"));
      CHECK(report["outputs"]["regions"] == "parts/regions.json");
      // partition writes them too (on fit's output, whose vertices include the network's).
      const Run_result p = run(dir, "partition --quiet --template " + output + " --curves " +
                                        q(data + "/curves.polylines.txt") + " --output p." + ext +
                                        " --split-regions " + q(dir.file("p-parts")));
      INFO(p.err);
      REQUIRE(p.status == 0);
      check_split(dir, "p." + ext, "p-parts", ext, 12);
    }
  }
}

TEST_CASE("cli ecosystem: a --split-regions directory that cannot be used is refused before any work", "[cli][ecosystem][split]") {
  Temp_dir dir;
  const std::string file = dir.write("a-file", "keep");
  const Run_result not_dir = run(dir, "fit" + example_inputs + " --output o.ply --split-regions a-file");
  CHECK(not_dir.status == 1);
  CHECK(not_dir.err.find("a-file") != std::string::npos);
  CHECK(not_dir.err.find("is not a directory") != std::string::npos);
  CHECK(read_text(file) == "keep");
  const Run_result no_parent = run(dir, "partition --template " + q(data + "/template.off") + " --curves " +
                                            q(data + "/curves.polylines.txt") + " --output o.ply --split-regions no/parts");
  CHECK(no_parent.status == 1);
  CHECK(no_parent.err.find("neither does its parent") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir.file("no")));
  // An input where a region file would go.
  std::filesystem::create_directory(dir.file("parts"));
  std::filesystem::copy_file(data + "/template.off", dir.file("parts/region_0.off"));
  const Run_result input = run(dir, "fit --template parts/region_0.off --curves " + q(data + "/curves.polylines.txt") +
                                        " --correspondences " + q(data + "/pairs.txt") +
                                        " --output o.off --split-regions parts");
  CHECK(input.status == 1);
  CHECK(input.err.find("refusing to overwrite") != std::string::npos);
  // None of them ran the pipeline or wrote an output.
  for (const Run_result* r : {&not_dir, &no_parent, &input}) {
    CHECK(r->err.find("meshfit: deform") == std::string::npos);
    CHECK(r->err.find("meshfit: partition:") == std::string::npos);
  }
  CHECK_FALSE(std::filesystem::exists(dir.file("o.ply")));
  CHECK_FALSE(std::filesystem::exists(dir.file("o.off")));
  CHECK(read_text(dir.file("parts/region_0.off")) == read_text(data + "/template.off"));
  // A missing directory whose parent exists is created.
  REQUIRE(run(dir, "fit --quiet" + example_inputs + " --output o.ply --split-regions new-parts").status == 0);
  CHECK(std::filesystem::exists(dir.file("new-parts/regions.json")));
  CHECK(std::filesystem::exists(dir.file("new-parts/region_0.ply")));
}

// ---- vertex attributes: carried by fit, smooth and partition; warned about where they are not ----

namespace {

/// An output OBJ read by the test itself (not meshfit's reader): `v` (and colour), `vt`, `vn`
/// values, and the faces' corners as written (`a`, `a/b`, `a//c`, `a/b/c`, 1-based).
struct Obj_text {
  std::vector<std::array<double, 3>> v;
  std::vector<std::vector<double>> v_extra;  // values after x y z
  std::vector<std::array<double, 2>> vt;
  std::vector<std::array<double, 3>> vn;
  std::vector<std::array<std::array<long, 3>, 3>> f;  // per corner: v, vt, vn (0: none)
};

Obj_text parse_obj_text(const std::string& text) {
  Obj_text o;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "v") {
      std::array<double, 3> p{};
      ls >> p[0] >> p[1] >> p[2];
      o.v.push_back(p);
      std::vector<double> extra;
      for (double x; ls >> x;) extra.push_back(x);
      o.v_extra.push_back(extra);
    } else if (key == "vt") {
      std::array<double, 2> t{};
      ls >> t[0] >> t[1];
      o.vt.push_back(t);
    } else if (key == "vn") {
      std::array<double, 3> n{};
      ls >> n[0] >> n[1] >> n[2];
      o.vn.push_back(n);
    } else if (key == "f") {
      std::array<std::array<long, 3>, 3> face{};
      for (auto& c : face) {
        std::string tok;
        ls >> tok;
        std::size_t at = 0;
        for (int k = 0; k < 3 && at <= tok.size(); ++k) {
          const std::size_t slash = tok.find('/', at);
          const std::string part = tok.substr(at, slash == std::string::npos ? std::string::npos : slash - at);
          c[k] = part.empty() ? 0 : std::stol(part);
          if (slash == std::string::npos) break;
          at = slash + 1;
        }
      }
      o.f.push_back(face);
    }
  }
  return o;
}

/// An ASCII PLY's vertex element read by the test itself: property names and one row of values
/// per vertex, and the faces' corner indices.
struct Ply_text {
  std::vector<std::string> vertex_properties;
  std::vector<std::vector<double>> rows;
  std::vector<std::array<std::size_t, 3>> faces;
  std::size_t column(const std::string& name) const {
    return std::size_t(std::find(vertex_properties.begin(), vertex_properties.end(), name) - vertex_properties.begin());
  }
};

Ply_text parse_ply_text(const std::string& text) {
  Ply_text p;
  std::istringstream in(text);
  std::string line, element;
  std::size_t nv = 0, nf = 0;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream ls(line);
    std::string key, a, b;
    ls >> key >> a >> b;
    if (key == "element") {
      element = a;
      if (a == "vertex") nv = std::stoul(b);
      if (a == "face") nf = std::stoul(b);
    } else if (key == "property" && element == "vertex") {
      p.vertex_properties.push_back(b);
    }
  }
  for (std::size_t i = 0; i < nv && std::getline(in, line); ++i) {
    std::istringstream ls(line);
    std::vector<double> row;
    for (double x; ls >> x;) row.push_back(x);
    p.rows.push_back(row);
  }
  for (std::size_t i = 0; i < nf && std::getline(in, line); ++i) {
    std::istringstream ls(line);
    std::size_t n = 0;
    std::array<std::size_t, 3> t{};
    ls >> n >> t[0] >> t[1] >> t[2];
    p.faces.push_back(t);
  }
  return p;
}

/// For each vertex k >= `fixed`, the largest |value(k) − mean of its neighbours' values| over the
/// channels (the harmonic extension makes it zero), neighbours read from `faces`.
double largest_mean_residual(const std::vector<std::array<std::size_t, 3>>& faces,
                             const std::vector<std::vector<double>>& values, std::size_t fixed) {
  std::vector<std::set<std::size_t>> nb(values.size());
  for (const auto& t : faces)
    for (int k = 0; k < 3; ++k) {
      nb[t[k]].insert(t[(k + 1) % 3]);
      nb[t[(k + 1) % 3]].insert(t[k]);
    }
  double worst = 0;
  for (std::size_t v = fixed; v < values.size(); ++v)
    for (std::size_t c = 0; c < values[v].size(); ++c) {
      double mean = 0;
      for (std::size_t u : nb[v]) mean += values[u][c];
      mean /= double(nb[v].size());
      worst = std::max(worst, std::abs(values[v][c] - mean));
    }
  return worst;
}

}  // namespace

TEST_CASE("cli ecosystem: fit and deform carry the template's texture coordinates, normals and colours to .obj, .ply, .vtp and .vtk outputs",
          "[cli][ecosystem][attributes]") {
  Temp_dir dir;
  const meshfit::Mesh_data t = meshfit::read_mesh_data(data + "/template.off");
  const std::size_t nt = t.points.size();
  // The example's template as an OBJ with texture coordinates (vt k for vertex k) and normals
  // shared through one vn per vertex, and as a PLY with normals and byte colours.
  auto uv_of = [](const meshfit::Point_3& p) { return std::array<double, 2>{0.5 + 0.5 * p.x(), 0.25 - 0.5 * p.z()}; };
  {
    std::ofstream obj(dir.file("template.obj"));
    obj.precision(17);
    for (const auto& p : t.points) obj << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    for (const auto& p : t.points) obj << "vt " << uv_of(p)[0] << ' ' << uv_of(p)[1] << '\n';
    for (const auto& p : t.points) obj << "vn " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    for (const auto& f : t.triangles) {
      obj << 'f';
      for (std::size_t v : f) obj << ' ' << v + 1 << '/' << v + 1 << '/' << v + 1;
      obj << '\n';
    }
  }
  auto colour_of = [](std::size_t i) { return std::array<int, 3>{int(i % 256), int((7 * i) % 256), 255}; };
  {
    std::ofstream ply(dir.file("template.ply"));
    ply.precision(17);
    ply << "ply\nformat ascii 1.0\nelement vertex " << nt
        << "\nproperty double x\nproperty double y\nproperty double z\nproperty double nx\nproperty double ny\n"
           "property double nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face "
        << t.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
    for (std::size_t i = 0; i < nt; ++i) {
      const auto& p = t.points[i];
      const auto c = colour_of(i);
      ply << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << c[0]
          << ' ' << c[1] << ' ' << c[2] << '\n';
    }
    for (const auto& f : t.triangles) ply << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  }
  const std::string rest = " --curves " + q(data + "/curves.polylines.txt") + " --correspondences " + q(data + "/pairs.txt");
  auto not_carried = [&](const std::string& name) {
    const Json j = read_json(dir.file(name));
    std::vector<std::string> w;
    for (const Json& s : j["warnings"])
      if (s.get<std::string>().find("read and not carried") != std::string::npos) w.push_back(s.get<std::string>());
    return w;
  };

  // OBJ in, OBJ out: vt and vn per vertex, every corner naming its vertex's.
  const Run_result obj = run(dir, "fit --quiet --template template.obj" + rest + " --output a.obj --report a.json");
  INFO(obj.err);
  REQUIRE(obj.status == 0);
  CHECK(not_carried("a.json").empty());
  const Obj_text a = parse_obj_text(read_text(dir.file("a.obj")));
  const Obj_text in = parse_obj_text(read_text(dir.file("template.obj")));
  REQUIRE(a.v.size() > nt);  // fit added vertices
  REQUIRE(a.vt.size() == a.v.size());
  REQUIRE(a.vn.size() == a.v.size());
  for (const auto& face : a.f)
    for (const auto& c : face) CHECK((c[1] == c[0] && c[2] == c[0]));
  // The template's vertices keep their values exactly (as the input text gives them).
  for (std::size_t i = 0; i < nt; ++i) {
    CHECK(a.vt[i] == in.vt[i]);
    CHECK(a.vn[i] == in.vn[i]);
  }
  // The added vertices' texture coordinates are the mean of their neighbours' (harmonic
  // extension); their normals have unit length.
  std::vector<std::array<std::size_t, 3>> faces;
  for (const auto& face : a.f) faces.push_back({std::size_t(face[0][0] - 1), std::size_t(face[1][0] - 1), std::size_t(face[2][0] - 1)});
  std::vector<std::vector<double>> uvs;
  for (const auto& x : a.vt) uvs.push_back({x[0], x[1]});
  CHECK(largest_mean_residual(faces, uvs, nt) < 1e-9);
  for (std::size_t i = nt; i < a.vn.size(); ++i)
    CHECK(std::abs(std::hypot(a.vn[i][0], a.vn[i][1], a.vn[i][2]) - 1) < 1e-12);

  // PLY in, PLY out: nx ny nz and red green blue alpha.
  REQUIRE(run(dir, "fit --quiet --template template.ply" + rest + " --output b.ply --report b.json").status == 0);
  CHECK(not_carried("b.json").empty());
  const Ply_text b = parse_ply_text(read_text(dir.file("b.ply")));
  for (const char* name : {"nx", "ny", "nz", "red", "green", "blue", "alpha"})
    CHECK(b.column(name) < b.vertex_properties.size());
  REQUIRE(b.rows.size() > nt);
  const std::size_t r = b.column("red"), nx = b.column("nx");
  for (std::size_t i = 0; i < nt; ++i) {
    const auto c = colour_of(i);
    CHECK(b.rows[i][r] == c[0]);
    CHECK(b.rows[i][r + 1] == c[1]);
    CHECK(b.rows[i][r + 2] == c[2]);
    CHECK(b.rows[i][r + 3] == 255);
    const auto& p = t.points[i];  // the normal given was the template's position
    CHECK(std::array<double, 3>{b.rows[i][nx], b.rows[i][nx + 1], b.rows[i][nx + 2]} ==
          std::array<double, 3>{p.x(), p.y(), p.z()});
  }
  std::vector<std::vector<double>> colours;
  for (const auto& row : b.rows) colours.push_back({row[r], row[r + 1], row[r + 2]});
  CHECK(largest_mean_residual(b.faces, colours, nt) <= 1 + 1e-9);  // every value rounded to a byte
  for (std::size_t i = nt; i < b.rows.size(); ++i) {
    CHECK(std::abs(std::hypot(b.rows[i][nx], b.rows[i][nx + 1], b.rows[i][nx + 2]) - 1) < 1e-6);
    for (std::size_t k = r; k < r + 3; ++k) CHECK((b.rows[i][k] >= 0 && b.rows[i][k] <= 255));
  }
  // The geometry does not depend on the attributes: the same fit as from the plain template.
  REQUIRE(run(dir, "fit --quiet" + example_inputs + " --output c.ply --report c.json").status == 0);
  const Ply_text c = parse_ply_text(read_text(dir.file("c.ply")));
  REQUIRE(c.rows.size() == b.rows.size());
  for (std::size_t i = 0; i < c.rows.size(); ++i)
    CHECK(std::vector<double>(b.rows[i].begin(), b.rows[i].begin() + 3) == c.rows[i]);
  CHECK(c.faces == b.faces);

  // An output that holds no vertex attribute says so in the report and on stderr.
  const Run_result off = run(dir, "fit --template template.obj" + rest + " --output d.off --report d.json");
  REQUIRE(off.status == 0);
  CHECK(not_carried("d.json") ==
        std::vector<std::string>{"template.obj: texture coordinates are read and not carried to the output (OFF holds "
                                 "no vertex attributes: write .obj, .ply, .vtp or .vtk)",
                                 "template.obj: vertex normals are read and not carried to the output (OFF holds no "
                                 "vertex attributes: write .obj, .ply, .vtp or .vtk)"});
  CHECK(off.err.find("warning: template.obj: texture coordinates are read and not carried") != std::string::npos);

  // deform carries them too: the template's vertices keep theirs, the added ones get the mean of
  // their neighbours' (colours, as bytes, within rounding), unit normals.
  const Run_result deform = run(dir, "deform --quiet --template template.ply" + rest + " --output e.ply --report e.json");
  INFO(deform.err);
  REQUIRE(deform.status == 0);
  CHECK(not_carried("e.json").empty());
  const Ply_text e = parse_ply_text(read_text(dir.file("e.ply")));
  REQUIRE(e.rows.size() > nt);  // deform added vertices
  const std::size_t er = e.column("red"), enx = e.column("nx");
  REQUIRE(er < e.vertex_properties.size());
  REQUIRE(enx < e.vertex_properties.size());
  for (std::size_t i = 0; i < nt; ++i) {
    const auto given = colour_of(i);
    CHECK((e.rows[i][er] == given[0] && e.rows[i][er + 1] == given[1] && e.rows[i][er + 2] == given[2]));
    const auto& p = t.points[i];
    CHECK(std::array<double, 3>{e.rows[i][enx], e.rows[i][enx + 1], e.rows[i][enx + 2]} ==
          std::array<double, 3>{p.x(), p.y(), p.z()});
  }
  std::vector<std::vector<double>> deform_colours;
  for (const auto& row : e.rows) deform_colours.push_back({row[er], row[er + 1], row[er + 2]});
  CHECK(largest_mean_residual(e.faces, deform_colours, nt) <= 1 + 1e-9);
  for (std::size_t i = nt; i < e.rows.size(); ++i)
    CHECK(std::abs(std::hypot(e.rows[i][enx], e.rows[i][enx + 1], e.rows[i][enx + 2]) - 1) < 1e-6);

  // .vtp and .vtk carry them as point data: the values of the .obj and .ply outputs of the same fit.
  REQUIRE(run(dir, "fit --quiet --template template.obj" + rest + " --output a.vtp --report av.json").status == 0);
  CHECK(not_carried("av.json").empty());
  const std::string vtp = read_text(dir.file("a.vtp"));
  CHECK(vtp.find("<PointData TCoords=\"TCoords\" Normals=\"Normals\">") != std::string::npos);
  auto vtp_array = [&](const std::string& name) {
    const std::size_t at = vtp.find("Name=\"" + name + "\"");
    REQUIRE(at != std::string::npos);
    std::istringstream text(vtp.substr(vtp.find('>', at) + 1, vtp.find("</DataArray>", at) - vtp.find('>', at) - 1));
    std::vector<double> values;
    for (double x; text >> x;) values.push_back(x);
    return values;
  };
  std::vector<double> obj_uvs, obj_normals;
  for (const auto& x : a.vt) obj_uvs.insert(obj_uvs.end(), {x[0], x[1]});
  for (const auto& x : a.vn) obj_normals.insert(obj_normals.end(), {x[0], x[1], x[2]});
  CHECK(vtp_array("TCoords") == obj_uvs);
  CHECK(vtp_array("Normals") == obj_normals);
  REQUIRE(run(dir, "fit --quiet --template template.ply" + rest + " --output b.vtk --report bv.json").status == 0);
  CHECK(not_carried("bv.json").empty());
  const std::string vtk = read_text(dir.file("b.vtk"));
  auto vtk_array = [&](const std::string& header, std::size_t count) {
    const std::size_t at = vtk.find(header);
    REQUIRE(at != std::string::npos);
    std::istringstream text(vtk.substr(at + header.size()));
    std::vector<double> values(count);
    for (double& x : values) text >> x;
    return values;
  };
  const std::size_t nb = b.rows.size();
  std::vector<double> ply_normals, ply_colours;
  for (const auto& row : b.rows) {
    ply_normals.insert(ply_normals.end(), {row[nx], row[nx + 1], row[nx + 2]});
    ply_colours.insert(ply_colours.end(), {row[r], row[r + 1], row[r + 2], row[r + 3]});
  }
  CHECK(vtk.find("POINT_DATA " + std::to_string(nb) + "\nFIELD attributes 2\n") != std::string::npos);
  CHECK(vtk_array("Normals 3 " + std::to_string(nb) + " double\n", 3 * nb) == ply_normals);
  CHECK(vtk_array("Colors 4 " + std::to_string(nb) + " unsigned_char\n", 4 * nb) == ply_colours);
  // smooth moves vertices only: the attributes are the template's, unchanged.
  REQUIRE(run(dir, "smooth --quiet --template template.obj --output s.obj --report s.json").status == 0);
  CHECK(not_carried("s.json").empty());
  const Obj_text sm = parse_obj_text(read_text(dir.file("s.obj")));
  CHECK(sm.vt == in.vt);
  CHECK(sm.vn == in.vn);
}

namespace {

// The float32 values of the page's blob `id` (base64, little-endian).
std::vector<float> page_floats(const std::string& page, const std::string& id) {
  const std::string open = "id=\"" + id + "\">";
  const std::size_t begin = page.find(open);
  REQUIRE(begin != std::string::npos);
  const std::size_t start = begin + open.size(), end = page.find("</script>", start);
  std::vector<unsigned char> bytes;
  std::uint32_t acc = 0;
  int bits = 0;
  for (std::size_t i = start; i < end; ++i) {
    const char c = page[i];
    const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const char* at = std::strchr(digits, c);
    if (c == '=' || !at || c == '\0') continue;
    acc = (acc << 6) | std::uint32_t(at - digits);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      bytes.push_back(static_cast<unsigned char>((acc >> bits) & 0xff));
    }
  }
  std::vector<float> out(bytes.size() / 4);
  for (std::size_t k = 0; k < out.size(); ++k) {
    const std::uint32_t b = std::uint32_t(bytes[4 * k]) | std::uint32_t(bytes[4 * k + 1]) << 8 |
                            std::uint32_t(bytes[4 * k + 2]) << 16 | std::uint32_t(bytes[4 * k + 3]) << 24;
    std::memcpy(&out[k], &b, 4);
  }
  return out;
}

// `text` (a polylines or pairs file) with every coordinate multiplied by `s`: the first number of
// a polylines line (its count) and of a pairs line (the template vertex) are kept.
std::string scaled_text(const std::string& text, double s) {
  std::istringstream in(text);
  std::ostringstream out;
  out.precision(17);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      out << line << '\n';
      continue;
    }
    std::istringstream words(line);
    std::string first;
    words >> first;
    out << first;
    double x;
    while (words >> x) out << ' ' << x * s;
    out << '\n';
  }
  return out.str();
}

}  // namespace

TEST_CASE("cli ecosystem: a .ply output colours each face by its region beside patch_id, and reads back without a warning",
          "[cli][ecosystem][ply]") {
  Temp_dir dir;
  REQUIRE(run(dir, "fit --quiet" + example_inputs + " --output fit-ascii.ply").status == 0);
  // The same mesh in binary, by the library's writer.
  meshfit::Write_options binary;
  binary.ply_encoding = meshfit::Ply_encoding::binary_little_endian;
  meshfit::write_mesh_data(dir.file("fit-binary.ply"), meshfit::read_mesh_data(dir.file("fit-ascii.ply")), binary);
  for (const char* encoding : {"ascii", "binary"}) {
    INFO(encoding);
    const std::string out = std::string("fit-") + encoding + ".ply";
    const std::string text = read_text(dir.file(out));
    CHECK(text.find("property int patch_id\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n") !=
          std::string::npos);
    // One colour per region, a different one for each: read by CGAL's reader (f:patch_id, f:color).
    CGAL::Surface_mesh<meshfit::Point_3> m;
    std::ifstream in(dir.file(out), std::ios::binary);
    REQUIRE(CGAL::IO::read_PLY(in, m));
    auto [patch, has_patch] = m.property_map<CGAL::Surface_mesh<meshfit::Point_3>::Face_index, int>("f:patch_id");
    auto [colour, has_colour] =
        m.property_map<CGAL::Surface_mesh<meshfit::Point_3>::Face_index, CGAL::IO::Color>("f:color");
    REQUIRE(has_patch);
    REQUIRE(has_colour);
    std::map<int, std::array<int, 3>> colour_of_region;
    bool consistent = true;
    for (auto f : m.faces()) {
      const std::array<int, 3> c{colour[f].r(), colour[f].g(), colour[f].b()};
      consistent = consistent && colour_of_region.emplace(patch[f], c).first->second == c;
    }
    CHECK(consistent);
    std::set<std::array<int, 3>> distinct;
    for (const auto& [region, c] : colour_of_region) distinct.insert(c);
    CHECK(colour_of_region.size() == 12);
    CHECK(distinct.size() == colour_of_region.size());
  }
  // meshfit reads its own .ply back with no warning about the colours (it writes them again from
  // patch_id) ...
  const Run_result back = run(dir, "smooth --template fit-ascii.ply --output back.ply --report back.json");
  REQUIRE(back.status == 0);
  CHECK(back.err.find("colours") == std::string::npos);
  CHECK(read_text(dir.file("back.json")).find("colours") == std::string::npos);
  // ... but face colours that are not the regions' are reported as not carried.
  std::string other = read_text(dir.file("fit-ascii.ply"));
  const std::size_t body = other.find("end_header\n") + 11;
  std::size_t line = body;
  const std::size_t nv = std::stoul(other.substr(other.find("element vertex ") + 15));
  for (std::size_t i = 0; i < nv; ++i) line = other.find('\n', line) + 1;
  const std::size_t eol = other.find('\n', line);
  other.replace(other.rfind(' ', eol) + 1, eol - other.rfind(' ', eol) - 1, "7");  // the first face's blue
  dir.write("other.ply", other);
  const Run_result warned = run(dir, "smooth --template other.ply --output o.ply --report o.json");
  REQUIRE(warned.status == 0);
  CHECK(warned.err.find("other.ply: face colours (red green blue) other than meshfit's region colours are read and "
                        "not carried to the output") != std::string::npos);
}

TEST_CASE("cli ecosystem: an .obj output names a material library beside it, one material per region, in the region's colour",
          "[cli][ecosystem][obj]") {
  Temp_dir dir;
  REQUIRE(run(dir, "fit --quiet" + example_inputs + " --output fit.obj --split-regions parts").status == 0);
  // Every group takes the material of its name, from the library the first lines name.
  std::istringstream obj(read_text(dir.file("fit.obj")));
  std::vector<std::string> lines;
  for (std::string line; std::getline(obj, line);) lines.push_back(line);
  REQUIRE(lines.size() > 2);
  CHECK(lines[1] == "mtllib fit.obj.mtl");
  std::size_t groups = 0;
  for (std::size_t i = 0; i + 1 < lines.size(); ++i)
    if (lines[i].rfind("g ", 0) == 0) {
      ++groups;
      CHECK(lines[i + 1] == "usemtl " + lines[i].substr(2));
    }
  CHECK(groups == 12);
  // The library: 12 materials, each its region's colour (as in the .ply), all different.
  std::istringstream mtl(read_text(dir.file("fit.obj.mtl")));
  std::map<std::string, std::array<double, 3>> kd;
  std::string current;
  for (std::string key; mtl >> key;) {
    if (key == "newmtl") mtl >> current;
    else if (key == "Kd") mtl >> kd[current][0] >> kd[current][1] >> kd[current][2];
    else std::getline(mtl, key);
  }
  REQUIRE(kd.size() == 12);
  std::set<std::array<double, 3>> distinct;
  for (const auto& [name, c] : kd) {
    const auto expected = meshfit::region_colour(std::stoi(name.substr(7)));
    for (int k = 0; k < 3; ++k) CHECK(std::lround(c[k] * 255) == expected[k]);
    distinct.insert(c);
  }
  CHECK(distinct.size() == 12);
  // CGAL's reader still reads the .obj; the region files name no library.
  CGAL::Surface_mesh<meshfit::Point_3> m;
  CHECK(CGAL::IO::read_polygon_mesh(dir.file("fit.obj"), m));
  CHECK(m.number_of_faces() == meshfit::read_mesh_data(dir.file("fit.obj")).triangles.size());
  CHECK(read_text(dir.file("parts/region_0.obj")).find("mtllib") == std::string::npos);
  // The library's path is checked before any work like the output's: never over an input.
  const std::string pairs = read_text(data + "/pairs.txt");
  dir.write("o.obj.mtl", pairs);
  const Run_result over = run(dir, "fit --quiet --template " + q(data + "/template.off") + " --curves " +
                                       q(data + "/curves.polylines.txt") + " --correspondences o.obj.mtl --output o.obj");
  CHECK(over.status == 1);
  CHECK(over.err.find("o.obj.mtl") != std::string::npos);
  CHECK(read_text(dir.file("o.obj.mtl")) == pairs);
  CHECK_FALSE(std::filesystem::exists(dir.file("o.obj")));
  const Run_result clash = run(dir, "fit --quiet" + example_inputs + " --output x.obj --report x.obj.mtl");
  CHECK(clash.status == 1);
  CHECK(clash.err.find("the report is the material library written beside the output") != std::string::npos);
}

TEST_CASE("cli ecosystem: view draws meshes at 1e40 and 1e-45 (float32's range) in a frame of order one",
          "[cli][view]") {
  // The page's float32 positions were the file's coordinates less the centre: Inf at 1e40, zeros
  // below 1e-45.
  const std::string data = MESHFIT_EXAMPLE_DATA_DIR;
  for (const int e : {133, -150}) {
    INFO("scale 2^" << e);
    Temp_dir dir;
    const double s = std::ldexp(1.0, e);
    meshfit::Mesh_data t = meshfit::read_mesh_data(data + "/template.off");
    for (auto& p : t.points) p = meshfit::Point_3(p.x() * s, p.y() * s, p.z() * s);
    meshfit::write_mesh_data(dir.file("t.off"), t);
    dir.write("c.polylines.txt", scaled_text(read_text(data + "/curves.polylines.txt"), s));
    REQUIRE(run(dir, "view --quiet --template t.off --curves c.polylines.txt --output v.html").status == 0);
    const std::string page = read_text(dir.file("v.html"));
    const std::vector<float> positions = page_floats(page, "mf-blob-0");  // the template's
    REQUIRE(positions.size() == 3 * t.points.size());
    float largest = 0;
    for (float x : positions) {
      REQUIRE(std::isfinite(x));
      largest = std::max(largest, std::abs(x));
    }
    CHECK(largest > 1.0f / 16);  // the network's largest side is in [1, 2) on the page
    CHECK(largest < 16.0f);
  }
}

TEST_CASE("cli ecosystem: --threads N limits the commands that compute, and a bad N is a usage error (exit 2)",
          "[cli][ecosystem][threads]") {
  Temp_dir dir;
  for (const std::string command : {"fit", "deform", "partition", "smooth"}) {
    INFO(command);
    CHECK(run(dir, command + " --help").out.find("--threads") != std::string::npos);
  }
  CHECK(run(dir, "check --help").out.find("--threads") == std::string::npos);

  const Run_result one = run(dir, "fit --quiet --threads 1" + example_inputs + " --output f.ply --report f.json");
  INFO(one.err);
  REQUIRE(one.status == 0);
  CHECK(read_json(dir.file("f.json"))["counts"]["regions"] == 12);
  const std::string curves = q(data + "/curves.polylines.txt");
  CHECK(run(dir, "deform --quiet --threads=2" + example_inputs + " --output d.ply").status == 0);
  CHECK(run(dir, "partition --quiet --threads 1 --template d.ply --curves " + curves + " --output p.ply").status == 0);
  CHECK(run(dir, "smooth --quiet --threads 1 --template p.ply --curves " + curves + " --output s.ply").status == 0);

  for (const std::string bad : {"0", "-1", "abc", "1.5", "2x", "99999999999999999999"}) {
    INFO("--threads=" << bad);
    const Run_result r = run(dir, "fit --quiet --threads=" + bad + example_inputs + " --output b.ply --report b.json");
    CHECK(r.status == 2);
    CHECK(r.err.find("--threads needs an integer from 1 to 4096, not '" + bad + "'") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir.file("b.ply")));
    const Json j = read_json(dir.file("b.json"));
    CHECK(j["exit_status"] == 2);
    CHECK(j["stage"] == "usage");
  }
  // As separate words too (CLI11 takes "-1" as a value, or refuses it: either way exit 2).
  for (const std::string bad : {"0", "-1", "abc"}) {
    INFO("--threads " << bad);
    const Run_result r = run(dir, "smooth --quiet --threads " + bad + " --template p.ply --output b.ply");
    CHECK(r.status == 2);
    CHECK(r.err.find("--threads needs an integer from 1 to 4096, not '" + bad + "'") != std::string::npos);
  }
}

TEST_CASE("cli ecosystem: a report named like an output is refused with a message naming that output",
          "[cli][ecosystem]") {
  Temp_dir dir;
  // The report on the mesh output, and on the curve file beside it: exit 1 before any work, a
  // message that says which output, not "input".
  const Run_result mesh = run(dir, "fit --quiet" + example_inputs + " --output o.ply --report o.ply");
  CHECK(mesh.status == 1);
  CHECK(mesh.err.find("the report is the output mesh 'o.ply'") != std::string::npos);
  CHECK(mesh.err.find("input") == std::string::npos);
  const Run_result curves =
      run(dir, "fit --quiet" + example_inputs + " --output o.ply --report o.ply.curves.polylines.txt");
  CHECK(curves.status == 1);
  CHECK(curves.err.find("the report is the curve file written beside the output 'o.ply.curves.polylines.txt'") !=
        std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir.file("o.ply")));
  // The same file under another name, once it exists.
  REQUIRE(run(dir, "fit --quiet" + example_inputs + " --output o.ply").status == 0);
  const Run_result other = run(dir, "fit --quiet" + example_inputs + " --output o.ply --report ./o.ply");
  CHECK(other.status == 1);
  CHECK(other.err.find("the report is the output mesh") != std::string::npos);
  // A report on an input is refused as before, naming the input.
  const Run_result input = run(dir, "fit --quiet" + example_inputs + " --output q.ply --report " + q(data + "/pairs.txt"));
  CHECK(input.status == 1);
  CHECK(input.err.find("the output is the input file") != std::string::npos);
}

}  // namespace meshfit_cli_ecosystem_test
