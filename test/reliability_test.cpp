// Issue 13 (reliability), in the library: the supported coordinate range (coordinate_range.h), results
// that do not depend on the unit of the coordinates, outputs only to regular files, the memory
// limit of the dense RBF, unused template vertices, numbers in messages. The command line's side
// is bench/reliability/run.sh (CTest: reliability_table).
#include <meshfit/coordinate_range.h>
#include <meshfit/correspondence.h>
#include <meshfit/fit.h>
#include <meshfit/internal/format_number.h>
#include <meshfit/internal/resample_network.h>
#include <meshfit/io.h>
#include <meshfit/memory_limit.h>
#include <meshfit/rbf.h>

#include <CGAL/Surface_mesh.h>

#include <nlohmann/json.hpp>

#include "oracle_helpers.h"
#include "test_helpers.h"

#include <sys/stat.h>
#include <unistd.h>

#include <climits>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>

namespace meshfit_reliability_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;
using meshfit::Point_3;
using namespace meshfit_test;

namespace {

struct Inputs {
  Mesh tm;
  meshfit::Curve_network network;
  std::vector<meshfit::Correspondence> pairs;
};

/// The embedded example with every coordinate of the template multiplied by `s` and every point
/// of the network by `sn` (the pairs refer to the same network vertices: merging is the same at
/// every scale).
Inputs example(double s = 1, std::optional<double> network_scale = {}) {
  const double sn = network_scale.value_or(s);
  Inputs in;
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  meshfit::read_triangle_mesh(d + "/template.off", in.tm);
  const meshfit::Curve_network network = meshfit::read_curve_network(d + "/curves.polylines.txt");
  in.pairs = meshfit::read_correspondences(d + "/pairs.txt", network);
  for (auto v : in.tm.vertices()) {
    const Point_3& p = in.tm.point(v);
    in.tm.point(v) = Point_3(p.x() * s, p.y() * s, p.z() * s);
  }
  std::vector<meshfit::Curve_network::Polyline> polylines;
  for (const auto& ids : network.polylines()) {
    polylines.emplace_back();
    for (std::size_t v : ids) {
      const Point_3& p = network.point(v);
      polylines.back().emplace_back(p.x() * sn, p.y() * sn, p.z() * sn);
    }
  }
  in.network = meshfit::Curve_network(polylines);
  return in;
}

}  // namespace

TEST_CASE("coordinate range: a coordinate beyond 1e100 is refused, naming the element", "[coordinate_range]") {
  const Point_3 far(0, 2e100, 0);
  try {
    meshfit::check_coordinate_range(far, meshfit::Input_location::at_line("c.txt", 3), "polyline 1, point 2");
    FAIL("no exception");
  } catch (const meshfit::Invalid_input& e) {
    CHECK(std::string(e.what()).find("c.txt:3: polyline 1, point 2") == 0);
    CHECK(std::string(e.what()).find("2e+100") != std::string::npos);
  }
  CHECK_NOTHROW(meshfit::check_coordinate_range(Point_3(-1e100, 1e100, 0), {}, "p"));
  CHECK_THROWS_AS(meshfit::check_coordinate_range(Point_3(0, 0, std::nan("")), {}, "p"), meshfit::Invalid_input);
  auto box = [](double side) { return meshfit::Bbox_3(0, 0, 0, side, 0, 0); };
  CHECK_THROWS_AS(meshfit::check_extent(box(0.5e-100), {}, "the mesh"), meshfit::Invalid_input);
  CHECK_THROWS_AS(meshfit::check_extent(box(0), {}, "the mesh"), meshfit::Invalid_input);
  CHECK(meshfit::check_extent(box(1e-100), {}, "the mesh") == 1e-100);
  // Far below the range the extent is named as too small, not as zero (its square underflows).
  try {
    meshfit::check_extent(meshfit::Bbox_3(0, 0, 0, 1e-200, 1e-200, 1e-200), {}, "the mesh");
    FAIL("no exception");
  } catch (const meshfit::Invalid_input& e) {
    CHECK(std::string(e.what()).find("below the supported") != std::string::npos);
    CHECK(std::string(e.what()).find("1.73e-200") != std::string::npos);
  }
  // Near the top of the range the diagonal does not overflow.
  CHECK(meshfit::bbox_diagonal(meshfit::Bbox_3(-1e100, -1e100, -1e100, 1e100, 1e100, 1e100)) ==
        Approx(2 * std::sqrt(3.0) * 1e100));
}

