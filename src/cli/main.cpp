// The meshfit command: subcommands and exit codes as fixed in DESIGN.md.
//   0 success; 1 invalid input; 2 usage error; 3 the algorithm could not complete.
#include <meshfit/check.h>
#include <meshfit/deform.h>
#include <meshfit/exceptions.h>
#include <meshfit/fit.h>
#include <meshfit/io.h>
#include <meshfit/partition.h>
#include <meshfit/smooth.h>
#include <meshfit/version.h>

#include "../write_file.h"
#include "view.h"

using meshfit_cli::json_string;

#include <CGAL/Surface_mesh.h>

#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

#include <cstdlib>
#include <iostream>
#include <map>
#include <new>
#include <string>
#include <vector>

namespace {

enum Exit_status { success = 0, invalid_input = 1, usage_error = 2, algorithm_failed = 3 };

const char* const usage_text =
    "usage:\n"
    "  meshfit fit       --template T --curves C --correspondences P --output O [--report R.json] [options]\n"
    "  meshfit deform    --template T --curves C --correspondences P --output O [--report R.json] [options]\n"
    "  meshfit partition --template M --curves C --output O [--report R.json] [options]\n"
    "  meshfit smooth    --template M [--curves C] --output O [--report R.json] [options]\n"
    "  meshfit check     --template T --curves C --correspondences P\n"
    "  meshfit view      --template T --curves C [--correspondences P] [--result R [--result-report R.json]]...\n"
    "                    --output O.html\n"
    "options:\n"
    "  --merge-tolerance X  curve points closer than X times the network's bounding-box diagonal\n"
    "                       are one network vertex (default 1e-9)\n"
    "  --quiet              no progress on stderr\n"
    "deform options:\n"
    "  --coarse-only        stop after the coarse level (RBF through the given pairs)\n"
    "  --kernel K           RBF basis: linear (phi(r)=r, default) or cubic (phi(r)=r^3)\n"
    "  --curve-density D    refine (default: every network vertex gets a mesh vertex) or drop\n"
    "                       (the template keeps its size; network vertices that lose their\n"
    "                       nearest template vertex are dropped and reported)\n"
    "  --fine-level L       surface (default: embed the curves in the coarse surface, then move them into\n"
    "                       place with a thin-plate displacement) or thesis (nearest-vertex RBF, subdivision)\n"
    "  --max-rounds N       flip prevention (thesis) or untangling (surface) rounds at most (default 10)\n"
    "  --max-memory SIZE    refuse (exit 3, with the estimate) work whose largest allocation, the thesis\n"
    "                       level's dense RBF system, would exceed SIZE (2G, 512M; default RAM / 8)\n"
    "smooth options (thesis ch. 4: modified mean-curvature flow, then modified Laplacian flow):\n"
    "  --iterations N       iterations in all (default 100: a fifth mean curvature, the rest Laplacian)\n"
    "  --mc-iterations N    iterations of the modified mean-curvature flow\n"
    "  --laplacian-iterations N  iterations of the modified Laplacian flow\n"
    "  --step X             step lambda in (0, 1] (default 1)\n"
    "                       Fixed: the mesh boundary, the curve edges' vertices (curve edges of\n"
    "                       a .ply/.obj template, and with --curves the mesh vertices on network\n"
    "                       vertices and the mesh edges along network segments)\n"
    "fit options: those of deform (but --coarse-only) and smooth, and\n"
    "  --allow-defects      write the result even when the final verification finds defects\n"
    "                       (segments not embedded, folded or degenerate faces, self-intersections);\n"
    "                       they are still reported\n"
    "  --no-self-intersection-check  skip the final self-intersection test (the slowest check)\n"
    "view options: --result (repeatable: fit's output, or one per stage, shown in that order);\n"
    "  --result-report R.json  the report of the result given before it, shown beside it\n"
    "  --help, --version\n";

struct Usage_error {
  std::string message;
};

struct Command_line {
  std::string command;
  std::map<std::string, std::string> values;
  std::vector<std::string> results, result_reports;  ///< view's repeatable --result, --result-report
  bool quiet = false;
  bool coarse_only = false;
  bool allow_defects = false;
  bool no_self_intersection_check = false;
};

Command_line parse(int argc, char** argv) {
  Command_line cl;
  if (argc < 2) throw Usage_error{"no command given"};
  cl.command = argv[1];
  static const char* const valued[] = {"--template", "--curves", "--correspondences", "--output",
                                       "--report", "--merge-tolerance", "--kernel",
                                       "--curve-density", "--max-rounds", "--fine-level", "--max-memory",
                                       "--iterations", "--mc-iterations", "--laplacian-iterations", "--step"};
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--quiet") { cl.quiet = true; continue; }
    if (arg == "--coarse-only") { cl.coarse_only = true; continue; }
    if (arg == "--allow-defects") { cl.allow_defects = true; continue; }
    if (arg == "--no-self-intersection-check") { cl.no_self_intersection_check = true; continue; }
    if (arg == "--result" || arg == "--result-report") {
      if (i + 1 >= argc) throw Usage_error{"option " + arg + " needs a value"};
      if (arg == "--result") {
        cl.results.push_back(argv[++i]);
      } else {
        if (cl.result_reports.size() >= cl.results.size())
          throw Usage_error{"--result-report " + std::string(argv[i + 1]) + " follows no --result of its own"};
        cl.result_reports.resize(cl.results.size());
        cl.result_reports.back() = argv[++i];
      }
      continue;
    }
    bool known = false;
    for (const char* v : valued) known = known || arg == v;
    if (!known) throw Usage_error{"unknown option '" + arg + "'"};
    if (i + 1 >= argc) throw Usage_error{"option " + arg + " needs a value"};
    if (!cl.values.emplace(arg, argv[++i]).second) throw Usage_error{"option " + arg + " given twice"};
  }
  return cl;
}

