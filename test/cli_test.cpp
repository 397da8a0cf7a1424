// Runs the meshfit command as a user would and checks exit statuses and messages.
#include "malformed_catalogue.h"
#include <meshfit/correspondence.h>
#include "test_helpers.h"

#include <meshfit/curve_network.h>
#include <meshfit/deform.h>
#include <meshfit/smooth.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>

namespace meshfit_cli_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using namespace meshfit_test;

namespace {

// The --template, --curves and --correspondences options of a run where the malformed case's
// file `bad` replaces the input of its kind and the others are valid.
std::string inputs_with(const Temp_dir& dir, const Malformed_case& c, const std::string& bad) {
  const std::string t = c.kind == Input_kind::template_mesh ? bad : dir.write("t.off", valid_template_off());
  const std::string cu = c.kind == Input_kind::curves ? bad : dir.write("c.polylines.txt", valid_curves());
  const std::string p = c.kind == Input_kind::correspondences ? bad : dir.write("p.txt", valid_pairs());
  return " --template " + q(t) + " --curves " + q(cu) + " --correspondences " + q(p);
}

}  // namespace

TEST_CASE("cli: check on the embedded example succeeds and prints the summary", "[cli]") {
  Temp_dir dir;
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  const Run_result r = run(dir, "check --template " + q(d + "/template.off") + " --curves " +
                                    q(d + "/curves.polylines.txt") + " --correspondences " + q(d + "/pairs.txt"));
  CHECK(r.status == 0);
  CHECK(r.err.empty());
  CHECK(r.out.find("vertices:            2562") != std::string::npos);
  CHECK(r.out.find("feature points:      10") != std::string::npos);
  CHECK(r.out.find("genus:               0") != std::string::npos);
  CHECK(r.out.find("problems:              none") != std::string::npos);
}

TEST_CASE("cli: every malformed input gives one line with its location and exit status 1", "[cli][malformed]") {
  for (const Malformed_case& c : malformed_catalogue()) {
    SECTION(c.name) {
      Temp_dir dir;
      const std::string bad = dir.write("bad" + c.extension, c.content);
      const Run_result r = run(dir, "check" + inputs_with(dir, c, bad));
      INFO(c.name << ": " << r.err);
      CHECK(r.status == 1);
      CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
      std::string location = bad;
      if (c.line) location += ":" + std::to_string(c.line) + ": ";
      else if (c.byte_offset != SIZE_MAX) location += ": byte " + std::to_string(c.byte_offset) + ": ";
      CHECK(r.err.find(location) != std::string::npos);
      CHECK(r.err.find(c.fragment) != std::string::npos);
    }
  }
}

TEST_CASE("cli: the help gives each option's default as the library has it", "[cli]") {
  Temp_dir dir;
  const std::string help = run(dir, "fit --help").out;
  // The text of "(default X)" at the end of the option's line.
  auto default_in_help = [&](const std::string& option) {
    const std::size_t at = help.find("\n  " + option + " ");
    if (at == std::string::npos) return std::string("no line for ") + option;
    const std::string line = help.substr(at + 1, help.find('\n', at + 1) - at - 1);
    const std::size_t open = line.rfind("(default ");
    if (open == std::string::npos || line.back() != ')') return "no default in: " + line;
    return line.substr(open + 9, line.size() - open - 10);
  };
  const meshfit::Deform_options d;
  CHECK(default_in_help("--kernel") == meshfit::to_string(d.rbf_kernel));
  CHECK(default_in_help("--fine-level") == meshfit::to_string(d.fine_level));
  CHECK(default_in_help("--curve-density") == (d.curve_density == meshfit::Curve_density::refine ? "refine" : "drop"));
  CHECK(default_in_help("--max-rounds") == std::to_string(d.flip_prevention_rounds));
  CHECK(default_in_help("--iterations") == std::to_string(meshfit::internal::default_smoothing_iterations));
  CHECK(std::stod(default_in_help("--merge-tolerance")) == meshfit::default_merge_tolerance);
  CHECK(std::stod(default_in_help("--step")) == meshfit::internal::Flow_settings().step);
  CHECK(std::stod(default_in_help("--smooth-tolerance")) == meshfit::internal::default_smoothing_tolerance);
}

