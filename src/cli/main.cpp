// The meshfit command: subcommands and exit codes as fixed in DESIGN.md.
//   0 success; 1 invalid input; 2 usage error; 3 the algorithm could not complete.
#include <meshfit/check.h>
#include <meshfit/exceptions.h>
#include <meshfit/version.h>

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
    "options:\n"
    "  --merge-tolerance X  curve points closer than X times the network's bounding-box diagonal\n"
    "                       are one network vertex (default 1e-9)\n"
    "  --quiet              no progress on stderr\n"
    "  --help, --version\n";

struct Usage_error {
  std::string message;
};

struct Command_line {
  std::string command;
  std::map<std::string, std::string> values;
  bool quiet = false;
};

Command_line parse(int argc, char** argv) {
  Command_line cl;
  if (argc < 2) throw Usage_error{"no command given"};
  cl.command = argv[1];
  static const char* const valued[] = {"--template", "--curves", "--correspondences", "--output",
                                       "--report", "--merge-tolerance"};
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--quiet") { cl.quiet = true; continue; }
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
}

double merge_tolerance(const Command_line& cl) {
  const auto it = cl.values.find("--merge-tolerance");
  if (it == cl.values.end()) return meshfit::default_merge_tolerance;
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (end == it->second.c_str() || *end != '\0' || !(v > 0))
    throw Usage_error{"--merge-tolerance needs a positive number, not '" + it->second + "'"};
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

int not_available(const Command_line& cl, const char* stage) {
  std::cerr << "meshfit " << cl.command << ": not available yet: " << stage
            << " is not implemented in meshfit " << MESHFIT_VERSION_STRING << "\n";
  return usage_error;
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
    if (cl.command == "fit") return not_available(cl, "the full pipeline");
    if (cl.command == "deform") return not_available(cl, "stage 1 (global deformation)");
    if (cl.command == "partition") return not_available(cl, "stage 2 (partitioning)");
    if (cl.command == "smooth") return not_available(cl, "stage 3 (smoothing)");
    throw Usage_error{"unknown command '" + cl.command + "'"};
  } catch (const Usage_error& e) {
    std::cerr << "meshfit: " << e.message << "\n" << usage_text;
    return usage_error;
  } catch (const meshfit::Invalid_input& e) {
    std::cerr << "meshfit: error: " << e.what() << "\n";
    return invalid_input;
  } catch (const meshfit::Algorithm_failure& e) {
    std::cerr << "meshfit: failed: " << e.what() << "\n";
    return algorithm_failed;
  } catch (const std::bad_alloc&) {
    std::cerr << "meshfit: failed: out of memory\n";
    return algorithm_failed;
  } catch (const std::exception& e) {
    std::cerr << "meshfit: failed: " << e.what() << "\n";
    return algorithm_failed;
  }
}