void require(const Command_line& cl, std::initializer_list<const char*> required,
             std::initializer_list<const char*> allowed) {
  for (const char* r : required)
    if (!cl.values.count(r)) throw Usage_error{"meshfit " + cl.command + " needs " + r};
  for (const auto& kv : cl.values) {
    bool ok = false;
    for (const char* r : required) ok = ok || kv.first == r;
    for (const char* a : allowed) ok = ok || kv.first == a;
    if (!ok) throw Usage_error{"meshfit " + cl.command + " does not take " + kv.first};
  }
  if (cl.command != "view" && !cl.results.empty())
    throw Usage_error{"meshfit " + cl.command + " does not take --result"};
}

double merge_tolerance(const Command_line& cl) {
  const auto it = cl.values.find("--merge-tolerance");
  if (it == cl.values.end()) return meshfit::default_merge_tolerance;
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (end == it->second.c_str() || *end != '\0' || !(v >= 1e-15 && v <= 1e-2))
    throw Usage_error{"--merge-tolerance needs a number from 1e-15 to 1e-2, not '" + it->second + "'"};
  return v;
}

int run_check(const Command_line& cl) {
  require(cl, {"--template", "--curves", "--correspondences"}, {"--merge-tolerance"});
  const meshfit::Check_summary s =
      meshfit::check_inputs(cl.values.at("--template"), cl.values.at("--curves"),
                            cl.values.at("--correspondences"), merge_tolerance(cl));
  std::cout << "template " << cl.values.at("--template") << " ("
            << meshfit::to_string(s.mesh_report.format) << ")\n"
            << "  vertices:            " << s.mesh.vertices << "\n"
            << "  faces:               " << s.mesh.faces;
  if (s.mesh_report.polygons_triangulated > 0)
    std::cout << " (" << s.mesh_report.polygons_triangulated << " polygons triangulated)";
  std::cout << "\n"
            << "  edges:               " << s.mesh.edges << "\n"
            << "  boundaries:          " << s.mesh.boundaries << "\n"
            << "  components:          " << s.mesh.components << "\n"
            << "  genus:               " << s.mesh.genus << "\n"
            << "curve network " << cl.values.at("--curves") << "\n"
            << "  network vertices:    " << s.network_vertices << "\n"
            << "  segments:            " << s.network_segments << "\n"
            << "  feature points:      " << s.feature_points << "\n"
            << "  endpoints:           " << s.endpoints << "\n"
            << "  closed polylines:    " << s.closed_polylines << "\n"
            << "  curves:              " << s.curves << " (between feature points and endpoints)\n"
            << "  independent loops:   " << s.independent_cycles << "\n"
            << "  components:          " << s.network_components << "\n"
            << "correspondences " << cl.values.at("--correspondences") << "\n"
            << "  pairs:               " << s.correspondences << "\n"
            << "problems:              " << (s.problems.empty() ? "none" : "") << "\n";
  for (const std::string& p : s.problems) std::cout << "  - " << p << "\n";
  return success;
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream os;
  os << std::setprecision(6) << v;
  return os.str();
}

/// The report of the running command once its path is checked, so that every exit 1 or 3 after
/// that writes one (main's handlers write a short one when the command did not get to it).
struct Pending_report {
  std::string path, command;
  std::string stage = "read";  ///< the stage running (from the progress callback)
  bool written = false;
} pending_report;

/// Checks the output paths before any work: the mesh output's format, that it and the report can
/// be written (regular files in existing directories), and that neither is an input or the other.
/// Returns the report path ("" when none).
std::string check_outputs(const Command_line& cl, const std::vector<std::string>& inputs) {
  const std::string& output = cl.values.at("--output");
  meshfit::mesh_format_of(output);
  meshfit::check_output_path(output, inputs);
  if (!cl.values.count("--report")) return "";
  const std::string& report_path = cl.values.at("--report");
  meshfit::check_output_path(report_path, inputs);
  meshfit::check_output_path(output, {report_path});
  pending_report.path = report_path;
  pending_report.command = cl.command;
  return report_path;
}

void write_report(const std::string& report_path, const std::string& text) {
  if (report_path.empty()) return;
  pending_report.written = true;  // (a failure to write it is not retried)
  meshfit::internal::write_file_atomically(report_path, [&](std::ostream& os) { os << text; });
}

/// "completed", "failure" and "stage" of a report: `failure` empty when the command completed.
std::string json_outcome(const std::string& failure, const std::string& stage) {
  return std::string("  \"completed\": ") + (failure.empty() ? "true" : "false") + ",\n  \"failure\": " +
         (failure.empty() ? "null" : json_string(failure)) + ",\n  \"stage\": " +
         (failure.empty() ? "null" : json_string(stage)) + ",\n";
}

/// The report of a command that failed before it could gather its figures (bad input found after
/// the paths were checked, out of memory, an unexpected error): written by main.
void write_failure_report(const std::string& failure, const std::string& stage, int exit_status) noexcept {
  if (pending_report.path.empty() || pending_report.written) return;
  try {
    std::ostringstream js;
    js << "{\n  \"command\": \"" << pending_report.command << "\",\n  \"meshfit_version\": \"" << MESHFIT_VERSION_STRING
       << "\",\n" << json_outcome(failure, stage) << "  \"exit_status\": " << exit_status
       << ",\n  \"timings_s\": {},\n  \"counts\": {}\n}\n";
    write_report(pending_report.path, js.str());
  } catch (const std::exception& e) {
    std::cerr << "meshfit: could not write the report: " << e.what() << "\n";
  }
}

