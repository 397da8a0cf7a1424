// The command as other programs and people meet it (issue 14): --help per command, --opt=value,
// suggestions, outputs checked before work, --report -, one schema for every report, curve files
// beside the outputs and fed back as inputs, pairs by network-vertex index, CGAL's PLY edge lists.
#include "test_helpers.h"

#include <meshfit/check.h>
#include <meshfit/correspondence.h>
#include <meshfit/curve_network.h>

#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh/IO/PLY.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>
#include <set>

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

TEST_CASE("cli ecosystem: meshfit's outputs fed back as curves; pairs by network vertex index", "[cli][ecosystem]") {
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