TEST_CASE("cli: usage errors exit with status 2", "[cli]") {
  Temp_dir dir;
  CHECK(run(dir, "").status == 2);
  CHECK(run(dir, "frobnicate").status == 2);
  CHECK(run(dir, "check --template").status == 2);
  CHECK(run(dir, "check --template a.off --curves c.txt").status == 2);
  CHECK(run(dir, "check --template a.off --curves c.txt --correspondences p.txt --bogus").status == 2);
  const Run_result missing = run(dir, "check --template " + q(dir.file("none.off")) + " --curves c --correspondences p");
  CHECK(missing.status == 1);
  CHECK(missing.err.find("cannot open") != std::string::npos);
  CHECK(run(dir, "--help").status == 0);
  // A directory where a file is expected is invalid input, named.
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  const Run_result folder = run(dir, "check --template " + q(d + "/template.off") + " --curves " + q(d) +
                                         " --correspondences " + q(d + "/pairs.txt"));
  CHECK(folder.status == 1);
  CHECK(folder.err.find("not a regular file") != std::string::npos);
  CHECK(run(dir, "check --template " + q(d + "/template.off") + " --curves " + q(d + "/curves.polylines.txt") +
                     " --correspondences " + q(d + "/pairs.txt") + " --merge-tolerance 0.5").status == 2);
  CHECK(run(dir, "--version").out.find("meshfit ") == 0);
}

TEST_CASE("cli: deform writes the deformed mesh and a report", "[cli][deform]") {
  Temp_dir dir;
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  const std::string inputs = " --template " + q(d + "/template.off") + " --curves " + q(d + "/curves.polylines.txt") +
                             " --correspondences " + q(d + "/pairs.txt");
  SECTION("both levels") {
    const Run_result r = run(dir, "deform" + inputs + " --output " + q(dir.file("out.ply")) + " --report " + q(dir.file("r.json")));
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK(r.err.find("meshfit: deform: ") != std::string::npos);
    const meshfit::Mesh_data m = meshfit::read_mesh_data(dir.file("out.ply"));
    CHECK(m.points.size() >= 2562);
    const std::string json = read_text(dir.file("r.json"));
    CHECK(json.find("\"flips_remaining\": 0") != std::string::npos);
    CHECK(json.find("\"network_vertices_embedded\": 210") != std::string::npos);
  }
  SECTION("coarse only, quietly") {
    const Run_result r = run(dir, "deform --quiet --coarse-only" + inputs + " --output " + q(dir.file("c.off")));
    CHECK(r.status == 0);
    CHECK(r.err.empty());
    CHECK(meshfit::read_mesh_data(dir.file("c.off")).points.size() == 2562);
  }
  SECTION("flips left after the allowed rounds: status 3, report written, no output") {
    const Run_result r = run(dir, "deform --fine-level thesis --max-rounds 1" + inputs + " --output " + q(dir.file("f.off")) + " --report " + q(dir.file("f.json")));
    CHECK(r.status == 3);
    CHECK(r.err.find("deform: ") != std::string::npos);
    CHECK(r.err.find("still flip") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir.file("f.off")));
    CHECK(read_text(dir.file("f.json")).find("\"flips_remaining\": 0") == std::string::npos);
  }
  SECTION("the output may not be an input, and options are checked") {
    const std::string copy = dir.write("t.off", read_text(d + "/template.off"));
    const std::string args = " --template " + q(copy) + " --curves " + q(d + "/curves.polylines.txt") +
                             " --correspondences " + q(d + "/pairs.txt");
    const Run_result same = run(dir, "deform" + args + " --output " + q(copy));
    CHECK(same.status == 1);
    CHECK(same.err.find("refusing to overwrite an input") != std::string::npos);
    CHECK(read_text(copy) == read_text(d + "/template.off"));
    CHECK(run(dir, "deform" + args + " --output " + q(dir.file("o.off")) + " --kernel gaussian").status == 2);
    // A choice of three names all three.
    const Run_result shape = run(dir, "deform" + args + " --output " + q(dir.file("o.off")) + " --fine-shape bent");
    CHECK(shape.status == 2);
    CHECK(shape.err.find("--fine-shape must be auto, approach or template, not 'bent'") != std::string::npos);
    CHECK(run(dir, "deform" + args + " --output " + q(dir.file("o.off")) + " --max-rounds 0").status == 2);
    CHECK(run(dir, "deform" + args).status == 2);
    const Run_result clash = run(dir, "deform" + args + " --output " + q(dir.file("same.json")) + " --report " + q(dir.file("same.json")));
    CHECK(clash.status == 1);
  }
  SECTION("a template without faces is invalid input") {
    const std::string bare = dir.write("bare.off", "OFF\n5 0 0\n1 0 0\n0 1 0\n0 0 1\n-1 0 0\n0 0 -1\n");
    const std::string p = dir.write("p.txt", "0 1.8680995472317172 0 -0.25\n1 -1.8680995472317172 0 -0.25\n"
                                             "2 0.29999999999999999 0 0.69208019766498163\n"
                                             "3 0.29999999999999999 0.73754142049024984 -0.25\n");
    const Run_result r = run(dir, "deform --template " + q(bare) + " --curves " + q(d + "/curves.polylines.txt") +
                                      " --correspondences " + q(p) + " --output " + q(dir.file("o.off")));
    CHECK(r.status == 1);
    CHECK(r.err.find("no face") != std::string::npos);
  }
}