/// Writes the output mesh, never over an input or the report.
void write_output(const Command_line& cl, const meshfit::Mesh_data& out, const std::vector<std::string>& inputs,
                  const std::string& report_path) {
  meshfit::Write_options options;
  options.protected_paths = inputs;
  if (!report_path.empty()) options.protected_paths.push_back(report_path);
  meshfit::write_mesh_data(cl.values.at("--output"), out, options);
  if (!cl.quiet)
    std::cerr << "meshfit: " << cl.command << ": wrote " << cl.values.at("--output") << " (" << out.points.size()
              << " vertices, " << out.triangles.size() << " faces)\n";
}

meshfit::Progress_callback progress_printer(bool quiet) {
  return [quiet](const meshfit::Progress_step& s) {
    pending_report.stage = s.stage;
    if (!quiet) std::cerr << "meshfit: " << s.stage << ": " << s.step << " (" << s.index + 1 << "/" << s.total << ")\n";
    return true;
  };
}

/// The fine level's own figures, the same block in the reports of deform and fit.
std::string json_fine_level(const meshfit::Deformation_report& r) {
  std::ostringstream js;
  js << "{\"method\": \"" << meshfit::to_string(r.fine_level) << "\"";
  if (r.fine_level == meshfit::Fine_level::surface)
    js << ", \"largest_projection_distance\": " << json_number(r.largest_projection_distance)
       << ", \"segments_embedded\": " << r.segments_embedded << ", \"segments_not_embedded\": "
       << r.segments_not_embedded.size() << ", \"segments_by_shortest_path\": " << r.segments_by_shortest_path
       << ", \"edges_split_between_curves\": " << r.edges_split_between_curves
       << ", \"projections_off_nearest\": " << r.projections_off_nearest << ", \"displacement_free_vertices\": " << r.displacement.free_vertices
       << ", \"untangle_rounds\": " << r.untangle_rounds << ", \"untangled_vertices\": " << r.untangled_vertices
       << ", \"remaining_folds\": " << r.remaining_folds;
  js << ", \"coarse_affine_determinant\": " << json_number(r.coarse_affine_determinant) << "}";
  return js.str();
}

std::string json_quality(const meshfit::Mesh_data& out) {
  std::ostringstream js;
  js << "{\"vertices\": " << out.points.size() << ", \"faces\": " << out.triangles.size()
     << ", \"minimum_angle_deg\": " << json_number(meshfit::minimum_angle_degrees(out)) << "}";
  return js.str();
}

struct Deform_options {
  meshfit::Rbf_kernel kernel = meshfit::Rbf_kernel::linear;
  meshfit::Curve_density density = meshfit::Curve_density::refine;
  meshfit::Fine_level fine_level = meshfit::Fine_level::surface;
  int rounds = 10;
  std::size_t memory_limit = 0;  ///< bytes; 0: meshfit::default_memory_limit()
};

Deform_options deform_options(const Command_line& cl) {
  Deform_options o;
  if (cl.values.count("--kernel")) {
    const std::string& k = cl.values.at("--kernel");
    if (k == "cubic") o.kernel = meshfit::Rbf_kernel::cubic;
    else if (k != "linear") throw Usage_error{"--kernel must be linear or cubic, not '" + k + "'"};
  }
  if (cl.values.count("--curve-density")) {
    const std::string& d = cl.values.at("--curve-density");
    if (d == "drop") o.density = meshfit::Curve_density::drop;
    else if (d != "refine") throw Usage_error{"--curve-density must be refine or drop, not '" + d + "'"};
  }
  if (cl.values.count("--fine-level")) {
    const std::string& f = cl.values.at("--fine-level");
    if (f == "thesis") o.fine_level = meshfit::Fine_level::thesis;
    else if (f != "surface") throw Usage_error{"--fine-level must be surface or thesis, not '" + f + "'"};
  }
  if (cl.values.count("--max-rounds")) {
    const std::string& r = cl.values.at("--max-rounds");
    char* end = nullptr;
    const long v = std::strtol(r.c_str(), &end, 10);
    if (end == r.c_str() || *end != '\0' || v < 1 || v > 1000)
      throw Usage_error{"--max-rounds needs an integer from 1 to 1000, not '" + r + "'"};
    o.rounds = static_cast<int>(v);
  }
  if (cl.values.count("--max-memory")) {
    // A number of bytes, or with a suffix K, M, G or T (powers of 1024).
    const std::string& m = cl.values.at("--max-memory");
    char* end = nullptr;
    double v = std::strtod(m.c_str(), &end);
    const std::string suffix = end ? end : "";
    const std::map<std::string, double> units{{"", 1.0}, {"K", 1024.0}, {"M", 1024.0 * 1024}, {"G", 1024.0 * 1024 * 1024},
                                              {"T", 1024.0 * 1024 * 1024 * 1024}};
    const auto u = units.find(suffix);
    if (end == m.c_str() || u == units.end() || !(v * u->second >= 1024 * 1024) || !(v * u->second <= 1e18))
      throw Usage_error{"--max-memory needs a size such as 2G, 512M or 3e9 (at least 1M), not '" + m + "'"};
    o.memory_limit = static_cast<std::size_t>(v * u->second);
  }
  return o;
}

using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;

/// The inputs of deform and fit, read and checked against each other.
struct Fit_inputs {
  Mesh tm;
  meshfit::Curve_network network;
  std::vector<meshfit::Correspondence> pairs;
  double read_seconds = 0;
};