TEST_CASE("coordinate range: the readers refuse meshes and networks outside it", "[coordinate_range][io]") {
  Temp_dir dir;
  const std::string off = dir.write("t.off", "OFF\n3 1 0\n0 0 0\n1e150 0 0\n0 1 0\n3 0 1 2\n");
  try {
    meshfit::read_mesh_data(off);
    FAIL("no exception");
  } catch (const meshfit::Invalid_input& e) {
    CHECK(std::string(e.what()).find("/t.off: vertex 1 ") != std::string::npos);
  }
  const std::string tiny = dir.write("s.off", "OFF\n3 1 0\n0 0 0\n1e-150 0 0\n0 1e-150 0\n3 0 1 2\n");
  CHECK_THROWS_AS(meshfit::read_mesh_data(tiny), meshfit::Invalid_input);
  const std::string curves = dir.write("c.polylines.txt", "# far\n2 0 0 0 1 1 1\n2 0 0 0 1e200 0 0\n");
  try {
    meshfit::read_curve_network(curves);
    FAIL("no exception");
  } catch (const meshfit::Invalid_input& e) {
    // The second polyline, numbered from 1 like its points and like the stages' messages.
    CHECK(std::string(e.what()).find("/c.polylines.txt:3: polyline 2, point 2 ") != std::string::npos);
  }
}

TEST_CASE("coordinate range: the library refuses a template outside it before any work", "[coordinate_range][fit]") {
  Inputs in = example();
  in.tm.point(Mesh::Vertex_index(5)) = Point_3(1e150, 0, 0);
  const Mesh before = in.tm;
  CHECK_THROWS_AS(meshfit::fit_template_to_curves(in.tm, in.network, in.pairs), meshfit::Invalid_input);
  CHECK_THROWS_AS(meshfit::deform_template(in.tm, in.network, in.pairs), meshfit::Invalid_input);
  CHECK(in.tm.point(Mesh::Vertex_index(5)) == before.point(Mesh::Vertex_index(5)));
}

TEST_CASE("coordinate range: fit gives the same result at the edges of the range as at scale 1",
          "[coordinate_range][fit]") {
  // Powers of two: the scaled inputs are exact, so the result must be the same, scaled. The whole
  // example at the edges of the range, then the template and the curves at scales up to 2^266
  // (about 1e80) apart, either way round: the coarse level maps the one onto the other, and the
  // result is the scale-1 result in the curves' frame.
  Inputs ref = example();
  const meshfit::Fit_report base = meshfit::fit_template_to_curves(ref.tm, ref.network, ref.pairs);
  // The scale-1 result is judged by the independent oracle; the scaled ones must be it, scaled
  // (a check of their own at 2^-330 would have its cross products underflow).
  REQUIRE(meshfit_test::oracle_passes(meshfit_test::check_example_fit(ref.tm)));
  for (const auto& [et, en] : {std::pair{330, 330}, std::pair{-330, -330}, std::pair{66, 66}, std::pair{-66, -66},
                               std::pair{0, -266}, std::pair{0, 266}, std::pair{266, 0}, std::pair{-200, 66}}) {
    INFO("template scale 2^" << et << ", curves scale 2^" << en);
    const double sn = std::ldexp(1.0, en);
    Inputs in = example(std::ldexp(1.0, et), sn);
    const meshfit::Fit_report r = meshfit::fit_template_to_curves(in.tm, in.network, in.pairs);
    CHECK(r.verification.passed());  // the report, computed at this scale, agrees
    CHECK(r.partition.regions == base.partition.regions);
    REQUIRE(in.tm.number_of_vertices() == ref.tm.number_of_vertices());
    std::size_t differ = 0;
    for (auto v : in.tm.vertices()) {
      const Point_3& p = ref.tm.point(v);
      differ += in.tm.point(v) != Point_3(p.x() * sn, p.y() * sn, p.z() * sn);
    }
    CHECK(differ == 0);
  }
}