TEST_CASE("cli: partition makes the deformed example's curves edges and labels 12 regions", "[cli][partition]") {
  Temp_dir dir;
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  const std::string curves = q(d + "/curves.polylines.txt");
  REQUIRE(run(dir, "deform --quiet --template " + q(d + "/template.off") + " --curves " + curves +
                       " --correspondences " + q(d + "/pairs.txt") + " --output " + q(dir.file("deformed.ply")))
              .status == 0);
  const meshfit::Mesh_data before = meshfit::read_mesh_data(dir.file("deformed.ply"));
  SECTION("to PLY with a report") {
    // (--curves-in-mesh: the curve edges in the PLY's edge element, flagged curve.)
    const Run_result r = run(dir, "partition --curves-in-mesh --template " + q(dir.file("deformed.ply")) + " --curves " +
                                      curves + " --output " + q(dir.file("p.ply")) + " --report " + q(dir.file("p.json")));
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK(r.err.find("meshfit: partition: labelling regions") != std::string::npos);
    const meshfit::Mesh_data m = meshfit::read_mesh_data(dir.file("p.ply"));
    CHECK(m.points.size() == before.points.size());
    CHECK(m.triangles.size() == before.triangles.size());
    CHECK(m.curve_edges.size() >= 220);  // a segment split at a vertex moved onto it is two edges
    REQUIRE(m.face_patch.size() == m.triangles.size());
    CHECK(*std::max_element(m.face_patch.begin(), m.face_patch.end()) == 11);
    const std::string json = read_text(dir.file("p.json"));
    CHECK(json.find("\"regions\": 12") != std::string::npos);
    CHECK(json.find("\"segments_not_embedded\": 0") != std::string::npos);
  }
  SECTION("to OBJ, quietly") {
    const Run_result r = run(dir, "partition --quiet --template " + q(dir.file("deformed.ply")) + " --curves " + curves +
                                      " --output " + q(dir.file("p.obj")));
    CHECK(r.status == 0);
    CHECK(r.err.empty());
    const std::string obj = read_text(dir.file("p.obj"));
    CHECK(obj.find("g region_11") != std::string::npos);
    // Issue 14: no l lines (CGAL's OBJ reader refuses them); the curve edges are beside the mesh.
    CHECK(obj.find("\nl ") == std::string::npos);
    CHECK(meshfit::read_curve_network(dir.file("p.obj.curves.polylines.txt")).number_of_segments() >= 220);
  }
  SECTION("curves that are not on the mesh: status 1 naming the network vertex") {
    const Run_result r = run(dir, "partition --template " + q(d + "/template.off") + " --curves " + curves +
                                      " --output " + q(dir.file("x.off")));
    CHECK(r.status == 1);
    CHECK(r.err.find("network vertex 0 (") != std::string::npos);
    CHECK(r.err.find("curves.polylines.txt") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir.file("x.off")));
  }
}