void read_fit_inputs(const Command_line& cl, Fit_inputs& in) {
  const std::string& template_path = cl.values.at("--template");
  const auto t0 = std::chrono::steady_clock::now();
  meshfit::read_triangle_mesh(template_path, in.tm);
  in.network = meshfit::read_curve_network(cl.values.at("--curves"), merge_tolerance(cl));
  in.pairs = meshfit::read_correspondences(cl.values.at("--correspondences"), in.network);
  const meshfit::Mesh_data template_data = meshfit::to_mesh_data(in.tm);
  if (template_data.triangles.empty())
    throw meshfit::Invalid_input(meshfit::Input_location{template_path, 0, meshfit::Input_location::no_offset},
                                 "the template has no face");
  // Coplanar template vertices are accepted here: the RBF adds auxiliary pairs off the plane.
  meshfit::validate_correspondences(in.pairs, template_data.points, in.network, true);
  in.read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

int run_deform(const Command_line& cl) {
  require(cl, {"--template", "--curves", "--correspondences", "--output"},
          {"--report", "--merge-tolerance", "--kernel", "--curve-density", "--max-rounds", "--fine-level", "--max-memory"});
  const std::string& template_path = cl.values.at("--template");
  const std::string& curves_path = cl.values.at("--curves");
  const std::string& pairs_path = cl.values.at("--correspondences");
  const std::vector<std::string> inputs{template_path, curves_path, pairs_path};
  const std::string report_path = check_outputs(cl, inputs);

  const Deform_options options = deform_options(cl);
  const meshfit::Rbf_kernel kernel = options.kernel;
  const meshfit::Curve_density density = options.density;
  const int rounds = options.rounds;

  Fit_inputs in;
  read_fit_inputs(cl, in);
  Mesh& tm = in.tm;
  const meshfit::Curve_network& network = in.network;
  const auto& pairs = in.pairs;
  const double read_s = in.read_seconds;

  const bool quiet = cl.quiet;
  const meshfit::Progress_callback progress = progress_printer(quiet);
  meshfit::Deformation_report r;
  std::string failure, stage = "deform";  // a failure, reported with the figures gathered so far
  try {
    r = meshfit::deform_template(
        tm, network, pairs,
        meshfit::parameters::rbf_kernel(kernel, meshfit::parameters::curve_density(
            density, meshfit::parameters::fine_level(options.fine_level, meshfit::parameters::coarse_only(
                cl.coarse_only, meshfit::parameters::progress(
                    progress, meshfit::parameters::memory_limit(
                        options.memory_limit, CGAL::parameters::number_of_iterations(rounds))))))));
  } catch (const meshfit::Numerical_error& e) {
    failure = e.what();
  } catch (const meshfit::Algorithm_failure& e) {
    failure = e.stage() == "deform" ? e.reason() : e.what();
    stage = e.stage();
  }
  if (failure.empty() && r.orientation_reversed)
    failure = meshfit::orientation_reversal_message(r.coarse_affine_determinant);
  else if (failure.empty() && density == meshfit::Curve_density::refine && !r.dropped_network_vertices.empty())
    failure = std::to_string(r.dropped_network_vertices.size()) +
              " network vertices could not be given a mesh vertex of their own (their nearest "
              "surface points are taken by nearer ones); --curve-density drop accepts that";
  else if (failure.empty() && r.remaining_flips > 0)
    failure = std::to_string(r.remaining_flips) + " faces still flip after " + std::to_string(r.flip_rounds) +
              " rounds of flip prevention (raise --max-rounds, or give more correspondences so that the "
              "coarse level brings the template closer to the curves)";
  const meshfit::Mesh_data out = meshfit::to_mesh_data(tm);

  if (!report_path.empty()) {
    std::size_t embedded = 0;
    for (std::size_t v : r.mesh_vertex_of_network_vertex) embedded += v != meshfit::Closest_point_assignment::unassigned;
    std::ostringstream js;
    js << "{\n  \"command\": \"deform\",\n  \"meshfit_version\": \"" << MESHFIT_VERSION_STRING << "\",\n"
       << json_outcome(failure, stage)
       << "  \"timings_s\": {\"read\": " << json_number(read_s) << ", \"coarse\": " << json_number(r.coarse_seconds)
       << ", \"fine\": " << json_number(r.fine_seconds) << "},\n"
       << "  \"counts\": {\"correspondences\": " << r.user_pairs << ", \"coarse_auxiliary_pairs\": "
       << r.coarse_fit.auxiliary_pairs << ", \"fine_pairs\": " << r.fine_pairs << ", \"flip_rounds\": " << r.flip_rounds
       << ", \"flips_found\": " << r.flips_found << ", \"flips_fixed\": " << (r.flips_found - r.remaining_flips)
       << ", \"flips_remaining\": " << r.remaining_flips << ", \"coarse_flipped_faces\": " << r.coarse_flipped_faces
       << ", \"orientation_reversed\": " << (r.orientation_reversed ? "true" : "false") << ", \"faces_subdivided\": " << r.faces_subdivided
       << ", \"vertices_inserted_for_density\": " << r.vertices_inserted_for_density
       << ", \"vertices_inserted_for_flips\": " << r.vertices_inserted_for_flips
       << ", \"network_vertices\": " << network.number_of_vertices() << ", \"network_vertices_embedded\": " << embedded
       << ", \"network_vertices_dropped\": " << r.dropped_network_vertices.size() << "},\n"
       << "  \"fine_level\": " << json_fine_level(r) << ",\n"
       << "  \"residuals\": {\"coarse\": " << json_number(r.coarse_fit.relative_residual) << ", \"fine\": "
       << json_number(r.fine_fit.relative_residual) << "},\n"
       << "  \"quality\": " << json_quality(out) << "\n}\n";
    write_report(report_path, js.str());
  }
  if (!failure.empty()) throw meshfit::Algorithm_failure("deform", failure);
  if (!quiet && r.coarse_flipped_faces > 0)
    std::cerr << "meshfit: deform: warning: the coarse level turns " << r.coarse_flipped_faces
              << " faces over relative to its affine part (more or better-spread pairs help)\n";
  write_output(cl, out, inputs, report_path);
  return success;
}

int run_partition(const Command_line& cl) {
  require(cl, {"--template", "--curves", "--output"}, {"--report", "--merge-tolerance"});
  const std::string& mesh_path = cl.values.at("--template");
  const std::string& curves_path = cl.values.at("--curves");
  const std::vector<std::string> inputs{mesh_path, curves_path};
  const std::string report_path = check_outputs(cl, inputs);

  Mesh tm;
  const auto t0 = std::chrono::steady_clock::now();
  meshfit::read_triangle_mesh(mesh_path, tm);
  const meshfit::Curve_network network = meshfit::read_curve_network(curves_path, merge_tolerance(cl));
  if (tm.number_of_faces() == 0)
    throw meshfit::Invalid_input(meshfit::Input_location{mesh_path, 0, meshfit::Input_location::no_offset},
                                 "the mesh has no face");
  const double read_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  auto curve = tm.add_property_map<Mesh::Edge_index, bool>("e:meshfit_curve", false).first;
  auto region = tm.add_property_map<Mesh::Face_index, int>("f:meshfit_region", 0).first;
  meshfit::Partition_report r;
  try {
    r = meshfit::partition_mesh(tm, network, meshfit::parameters::progress(progress_printer(cl.quiet),
        CGAL::parameters::edge_is_constrained_map(curve).face_patch_map(region)));
  } catch (const meshfit::Invalid_input& e) {
    // A network vertex that is not a mesh vertex: name the files.
    throw meshfit::Invalid_input(meshfit::Input_location{curves_path, 0, meshfit::Input_location::no_offset},
                                 std::string(e.what()) + " (mesh " + mesh_path + ")");
  }
  const meshfit::Mesh_data out =
      meshfit::to_mesh_data(tm, CGAL::parameters::edge_is_constrained_map(curve).face_patch_map(region));

  std::ostringstream js;
  const std::string failure =
      r.not_embedded.empty() ? "" : std::to_string(r.not_embedded.size()) + " segments could not be made mesh edges";
  js << "{\n  \"command\": \"partition\",\n  \"meshfit_version\": \"" << MESHFIT_VERSION_STRING << "\",\n"
     << json_outcome(failure, "partition")
     << "  \"timings_s\": {\"read\": " << json_number(read_s) << ", \"partition\": " << json_number(r.seconds) << "},\n"
     << "  \"counts\": {\"segments\": " << r.segments << ", \"segments_already_edges\": " << r.existing_edges
     << ", \"segments_embedded_by_walk\": " << r.by_walk << ", \"segments_embedded_by_fallback\": " << r.by_fallback
     << ", \"segments_not_embedded\": " << r.not_embedded.size() << ", \"walks_failed\": " << r.walks_failed
     << ", \"faces_crossed\": " << r.faces_crossed << ", \"edge_flips\": " << r.edge_flips
     << ", \"vertices_moved\": " << r.vertices_moved << ", \"curve_edges\": " << r.curve_edges
     << ", \"regions\": " << r.regions << "},\n"
     << "  \"not_embedded_segments\": [";
  for (std::size_t i = 0; i < r.not_embedded.size(); ++i) js << (i ? ", " : "") << r.not_embedded[i];
  js << "],\n  \"quality\": " << json_quality(out) << "\n}\n";
  write_report(report_path, js.str());

  if (!r.not_embedded.empty()) {
    std::string list;
    for (std::size_t i = 0; i < r.not_embedded.size() && i < 10; ++i) {
      const auto& sg = network.segments()[r.not_embedded[i]];
      list += (i ? ", " : "") + std::to_string(r.not_embedded[i]) + " (network vertices " + std::to_string(sg[0]) +
              "-" + std::to_string(sg[1]) + ")";
    }
    if (r.not_embedded.size() > 10) list += ", …";
    throw meshfit::Algorithm_failure(
        "partition", std::to_string(r.not_embedded.size()) + " of " + std::to_string(r.segments) +
                         " segments could not be made mesh edges without folding the mesh: segments " + list);
  }
  if (!cl.quiet)
    std::cerr << "meshfit: partition: " << r.segments << " segments: " << r.existing_edges << " already edges, "
              << r.by_walk << " by walk, " << r.by_fallback << " by fallback; " << r.regions << " regions\n";
  write_output(cl, out, inputs, report_path);
  return success;
}

/// A non-negative integer option (at most `most`), or `fallback` when absent.
long count_option(const Command_line& cl, const char* name, long fallback, long most) {
  const auto it = cl.values.find(name);
  if (it == cl.values.end()) return fallback;
  char* end = nullptr;
  const long v = std::strtol(it->second.c_str(), &end, 10);
  if (end == it->second.c_str() || *end != '\0' || v < 0 || v > most)
    throw Usage_error{std::string(name) + " needs an integer from 0 to " + std::to_string(most) + ", not '" + it->second + "'"};
  return v;
}

struct Smooth_options {
  long mean_curvature_iterations = 20, laplacian_iterations = 80;
  double step = 1;
};

Smooth_options smooth_options(const Command_line& cl) {
  Smooth_options o;
  const long total = count_option(cl, "--iterations", 100, 100000);
  o.mean_curvature_iterations = count_option(cl, "--mc-iterations", total / 5, 100000);
  o.laplacian_iterations = count_option(cl, "--laplacian-iterations", total - total / 5, 100000);
  if (cl.values.count("--step")) {
    const std::string& x = cl.values.at("--step");
    char* end = nullptr;
    o.step = std::strtod(x.c_str(), &end);
    if (end == x.c_str() || *end != '\0' || !(o.step > 0 && o.step <= 1))
      throw Usage_error{"--step needs a number in (0, 1], not '" + x + "'"};
  }
  return o;
}

int run_smooth(const Command_line& cl) {
  require(cl, {"--template", "--output"},
          {"--curves", "--report", "--merge-tolerance", "--iterations", "--mc-iterations", "--laplacian-iterations",
           "--step"});
  const std::string& template_path = cl.values.at("--template");
  std::vector<std::string> inputs{template_path};
  if (cl.values.count("--curves")) inputs.push_back(cl.values.at("--curves"));
  const std::string report_path = check_outputs(cl, inputs);
  const Smooth_options so = smooth_options(cl);
  const long mc = so.mean_curvature_iterations, lap = so.laplacian_iterations;
  const double step = so.step;

  const auto t0 = std::chrono::steady_clock::now();
  meshfit::Mesh_data data = meshfit::read_mesh_data(template_path);
  if (data.triangles.empty())
    throw meshfit::Invalid_input(meshfit::Input_location{template_path, 0, meshfit::Input_location::no_offset},
                                 "the template has no face");
  Mesh tm;
  auto curve = tm.add_property_map<Mesh::Edge_index, bool>("e:meshfit_curve", false).first;
  // Vertex i of the file is vertex i of tm (build_triangle_mesh keeps the order).
  meshfit::build_triangle_mesh(data, tm, CGAL::parameters::edge_is_constrained_map(curve));
  auto pinned = tm.add_property_map<Mesh::Vertex_index, bool>("v:meshfit_pinned", false).first;
  std::size_t network_vertices = 0, matched_vertices = 0, segments = 0, matched_segments = 0;
  if (cl.values.count("--curves")) {
    const meshfit::Curve_network network = meshfit::read_curve_network(cl.values.at("--curves"), merge_tolerance(cl));
    network_vertices = network.number_of_vertices();
    segments = network.number_of_segments();
    std::vector<Mesh::Vertex_index> on(network_vertices, Mesh::null_vertex());
    for (auto v : tm.vertices())
      if (const auto nv = network.find_vertex(tm.point(v))) {
        if (on[*nv] == Mesh::null_vertex()) ++matched_vertices;
        on[*nv] = v;
        pinned[v] = true;
      }
    for (const auto& seg : network.segments()) {
      if (on[seg[0]] == Mesh::null_vertex() || on[seg[1]] == Mesh::null_vertex()) continue;
      const auto h = CGAL::halfedge(on[seg[0]], on[seg[1]], tm);
      if (!h.second) continue;
      curve[tm.edge(h.first)] = true;
      ++matched_segments;
    }
  }
  std::size_t curve_edges = 0;
  for (auto e : tm.edges()) curve_edges += curve[e];
  const double min_angle_before = meshfit::minimum_angle_degrees(data);
  const double read_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const bool quiet = cl.quiet;
  auto progress = [quiet](const meshfit::Progress_step& s) {
    // One line per ten iterations: a hundred lines would drown the other stages' output.
    if (!quiet && (s.index % 10 == 0 || s.index + 1 == s.total))
      std::cerr << "meshfit: " << s.stage << ": " << s.step << " (" << s.index + 1 << "/" << s.total << ")\n";
    return true;
  };
  meshfit::Smoothing_report r;
  std::string failure;
  try {
    r = meshfit::smooth_mesh(
        tm, meshfit::parameters::mean_curvature_iterations(
                mc, meshfit::parameters::laplacian_iterations(
                        lap, meshfit::parameters::step_size(
                                 step, meshfit::parameters::progress(
                                           progress, CGAL::parameters::edge_is_constrained_map(curve)
                                                         .vertex_is_constrained_map(pinned))))));
  } catch (const meshfit::Numerical_error& e) {
    failure = e.what();
  }
  for (auto v : tm.vertices()) data.points[v.idx()] = tm.point(v);
  data.curve_edges.clear();
  for (auto e : tm.edges())
    if (curve[e]) data.curve_edges.push_back({tm.vertex(e, 0).idx(), tm.vertex(e, 1).idx()});

  if (!report_path.empty()) {
    std::ostringstream js;
    js << "{\n  \"command\": \"smooth\",\n  \"meshfit_version\": \"" << MESHFIT_VERSION_STRING << "\",\n"
       << json_outcome(failure, "smooth")
       << "  \"timings_s\": {\"read\": " << json_number(read_s) << ", \"smooth\": " << json_number(r.seconds) << "},\n"
       << "  \"counts\": {\"iterations\": " << r.iterations << ", \"mean_curvature_iterations\": " << mc
       << ", \"laplacian_iterations\": " << lap << ", \"fixed_vertices\": " << r.fixed_vertices
       << ", \"curve_edges\": " << curve_edges << ", \"network_vertices\": " << network_vertices
       << ", \"network_vertices_on_mesh\": " << matched_vertices << ", \"network_segments\": " << segments
       << ", \"network_segments_on_mesh\": " << matched_segments << ", \"steps_reduced\": " << r.steps_reduced
       << ", \"steps_cancelled\": " << r.steps_cancelled << ", \"clamped_cotangents\": " << r.clamped_cotangents
       << ", \"projections_clamped\": " << r.projections_clamped << "},\n"
       << "  \"displacement\": {\"mean\": " << json_number(r.mean_displacement) << ", \"max\": "
       << json_number(r.max_displacement) << ", \"last_iteration_max\": " << json_number(r.last_step_max_displacement)
       << "},\n"
       << "  \"quality\": {\"vertices\": " << data.points.size() << ", \"faces\": " << data.triangles.size()
       << ", \"minimum_angle_deg_before\": " << json_number(min_angle_before)
       << ", \"minimum_angle_deg\": " << json_number(meshfit::minimum_angle_degrees(data)) << "}\n}\n";
    write_report(report_path, js.str());
  }
  if (!failure.empty()) throw meshfit::Algorithm_failure("smooth", failure);
  if (!quiet && segments > matched_segments)
    std::cerr << "meshfit: smooth: warning: " << segments - matched_segments << " of " << segments
              << " network segments are not mesh edges (run partition first); their vertices on the mesh are "
                 "still fixed\n";
  if (!quiet)
    std::cerr << "meshfit: smooth: " << r.iterations << " iterations, " << r.fixed_vertices
              << " vertices fixed, mean displacement " << r.mean_displacement << "\n";
  write_output(cl, data, inputs, report_path);
  return success;
}

int run_view(const Command_line& cl) {
  require(cl, {"--template", "--curves", "--output"}, {"--correspondences", "--merge-tolerance"});
  meshfit_cli::View_inputs in;
  in.template_path = cl.values.at("--template");
  in.curves_path = cl.values.at("--curves");
  if (cl.values.count("--correspondences")) in.correspondences_path = cl.values.at("--correspondences");
  in.results = cl.results;
  in.merge_tolerance = merge_tolerance(cl);
  std::vector<std::string> inputs{in.template_path, in.curves_path};
  if (!in.correspondences_path.empty()) inputs.push_back(in.correspondences_path);
  inputs.insert(inputs.end(), cl.results.begin(), cl.results.end());
  for (std::size_t k = 0; k < cl.result_reports.size(); ++k)
    if (!cl.result_reports[k].empty()) inputs.push_back(cl.result_reports[k]);
  // A report belongs to its result: one given for the second result only leaves a gap ("").
  in.reports = cl.result_reports;
  const std::string& output = cl.values.at("--output");
  if (output.size() < 5 || output.compare(output.size() - 5, 5, ".html") != 0)
    throw Usage_error{"meshfit view writes a .html page, not '" + output + "'"};
  meshfit::check_output_path(output, inputs);
  meshfit_cli::View_summary s;
  meshfit::internal::write_file_atomically(output, [&](std::ostream& os) { s = meshfit_cli::write_view_page(os, in); });
  if (!cl.quiet)
    std::cerr << "meshfit: view: wrote " << output << " (template " << s.template_faces << " faces, "
              << s.network_vertices << " network vertices, " << s.pairs << " pairs, " << cl.results.size()
              << " results, " << s.result_faces << " faces)\n";
  return success;
}

int run_fit(const Command_line& cl) {
  require(cl, {"--template", "--curves", "--correspondences", "--output"},
          {"--report", "--merge-tolerance", "--kernel", "--curve-density", "--max-rounds", "--fine-level", "--max-memory", "--iterations",
           "--mc-iterations", "--laplacian-iterations", "--step"});
  if (cl.coarse_only) throw Usage_error{"meshfit fit does not take --coarse-only (use meshfit deform)"};
  const std::vector<std::string> inputs{cl.values.at("--template"), cl.values.at("--curves"),
                                        cl.values.at("--correspondences")};
  const std::string report_path = check_outputs(cl, inputs);
  const Deform_options d = deform_options(cl);
  const Smooth_options so = smooth_options(cl);
  Fit_inputs in;
  read_fit_inputs(cl, in);

  auto curve = in.tm.add_property_map<Mesh::Edge_index, bool>("e:meshfit_curve", false).first;
  auto region = in.tm.add_property_map<Mesh::Face_index, int>("f:meshfit_region", 0).first;
  meshfit::Fit_report r;
  std::string failure, stage = "fit";  // a failure, reported with the figures gathered so far
  try {
    r = meshfit::fit_template_to_curves(
        in.tm, in.network, in.pairs,
        meshfit::parameters::rbf_kernel(d.kernel, meshfit::parameters::fine_level(d.fine_level, meshfit::parameters::curve_density(
            d.density, meshfit::parameters::mean_curvature_iterations(
                so.mean_curvature_iterations, meshfit::parameters::laplacian_iterations(
                    so.laplacian_iterations, meshfit::parameters::step_size(
                        so.step, meshfit::parameters::check_self_intersections(
                            !cl.no_self_intersection_check, meshfit::parameters::progress(
                                progress_printer(cl.quiet), meshfit::parameters::memory_limit(
                                    d.memory_limit, CGAL::parameters::number_of_iterations(d.rounds)
                                    .edge_is_constrained_map(curve).face_patch_map(region)))))))))));
  } catch (const meshfit::Numerical_error& e) {
    failure = e.what();
    stage = pending_report.stage;
  } catch (const meshfit::Algorithm_failure& e) {
    failure = e.what();
    stage = e.stage();
  }
  const meshfit::Mesh_data out =
      meshfit::to_mesh_data(in.tm, CGAL::parameters::edge_is_constrained_map(curve).face_patch_map(region));
  const meshfit::Fit_verification& v = r.verification;
  const std::vector<std::string> problems = v.problems();
  const bool completed = failure.empty();
  if (completed && !problems.empty() && !cl.allow_defects) {
    std::string list;
    for (std::size_t i = 0; i < problems.size(); ++i) list += (i ? "; " : "") + problems[i];
    failure = "the result failed verification: " + list + " (--allow-defects writes it anyway)";
  }
  const meshfit::Deformation_report& dr = r.deformation;
  const meshfit::Partition_report& pr = r.partition;
  const meshfit::Smoothing_report& sr = r.smoothing;

  std::ostringstream js;
  js << "{\n  \"command\": \"fit\",\n  \"meshfit_version\": \"" << MESHFIT_VERSION_STRING << "\",\n"
     << json_outcome(failure, stage)
     << "  \"verified\": " << (completed && problems.empty() ? "true" : "false") << ",\n"
     << "  \"timings_s\": {\"read\": " << json_number(in.read_seconds) << ", \"deform\": " << json_number(r.deform_seconds)
     << ", \"partition\": " << json_number(r.partition_seconds) << ", \"smooth\": " << json_number(r.smooth_seconds)
     << ", \"verify\": " << json_number(r.verify_seconds) << ", \"total\": " << json_number(r.total_seconds) << "},\n"
     << "  \"counts\": {\"correspondences\": " << dr.user_pairs << ", \"fine_pairs\": " << dr.fine_pairs
     << ", \"flip_rounds\": " << dr.flip_rounds << ", \"flips_found\": " << dr.flips_found
     << ", \"flips_fixed\": " << (dr.flips_found - dr.remaining_flips) << ", \"flips_remaining\": " << dr.remaining_flips
     << ", \"coarse_flipped_faces\": " << dr.coarse_flipped_faces << ", \"faces_subdivided\": " << dr.faces_subdivided
     << ", \"vertices_inserted_for_density\": " << dr.vertices_inserted_for_density
     << ", \"vertices_inserted_for_flips\": " << dr.vertices_inserted_for_flips << ", \"segments\": " << pr.segments
     << ", \"segments_already_edges\": " << pr.existing_edges << ", \"segments_embedded_by_walk\": " << pr.by_walk
     << ", \"segments_embedded_by_fallback\": " << pr.by_fallback << ", \"segments_not_embedded\": " << pr.not_embedded.size()
     << ", \"faces_crossed\": " << pr.faces_crossed << ", \"edge_flips\": " << pr.edge_flips
     << ", \"vertices_moved_onto_segments\": " << pr.vertices_moved << ", \"regions\": " << pr.regions
     << ", \"smoothing_iterations\": " << sr.iterations << ", \"vertices_fixed_in_smoothing\": " << sr.fixed_vertices
     << "},\n"
     << "  \"fine_level\": " << json_fine_level(dr) << ",\n"
     << "  \"verification\": {\"network_vertices_missing\": " << v.network_vertices_missing
     << ", \"segments_not_chains\": " << v.segments_not_chains << ", \"flips_remaining\": " << v.flips_remaining
     << ", \"degenerate_faces\": " << v.degenerate_faces << ", \"folded_edges\": " << v.folded_edges
     << ", \"template_folded_edges\": " << v.template_folded_edges
     << ", \"self_intersection_checked\": " << (v.self_intersection_checked ? "true" : "false")
     << ", \"self_intersects\": " << (v.self_intersects ? "true" : "false")
     << ", \"template_self_intersects\": " << (v.template_self_intersects ? "true" : "false")
     << ", \"non_finite_coordinates\": " << v.non_finite_coordinates << ", \"regions\": " << v.regions
     << ", \"expected_regions\": " << (v.expected_regions_known ? std::to_string(v.expected_regions) : "null")
     << ", \"problems\": [";
  for (std::size_t i = 0; i < problems.size(); ++i) js << (i ? ", " : "") << "\"" << problems[i] << "\"";
  js << "]},\n"
     << "  \"quality\": {\"template_vertices\": " << r.template_vertices << ", \"template_faces\": " << r.template_faces
     << ", \"vertices\": " << out.points.size() << ", \"faces\": " << out.triangles.size()
     << ", \"minimum_angle_deg\": " << json_number(completed ? r.minimum_angle_deg : meshfit::minimum_angle_degrees(out))
     << ", \"mean_smoothing_displacement\": " << json_number(sr.mean_displacement) << "}\n}\n";
  write_report(report_path, js.str());

  if (!failure.empty()) throw meshfit::Algorithm_failure("fit", failure);
  if (!problems.empty() && !cl.quiet) {
    std::string list;
    for (std::size_t i = 0; i < problems.size(); ++i) list += (i ? "; " : "") + problems[i];
    std::cerr << "meshfit: fit: warning: defects kept (--allow-defects): " << list << "\n";
  }
  if (!cl.quiet)
    std::cerr << "meshfit: fit: " << pr.segments << " segments (" << pr.by_walk << " by walk, " << pr.by_fallback
              << " by fallback), " << pr.regions << " regions, " << dr.flips_found << " flips fixed, "
              << r.total_seconds << " s\n";
  write_output(cl, out, inputs, report_path);
  return success;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc >= 2 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
      std::cout << usage_text;
      return success;
    }
    if (argc >= 2 && std::string(argv[1]) == "--version") {
      std::cout << "meshfit " << MESHFIT_VERSION_STRING << "\n";
      return success;
    }
    const Command_line cl = parse(argc, argv);
    if (cl.command == "check") return run_check(cl);
    if (cl.command == "fit") return run_fit(cl);
    if (cl.command == "deform") return run_deform(cl);
    if (cl.command == "partition") return run_partition(cl);
    if (cl.command == "smooth") return run_smooth(cl);
    if (cl.command == "view") return run_view(cl);
    throw Usage_error{"unknown command '" + cl.command + "'"};
  } catch (const Usage_error& e) {
    std::cerr << "meshfit: " << e.message << "\n" << usage_text;
    return usage_error;
  } catch (const meshfit::Invalid_input& e) {
    std::cerr << "meshfit: error: " << e.what() << "\n";
    write_failure_report(e.what(), pending_report.stage, invalid_input);
    return invalid_input;
  } catch (const meshfit::Algorithm_failure& e) {
    std::cerr << "meshfit: failed: " << e.what() << "\n";
    write_failure_report(e.what(), e.stage(), algorithm_failed);
    return algorithm_failed;
  } catch (const std::bad_alloc&) {
    std::cerr << "meshfit: failed: out of memory (in " << pending_report.stage << "; --max-memory bounds the largest allocations)\n";
    write_failure_report("out of memory", pending_report.stage, algorithm_failed);
    return algorithm_failed;
  } catch (const std::exception& e) {
    std::cerr << "meshfit: failed: " << e.what() << "\n";
    write_failure_report(e.what(), pending_report.stage, algorithm_failed);
    return algorithm_failed;
  }
}