TEST_CASE("coordinate range: smoothing at 2^266 gives the scale-1 result, scaled", "[coordinate_range][smooth]") {
  // At about 1e80 the squared areas of the flow overflowed: the smallest angle came out at 7.6
  // degrees instead of 53.7 (and the report said 90).
  const double s = std::ldexp(1.0, 266);
  Inputs ref = example(), big = example(s);
  const meshfit::Smoothing_report a = meshfit::smooth_fitted_mesh(ref.tm, CGAL::parameters::number_of_iterations(20));
  const meshfit::Smoothing_report b = meshfit::smooth_fitted_mesh(big.tm, CGAL::parameters::number_of_iterations(20));
  CHECK(b.iterations == a.iterations);
  std::size_t differ = 0;
  for (auto v : ref.tm.vertices()) {
    const Point_3& p = ref.tm.point(v);
    differ += big.tm.point(v) != Point_3(p.x() * s, p.y() * s, p.z() * s);
  }
  CHECK(differ == 0);
  const meshfit::Mesh_data small_data = meshfit::to_mesh_data(ref.tm), big_data = meshfit::to_mesh_data(big.tm);
  CHECK(meshfit::minimum_angle_degrees(big_data) == Approx(meshfit::minimum_angle_degrees(small_data)).epsilon(1e-12));
  CHECK(meshfit::minimum_angle_degrees(small_data) > 20);
}

TEST_CASE("unused vertices: one far away sets no scale, and the used vertices fit as without it", "[coordinate_range][fit]") {
  // An unused vertex at 1e20 used to set the template's size: thresholds 1e20 times too large
  // (extra vertices inserted, other vertices moved by up to 0.1), and at 1e80 a crash (GMP given
  // a non-finite number in an exact distance comparison).
  for (const double far : {1e20, 1e80}) {
    INFO("unused vertex at x = " << far);
    Inputs ref = example(), in = example();
    const auto extra = in.tm.add_vertex(Point_3(far, 0, 0));
    meshfit::fit_template_to_curves(ref.tm, ref.network, ref.pairs);
    const meshfit::Fit_report r = meshfit::fit_template_to_curves(in.tm, in.network, in.pairs);
    REQUIRE(meshfit_test::oracle_passes(meshfit_test::check_example_fit(ref.tm)));
    CHECK(meshfit_test::oracle_passes(meshfit_test::check_example_fit(in.tm)));
    CHECK(r.verification.passed());  // the report agrees
    // The added vertex is vertex n of the template, so the result's vertex i < n is the same
    // vertex in both, and the vertices the stages add come after it.
    REQUIRE(in.tm.number_of_vertices() == ref.tm.number_of_vertices() + 1);
    const std::size_t n = extra.idx();
    std::size_t differ = 0;
    for (std::size_t i = 0; i < ref.tm.number_of_vertices(); ++i) {
      const std::size_t j = i < n ? i : i + 1;
      differ += ref.tm.point(Mesh::Vertex_index(static_cast<std::uint32_t>(i))) !=
                in.tm.point(Mesh::Vertex_index(static_cast<std::uint32_t>(j)));
    }
    CHECK(differ == 0);
  }
}

TEST_CASE("far curve points: a segment that leaves the surface is refused at once, naming its point",
          "[coordinate_range][deform]") {
  // A 2-point polyline from a network vertex to a point 100 away: its first point lies on the
  // surface, so the polyline is not far as a whole; the surface fine level pulled the surface out
  // to the other and untangled for minutes (killed at 60 s).
  Inputs in = example();
  std::vector<meshfit::Curve_network::Polyline> lines;
  for (const auto& ids : in.network.polylines()) {
    lines.emplace_back();
    for (std::size_t v : ids) lines.back().push_back(in.network.point(v));
  }
  const Point_3 start = in.network.point(0);
  lines.push_back({start, Point_3(start.x(), start.y() + 100, start.z())});
  const meshfit::Curve_network network(lines);
  const std::vector<meshfit::Correspondence> pairs =
      meshfit::read_correspondences(std::string(MESHFIT_EXAMPLE_DATA_DIR) + "/pairs.txt", network);
  try {
    meshfit::deform_template(in.tm, network, pairs);
    FAIL("no exception");
  } catch (const meshfit::Algorithm_failure& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.find("polyline " + std::to_string(lines.size()) + " (in file order), point 2") != std::string::npos);
    CHECK(what.find("times the template's size") != std::string::npos);
    // The same, as figures: the polyline and point (from 1), and the distance over the size.
    REQUIRE(e.figures().size() == 3);
    CHECK(e.figures()[0].name == "polyline");
    CHECK(e.figures()[0].value == static_cast<double>(lines.size()));
    CHECK(e.figures()[1].name == "point");
    CHECK(e.figures()[1].value == 2);
    CHECK(e.figures()[2].name == "distance_over_template_size");
    CHECK(e.figures()[2].value > 1);
  }
}