TEST_CASE("cli: partition reports curves that cross without a shared vertex: status 3, no output", "[cli][partition]") {
  Temp_dir dir;
  meshfit::Mesh_data grid = meshfit_test::grid(4);
  meshfit::write_mesh_data(dir.file("grid.off"), grid);
  // (0,1)-(4,3) cuts the sheet from side to side; (0,3)-(4,1) has an end on each side of it.
  const std::string curves = dir.write("c.polylines.txt", "2 0 1 0 4 3 0\n2 0 3 0 4 1 0\n");
  const Run_result r = run(dir, "partition --template " + q(dir.file("grid.off")) + " --curves " + q(curves) +
                                    " --output " + q(dir.file("o.ply")) + " --report " + q(dir.file("o.json")));
  CHECK(r.status == 3);
  CHECK(r.err.find("1 of 2 segments could not be made mesh edges") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir.file("o.ply")));
  CHECK(nlohmann::json::parse(read_text(dir.file("o.json")))["details"]["not_embedded_segments"] ==
        nlohmann::json::array({1}));
}

TEST_CASE("cli: smooth holds the curves fixed and keeps regions and curve edges", "[cli][smooth]") {
  Temp_dir dir;
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  const std::string curves = d + "/curves.polylines.txt";
  const std::string deformed = dir.file("deformed.ply");
  REQUIRE(run(dir, "deform --quiet --template " + q(d + "/template.off") + " --curves " + q(curves) +
                       " --correspondences " + q(d + "/pairs.txt") + " --output " + q(deformed)).status == 0);
  const meshfit::Mesh_data before = meshfit::read_mesh_data(deformed);
  const meshfit::Curve_network network = meshfit::read_curve_network(curves);
  std::vector<std::size_t> on_curves;
  for (std::size_t i = 0; i < before.points.size(); ++i)
    if (network.find_vertex(before.points[i])) on_curves.push_back(i);
  REQUIRE(on_curves.size() == network.number_of_vertices());

  SECTION("with --curves: network vertices fixed, curve edges written") {
    const Run_result r = run(dir, "smooth --curves-in-mesh --template " + q(deformed) + " --curves " + q(curves) +
                                      " --output " + q(dir.file("s.ply")) + " --report " + q(dir.file("s.json")));
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK(r.err.find("meshfit: smooth: ") != std::string::npos);
    const meshfit::Mesh_data after = meshfit::read_mesh_data(dir.file("s.ply"));
    REQUIRE(after.points.size() == before.points.size());
    CHECK(after.triangles == before.triangles);
    for (std::size_t i : on_curves) CHECK(after.points[i] == before.points[i]);
    std::size_t moved = 0;
    for (std::size_t i = 0; i < after.points.size(); ++i) moved += after.points[i] != before.points[i];
    CHECK(moved > before.points.size() / 2);
    CHECK(!after.curve_edges.empty());
    const std::string json = read_text(dir.file("s.json"));
    CHECK(json.find("\"completed\": true") != std::string::npos);
    // At most the default 100 iterations; fewer when the flows converge first.
    const nlohmann::json report = nlohmann::json::parse(json);
    CHECK(report["counts"]["iterations"].get<int>() >= 1);
    CHECK(report["counts"]["iterations"].get<int>() <= 100);
    CHECK(json.find("\"network_vertices_on_mesh\": " + std::to_string(network.number_of_vertices())) != std::string::npos);

    SECTION("a .ply with curve edges and regions: its curve edges are the constraints") {
      meshfit::Mesh_data tagged = after;
      tagged.face_patch.assign(tagged.triangles.size(), 0);
      for (std::size_t f = 0; f < tagged.triangles.size(); ++f) tagged.face_patch[f] = int(f % 3);
      meshfit::Write_options with_curves;
      with_curves.curves_in_mesh = true;
      meshfit::write_mesh_data(dir.file("tagged.ply"), tagged, with_curves);
      const Run_result again = run(dir, "smooth --quiet --curves-in-mesh --iterations 10 --step 0.5 --template " + q(dir.file("tagged.ply")) +
                                            " --output " + q(dir.file("again.ply")));
      INFO(again.err);
      CHECK(again.status == 0);
      CHECK(again.err.empty());
      const meshfit::Mesh_data out = meshfit::read_mesh_data(dir.file("again.ply"));
      CHECK(out.face_patch == tagged.face_patch);
      CHECK(out.curve_edges.size() == tagged.curve_edges.size());
      for (const auto& e : tagged.curve_edges) {
        CHECK(out.points[e[0]] == tagged.points[e[0]]);
        CHECK(out.points[e[1]] == tagged.points[e[1]]);
      }
    }
  }
  SECTION("usage errors and bad input") {
    const std::string args = " --template " + q(deformed) + " --output " + q(dir.file("o.off"));
    CHECK(run(dir, "smooth" + args + " --step 2").status == 2);
    CHECK(run(dir, "smooth" + args + " --step 0").status == 2);
    const Run_result negative = run(dir, "smooth" + args + " --smooth-tolerance -0.1");
    CHECK(negative.status == 2);
    CHECK(negative.err.find("--smooth-tolerance") != std::string::npos);
    CHECK(run(dir, "smooth" + args + " --smooth-tolerance nan").status == 2);
    CHECK(run(dir, "smooth" + args + " --iterations -1").status == 2);
    CHECK(run(dir, "smooth" + args + " --mc-iterations many").status == 2);
    CHECK(run(dir, "smooth" + args + " --correspondences p.txt").status == 2);
    CHECK(run(dir, "smooth --template " + q(deformed)).status == 2);
    CHECK(run(dir, "smooth --template " + q(deformed) + " --output " + q(deformed)).status == 1);
    CHECK(run(dir, "smooth --template " + q(dir.file("none.off")) + " --output " + q(dir.file("o.off"))).status == 1);
    const Run_result zero = run(dir, "smooth --quiet --iterations 0" + args);
    CHECK(zero.status == 0);
    CHECK(meshfit::read_mesh_data(dir.file("o.off")).points == before.points);
  }
}