TEST_CASE("far from the origin: points added on long segments that round onto their ends cut nothing",
          "[coordinate_range][deform]") {
  // At x = 2^52 the spacing of doubles is 1: the points added on a segment of length 1 round onto
  // its ends. The dense network refused the zero-length segments as invalid input ("polyline 0:
  // points 1 and 2 coincide"), which the fit reported as exit 1 on the example translated by 1e15.
  const double x = std::ldexp(1.0, 52);
  const meshfit::Curve_network network(
      std::vector<meshfit::Curve_network::Polyline>{{Point_3(x, 0, 0), Point_3(x + 1, 0, 0), Point_3(x + 1, 1, 0)}});
  const meshfit::internal::Resampled_network r = meshfit::internal::resample_long_segments(network, 0.1);
  CHECK(r.added == 0);
  CHECK(r.network.number_of_vertices() == 3);
  CHECK(r.segment_of == std::vector<std::size_t>{0, 1});
}

TEST_CASE("far from the origin: fit and deform end with exit 0 or 3, not a false invalid input", "[cli][coordinate_range]") {
  // The example translated by 1e15 in x: its x coordinates are multiples of 1/8, some template
  // faces have no area. fit said "polyline 0: points 36 and 37 coincide" (the resampled network),
  // then "untangle: face 320 has a zero normal" (the ICP approach), both exit 1 for valid input.
  Temp_dir dir;
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  const auto moved = [](const Point_3& p) { return Point_3(p.x() + 1e15, p.y(), p.z()); };
  meshfit::Mesh_data t = meshfit::read_mesh_data(d + "/template.off");
  for (Point_3& p : t.points) p = moved(p);
  meshfit::write_mesh_data(dir.file("t.off"), t);
  const meshfit::Curve_network network = meshfit::read_curve_network(d + "/curves.polylines.txt");
  std::vector<meshfit::Curve_network::Polyline> lines;
  for (const auto& ids : network.polylines()) {
    lines.emplace_back();
    for (std::size_t v : ids) lines.back().push_back(moved(network.point(v)));
  }
  meshfit::write_curve_network(dir.file("c.polylines.txt"), meshfit::Curve_network(lines));
  std::ofstream pairs(dir.file("p.txt"));
  pairs.precision(17);
  for (const meshfit::Correspondence& c : meshfit::read_correspondences(d + "/pairs.txt", network)) {
    const Point_3 p = moved(network.point(c.network_vertex));
    pairs << c.template_vertex << ' ' << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  }
  pairs.close();
  for (const std::string command : {"fit", "deform"}) {
    const Run_result r =
        run(dir, command + " --quiet --template t.off --curves c.polylines.txt --correspondences p.txt --output o.off");
    INFO(command << ": " << r.err);
    CHECK((r.status == 0 || r.status == 3));
  }
}

TEST_CASE("write paths: special files are refused and left alone, a symlink's target is replaced",
          "[io][write]") {
  Temp_dir dir;
  meshfit::Mesh_data m = octahedron();
  const std::string fifo = dir.file("f.off");
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  CHECK_THROWS_AS(meshfit::write_mesh_data(fifo, m), meshfit::Invalid_input);
  CHECK(std::filesystem::is_fifo(fifo));
  const std::string folder = dir.file("d.off");
  std::filesystem::create_directory(folder);
  CHECK_THROWS_AS(meshfit::write_mesh_data(folder, m), meshfit::Invalid_input);
  CHECK(std::filesystem::is_directory(folder));
  CHECK_THROWS_AS(meshfit::check_output_path(dir.file("no/such/x.off"), {}), meshfit::Invalid_input);
  CHECK_THROWS_AS(meshfit::check_output_path(dir.file(std::string(300, 'n') + ".off"), {}), meshfit::Invalid_input);
  // A directory that passes access() but takes no new file: refused up front, not after the run.
  CHECK_THROWS_WITH(meshfit::check_output_path("/proc/x.off", {}), Catch::Contains("cannot create the output file"));
  // A path over PATH_MAX in an existing directory: its length is the problem, not the directory.
  std::string deep = dir.file("");
  while (deep.size() <= PATH_MAX) deep += "./";
  CHECK_THROWS_WITH(meshfit::check_output_path(deep + "x.off", {}), Catch::Contains("bytes long"));
  // A symbolic link: its target gets the mesh, the link stays a link.
  const std::string target = dir.write("target.off", "old\n");
  const std::string link = dir.file("link.off");
  std::filesystem::create_symlink("target.off", link);
  meshfit::write_mesh_data(link, m);
  CHECK(std::filesystem::is_symlink(link));
  CHECK(read_text(target).rfind("OFF", 0) == 0);
  // A 250-character name is valid; the temporary file beside it must not need a longer one.
  const std::string long_name = dir.file(std::string(246, 'a') + ".off");
  CHECK_NOTHROW(meshfit::write_mesh_data(long_name, m));
  CHECK(std::filesystem::is_regular_file(long_name));
}

TEST_CASE("memory limit: a dense RBF over the limit is refused before it is allocated", "[rbf][memory]") {
  std::vector<Point_3> c, v;
  for (int i = 0; i < 40; ++i) {
    c.emplace_back(std::cos(i * 0.7), std::sin(i * 1.3), std::cos(i * 2.1));
    v.push_back(c.back());
  }
  // 44×44 doubles, twice: about 31 kB.
  try {
    meshfit::Rbf_interpolant::fit(c, v, meshfit::Rbf_kernel::linear, {}, nullptr, 16 * 1024);
    FAIL("no exception");
  } catch (const meshfit::Algorithm_failure& e) {
    CHECK(std::string(e.what()).find("31 kB") != std::string::npos);
    REQUIRE(e.figures().size() == 2);
    CHECK(e.figures()[0].name == "estimated_bytes");
    CHECK(e.figures()[0].value == Approx(2 * 44 * 44 * 8).epsilon(0.2));
    CHECK(e.figures()[1].name == "memory_limit_bytes");
    CHECK(e.figures()[1].value == 16 * 1024);
  }
  CHECK_NOTHROW(meshfit::Rbf_interpolant::fit(c, v, meshfit::Rbf_kernel::linear, {}, nullptr, 64 * 1024));
  CHECK(meshfit::default_memory_limit() > 0);
  // At most 2 GiB, whatever the RAM: what is refused does not depend on the machine.
  CHECK(meshfit::default_memory_limit() <= std::size_t(2) << 30);
}

TEST_CASE("memory limit: the coarse level's dense RBF is under the limit too", "[rbf][memory][deform]") {
  // The coarse RBF through 8 002 pairs took 1.5 GB with --max-memory 512M (it used the default).
  Inputs in = example();
  // 8 pairs: a system of about 12×12, twice: some kB.
  CHECK_THROWS_WITH(meshfit::deform_template(in.tm, in.network, in.pairs,
                                             meshfit::parameters::coarse_only(true).memory_limit(std::size_t(1024))),
                    Catch::Contains("the RBF's dense"));
  CHECK_NOTHROW(meshfit::deform_template(in.tm, in.network, in.pairs,
                                         meshfit::parameters::coarse_only(true).memory_limit(std::size_t(1) << 20)));
}