TEST_CASE("cli: fit runs the whole pipeline on the embedded example", "[cli][fit]") {
  Temp_dir dir;
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  const std::string inputs = " --template " + q(d + "/template.off") + " --curves " + q(d + "/curves.polylines.txt") +
                             " --correspondences " + q(d + "/pairs.txt");
  SECTION("to PLY with a report: verified, regions and curve edges, template indices kept") {
    const Run_result r = run(dir, "fit" + inputs + " --output " + q(dir.file("fit.ply")) + " --report " + q(dir.file("fit.json")));
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(r.err.find("meshfit: deform: ") != std::string::npos);
    CHECK(r.err.find("meshfit: partition: ") != std::string::npos);
    CHECK(r.err.find("meshfit: smooth: ") != std::string::npos);
    CHECK(r.err.find("meshfit: fit: verifying") != std::string::npos);
    const meshfit::Mesh_data m = meshfit::read_mesh_data(dir.file("fit.ply"));
    const meshfit::Mesh_data t = meshfit::read_mesh_data(d + "/template.off");
    const std::string json = read_text(dir.file("fit.json"));
    CHECK(json.find("\"verified\": true") != std::string::npos);
    CHECK(json.find("\"regions\": 12") != std::string::npos);
    CHECK(json.find("\"faces\": " + std::to_string(m.triangles.size())) != std::string::npos);
    CHECK(m.points.size() >= t.points.size());
    // The curve edges are beside the output (issue 14), chains on its vertices.
    CHECK(m.curve_edges.empty());
    CHECK(meshfit::read_curve_network(dir.file("fit.ply.curves.polylines.txt")).number_of_segments() >= 220);
    REQUIRE(m.face_patch.size() == m.triangles.size());
    CHECK(*std::max_element(m.face_patch.begin(), m.face_patch.end()) == 11);
    // Output vertex i is template vertex i: each user pair's template vertex sits on its point.
    const auto network = meshfit::read_curve_network(d + "/curves.polylines.txt");
    for (const auto& c : meshfit::read_correspondences(d + "/pairs.txt", network))
      CHECK(m.points[c.template_vertex] == network.point(c.network_vertex));
  }
  SECTION("either fine level; the report says which and how many regions the network bounds") {
    for (const std::string level : {"surface", "thesis"}) {
      const Run_result r = run(dir, "fit --quiet --fine-level " + level + inputs + " --output " + q(dir.file("l.off")) +
                                        " --report " + q(dir.file("l.json")));
      INFO(level << ": " << r.err);
      CHECK(r.status == 0);
      const std::string json = read_text(dir.file("l.json"));
      CHECK(json.find("\"method\": \"" + level + "\"") != std::string::npos);
      CHECK(json.find("\"expected_regions\": 12") != std::string::npos);
      CHECK(json.find("\"failure\": null") != std::string::npos);
    }
    CHECK(run(dir, "fit --quiet --fine-level best" + inputs + " --output " + q(dir.file("l.off"))).status == 2);
  }
  SECTION("a polyline far from the template: status 3 at once, the reason in the message and the report") {
    std::string curves = read_text(d + "/curves.polylines.txt") + "3 1000 0 0 1000 1 0 1000 1 1\n";
    std::ofstream(dir.file("far.polylines.txt")) << curves;
    const auto start = std::chrono::steady_clock::now();
    const Run_result r = run(dir, "fit --template " + q(d + "/template.off") + " --curves " + q(dir.file("far.polylines.txt")) +
                                      " --correspondences " + q(d + "/pairs.txt") + " --output " + q(dir.file("far.off")) +
                                      " --report " + q(dir.file("far.json")));
    CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < 5);
    CHECK(r.status == 3);
    CHECK(r.err.find("polyline 5 (in file order) lies far from the template") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir.file("far.off")));
    const std::string json = read_text(dir.file("far.json"));
    CHECK(json.find("\"completed\": false") != std::string::npos);
    CHECK(json.find("far from the template") != std::string::npos);
  }
  SECTION("to OBJ and OFF, quietly") {
    CHECK(run(dir, "fit --quiet" + inputs + " --output " + q(dir.file("fit.obj"))).status == 0);
    CHECK(read_text(dir.file("fit.obj")).find("g region_11") != std::string::npos);
    const Run_result off = run(dir, "fit --quiet" + inputs + " --output " + q(dir.file("fit.off")));
    CHECK(off.status == 0);
    CHECK(off.err.empty());
  }
  SECTION("usage: no --coarse-only, options checked") {
    CHECK(run(dir, "fit --coarse-only" + inputs + " --output " + q(dir.file("o.off"))).status == 2);
    CHECK(run(dir, "fit" + inputs + " --output " + q(dir.file("o.off")) + " --step 3").status == 2);
    CHECK(run(dir, "fit" + inputs).status == 2);
  }
  SECTION("the algorithm cannot complete: status 3, report written, no output") {
    const Run_result r = run(dir, "fit --fine-level thesis --max-rounds 1" + inputs + " --output " + q(dir.file("f.ply")) + " --report " + q(dir.file("f.json")));
    CHECK(r.status == 3);
    CHECK(r.err.find("failed verification") != std::string::npos);
    CHECK(r.err.find("flipped in the deformation") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir.file("f.ply")));
    CHECK(read_text(dir.file("f.json")).find("\"verified\": false") != std::string::npos);
    const Run_result kept = run(dir, "fit --quiet --allow-defects --fine-level thesis --max-rounds 1" + inputs + " --output " + q(dir.file("k.ply")));
    CHECK(kept.status == 0);
    CHECK(std::filesystem::exists(dir.file("k.ply")));
  }
}