TEST_CASE("memory limit: the thesis level's fine RBF is refused from the counts, before the coarse level",
          "[rbf][memory][deform]") {
  // The 5.8 M-point line was refused ("needs about 538 TB") only after 39 s of coarse level and
  // closest-point queries. The example's fine RBF through its 210 network vertices: about 730 kB.
  Inputs in = example();
  std::vector<std::string> steps;
  const meshfit::Progress_callback record = [&](const meshfit::Progress_step& s) {
    steps.push_back(s.step);
    return true;
  };
  CHECK_THROWS_WITH(meshfit::deform_template(in.tm, in.network, in.pairs,
                                             meshfit::parameters::fine_level(meshfit::Fine_level::thesis)
                                                 .memory_limit(std::size_t(100) << 10)
                                                 .progress(record)),
                    Catch::Contains("the fine RBF through all 210 network vertices"));
  for (const std::string& step : steps) CHECK(step.find("coarse") == std::string::npos);
}

TEST_CASE("bounded work: fit with the thesis level and 'drop' refuses more network vertices than template vertices at once",
          "[fit][deform]") {
  // With 'drop' no vertex is added for the curves: each network vertex needs a template vertex of
  // its own. A 1.7 M-point line on the example template got its exit 3 only after 65 s of
  // closest-point queries; the counts say it before any work.
  Inputs in = example();
  const meshfit::internal::Resampled_network dense = meshfit::internal::resample_long_segments(in.network, 0.002);
  const std::size_t nv = dense.network.number_of_vertices(), tv = num_vertices(in.tm);
  REQUIRE(nv > tv);
  std::vector<meshfit::Correspondence> pairs = in.pairs;
  for (meshfit::Correspondence& c : pairs) c.network_vertex = dense.vertex_of[c.network_vertex];
  std::vector<std::string> steps;
  const meshfit::Progress_callback record = [&](const meshfit::Progress_step& s) {
    steps.push_back(s.step);
    return true;
  };
  const auto np = meshfit::parameters::fine_level(meshfit::Fine_level::thesis)
                      .curve_density(meshfit::Curve_density::drop)
                      .progress(record);
  try {
    meshfit::fit_template_to_curves(in.tm, dense.network, pairs, np);
    FAIL("fit did not refuse");
  } catch (const meshfit::Algorithm_failure& e) {
    CHECK_THAT(e.what(), Catch::Contains(std::to_string(nv) + " network vertices but only " + std::to_string(tv) +
                                         " template vertices: at least " + std::to_string(nv - tv) +
                                         " would be dropped"));
    // The figures, for a caller that does not parse the message.
    REQUIRE(e.figures().size() == 2);
    CHECK(e.figures()[0].name == "network_vertices");
    CHECK(e.figures()[0].value == static_cast<double>(nv));
    CHECK(e.figures()[1].name == "template_vertices");
    CHECK(e.figures()[1].value == static_cast<double>(tv));
  }
  CHECK(steps.empty());
  // With fewer network vertices than template vertices the fit runs; on the example the thesis
  // level's matching then leaves 4 network vertices without a mesh vertex, said after the stage.
  Inputs small = example();
  steps.clear();
  CHECK_THROWS_WITH(meshfit::fit_template_to_curves(small.tm, small.network, small.pairs, np),
                    Catch::Contains("4 network vertices have no mesh vertex of their own"));
  CHECK_FALSE(steps.empty());
}

TEST_CASE("memory limit: fit and deform refuse an input file whose reading would exceed it", "[cli][memory]") {
  // A 57 MB polyline peaked at 590 MB with --max-memory 100M. The example's template is 233 kB.
  Temp_dir dir;
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  const std::string args = " --template " + q(d + "/template.off") + " --curves " + q(d + "/curves.polylines.txt") +
                           " --correspondences " + q(d + "/pairs.txt") + " --output o.off --report r.json --quiet";
  for (const std::string command : {"fit", "deform"}) {
    const Run_result r = run(dir, command + args + " --max-memory 1M");
    INFO(r.err);
    CHECK(r.status == 3);
    CHECK(r.err.find("the input file '" + d + "/template.off' (233 kB") != std::string::npos);
    const nlohmann::json report = nlohmann::json::parse(read_text(dir.file("r.json")));
    CHECK(report["completed"] == false);
    CHECK(report["stage"] == "read");
    // The numbers behind the refusal: 10 times the file's size, and the limit.
    CHECK(report["failure_figures"]["estimated_bytes"].get<double>() > 2e6);
    CHECK(report["failure_figures"]["memory_limit_bytes"] == 1 << 20);
    CHECK_FALSE(std::filesystem::exists(dir.file("o.off")));
  }
  CHECK(run(dir, "deform" + args + " --max-memory 10M").status == 0);
  CHECK(nlohmann::json::parse(read_text(dir.file("r.json")))["failure_figures"].is_null());
}

TEST_CASE("unused vertices: smooth --curves matches the network to the surface, not to unused copies",
          "[cli][smooth]") {
  // deform's output with every vertex repeated once, the copies on no face: the network was
  // matched to the copies ("220 of 220 network segments are not mesh edges", no curve edge held).
  Temp_dir dir;
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  REQUIRE(run(dir, "deform --quiet --template " + q(d + "/template.off") + " --curves " + q(d + "/curves.polylines.txt") +
                       " --correspondences " + q(d + "/pairs.txt") + " --output d.off")
              .status == 0);
  meshfit::Mesh_data m = meshfit::read_mesh_data(dir.file("d.off"));
  const std::size_t n = m.points.size();
  for (std::size_t i = 0; i < n; ++i) m.points.push_back(m.points[i]);
  meshfit::write_mesh_data(dir.file("copies.off"), m);
  // The same counts as on deform's output itself (whose segments are not all edges yet).
  auto smooth_counts = [&](const std::string& mesh) {
    const Run_result r = run(dir, "smooth --quiet --template " + mesh + " --curves " + q(d + "/curves.polylines.txt") +
                                      " --output s.off --report s.json");
    INFO(r.err);
    REQUIRE(r.status == 0);
    return nlohmann::json::parse(read_text(dir.file("s.json")))["counts"];
  };
  const nlohmann::json plain = smooth_counts("d.off"), copies = smooth_counts("copies.off");
  CHECK(plain["network_segments_on_mesh"] > 0);
  CHECK(plain["curve_edges"] > 0);
  for (const char* key : {"network_vertices_on_mesh", "network_segments_on_mesh", "curve_edges"}) {
    INFO(key);
    CHECK(copies[key] == plain[key]);
  }
}

TEST_CASE("unused vertices: no closest-point candidates, and the thesis level fits a template with copies",
          "[closest_point][deform]") {
  // Every template vertex repeated once, the copies unused (coincident with the used ones).
  Inputs in = example();
  const std::size_t n = in.tm.number_of_vertices();
  std::vector<Point_3> copies;
  for (auto v : in.tm.vertices()) copies.push_back(in.tm.point(v));
  for (const Point_3& p : copies) in.tm.add_vertex(p);
  std::vector<bool> used(2 * n, true);
  std::fill(used.begin() + static_cast<std::ptrdiff_t>(n), used.end(), false);
  std::vector<Point_3> all = copies;
  all.insert(all.end(), copies.begin(), copies.end());
  const meshfit::Closest_point_assignment a =
      meshfit::closest_point_correspondences(all, in.network, in.pairs, meshfit::Loser_rule::drop, used);
  for (std::size_t t : a.template_of)
    if (t != meshfit::Closest_point_assignment::unassigned) CHECK(t < n);
  const meshfit::Deformation_report r = meshfit::deform_template(
      in.tm, in.network, in.pairs, meshfit::parameters::fine_level(meshfit::Fine_level::thesis));
  CHECK(r.remaining_flips == 0);
  CHECK(in.tm.number_of_vertices() >= 2 * n);
  // No copy is the mesh vertex of a network vertex.
  for (std::size_t t : r.mesh_vertex_of_network_vertex)
    if (t != meshfit::Closest_point_assignment::unassigned) CHECK((t < n || t >= 2 * n));
}

TEST_CASE("messages: numbers with significant digits", "[messages]") {
  CHECK(meshfit::internal::format_number(1.2e-17) == "1.2e-17");
  CHECK(meshfit::internal::format_number(1e-13) == "1e-13");
  CHECK(meshfit::internal::format_number(0.25) == "0.25");
  CHECK(meshfit::format_bytes(3.79e9) == "3.79 GB");
}

}  // namespace meshfit_reliability_test