TEST_CASE("cli: fit names the polylines nearest the faces the fine level left turned over", "[cli][fit][message]") {
  // The battery's open-patch-01-wave-boundary with the template's bending asked for: 11 faces
  // stay turned over (test/data/open-patch-01-wave-boundary/README.md).
  Temp_dir dir;
  const std::string d = MESHFIT_TEST_DATA_DIR "/open-patch-01-wave-boundary";
  const Run_result r = run(dir, "fit --quiet --fine-shape template --template " + q(d + "/template.off") + " --curves " +
                                    q(d + "/curves.polylines.txt") + " --correspondences " + q(d + "/pairs.txt") +
                                    " --output " + q(dir.file("o.off")) + " --report " + q(dir.file("o.json")));
  INFO(r.err);
  CHECK(r.status == 3);
  CHECK(r.err.find("flipped in the deformation; the faces the fine level left turned over or folded lie nearest polylines 1, 4 "
                   "(in file order); ") != std::string::npos);
  CHECK(r.err.find("give more correspondences (at crossings of those curves)") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir.file("o.off")));
  const std::string json = read_text(dir.file("o.json"));
  CHECK(json.find("\"polylines_near_defects\": [\n") != std::string::npos);
}

TEST_CASE("cli: deform makes the second start from the registered template unless --no-registration", "[cli][deform][registration]") {
  // The battery's ico2562-onto-pig (test/data/ico2562-onto-pig/README.md): the first start leaves a
  // face turned over, the second none, and is kept.
  Temp_dir dir;
  const std::string d = MESHFIT_TEST_DATA_DIR "/ico2562-onto-pig";
  const std::string inputs = " --template " + q(d + "/template.off") + " --curves " + q(d + "/curves.polylines.txt") +
                             " --correspondences " + q(d + "/pairs.txt");
  for (const bool registration : {true, false}) {
    const std::string report = dir.file(registration ? "with.json" : "without.json");
    const Run_result r = run(dir, "deform --quiet" + inputs + " --output " + q(dir.file("o.off")) + " --report " +
                                      q(report) + (registration ? "" : " --no-registration"));
    INFO(r.err);
    const nlohmann::json fine = nlohmann::json::parse(read_text(report))["details"]["fine_level"];
    CHECK(fine["coarse_registered"] == registration);
    if (registration) {
      CHECK(r.status == 0);
      CHECK(fine["registration_iterations"].get<int>() > 0);
      CHECK(fine["registration_turns_over"] == false);
      CHECK(fine["registration_distance_after"].get<double>() < fine["registration_distance_before"].get<double>());
      // The start kept is the third, from the Coherent Point Drift's warp (deform_test.cpp).
      CHECK(fine["registered_start"] == 2);
      CHECK(fine["registration_candidates"] == 5);
      CHECK(fine["registration_closest_point_iterations"].get<int>() > 0);
      CHECK(fine["registration_method"] == "closest_point");
      CHECK(fine["registration_far_matches_left_out"].is_boolean());
      CHECK(fine["registration_pair_weight"].get<double>() > 0);
    } else {
      CHECK(r.status == 3);  // a face still turned over
      CHECK(r.err.find("faces still turn over") != std::string::npos);
      CHECK(fine["registration_iterations"] == 0);
      CHECK(fine["registration_distance_before"].is_null());
      CHECK(fine["registration_method"].is_null());
      CHECK(fine["registration_candidates"] == 0);
      CHECK(fine["registered_start"] == 0);
    }
  }
}

TEST_CASE("cli: fit fed each malformed input exits 1, writes no output and a report that says why",
          "[cli][fit][malformed]") {
  for (const Malformed_case& c : malformed_catalogue()) {
    SECTION(c.name) {
      Temp_dir dir;
      const std::string bad = dir.write("bad" + c.extension, c.content);
      const Run_result r = run(dir, "fit" + inputs_with(dir, c, bad) + " --output " + q(dir.file("out.ply")) +
                                        " --report " + q(dir.file("r.json")));
      INFO(c.name << ": " << r.err);
      CHECK(r.status == 1);
      CHECK(r.err.find(bad) != std::string::npos);
      CHECK_FALSE(std::filesystem::exists(dir.file("out.ply")));
      // Issue 13: the report is written on every exit 1 after the paths were checked.
      const std::string report = read_text(dir.file("r.json"));
      CHECK(report.find("\"completed\": false") != std::string::npos);
      CHECK(report.find("\"stage\": \"read\"") != std::string::npos);
      CHECK(report.find("\"exit_status\": 1") != std::string::npos);
    }
  }
}

}  // namespace meshfit_cli_test
