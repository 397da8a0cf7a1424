// The meshfit command: subcommands and exit codes as fixed in doc/design.md.
//   0 success; 1 invalid input; 2 usage error; 3 the algorithm could not complete.
#include <meshfit/check.h>
#include <meshfit/deform.h>
#include <meshfit/exceptions.h>
#include <meshfit/fit.h>
#include <meshfit/internal/format_number.h>
#include <meshfit/internal/vertex_attributes.h>
#include <meshfit/io.h>
#include <meshfit/memory_limit.h>
#include <meshfit/partition.h>
#include <meshfit/smooth.h>
#include <meshfit/threads.h>
#include <meshfit/version.h>

#include "../io/write_file.h"
#include "view.h"

#include <CGAL/IO/Color.h>
#include <CGAL/Surface_mesh.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <sys/ioctl.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <unistd.h>

#include <algorithm>

#include <chrono>
#include <cmath>
#include <initializer_list>
#include <iomanip>
#include <sstream>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <new>
#include <string>
#include <vector>

namespace {

enum Exit_status { success = 0, invalid_input = 1, usage_error = 2, algorithm_failed = 3 };

/// The version of the report's layout (doc/report-schema.json): raised when a key changes meaning
/// or is removed; keys may be added within a version.
constexpr int report_schema_version = 1;

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
  bool no_registration = false;
  bool curves_in_mesh = false;
};

// ---- the command line (CLI11) -------------------------------------------------------------------

struct Option_spec {
  const char* name;
  const char* value;  ///< the value's name in the help, nullptr for a flag
  const char* help;
};

// Every option of every command, described once.
const Option_spec option_specs[] = {
    {"--template", "MESH", "template mesh (.off, .obj, .ply, .stl, .ase); for partition and smooth, the mesh to work on"},
    {"--curves", "CURVES", "curve network: .polylines.txt (N x1 y1 z1 ...), or the curve edges of an .obj (l lines) "
                           "or .ply (edges flagged curve)"},
    {"--correspondences", "PAIRS", "pairs, one per line: 'i x y z' (template vertex i, network point) or 'i @k' "
                                   "(network vertex k)"},
    {"--output", "OUT", "output mesh: .ply (patch_id per face), .obj (g region_<k>), .vtp/.vtk (cell data region "
                        "and curve), .off, .stl; the curve edges go to OUT.curves.polylines.txt"},
    {"--split-regions", "DIR", "also write one mesh per region to DIR: region_<k>.<ext> in the output's format (the "
                               "region's faces and the vertices they use) and regions.json (file, face and vertex "
                               "counts, and each local vertex's index in the output); DIR is created if missing"},
    {"--report", "R.json", "write a JSON report (doc/report.md), also when the run fails; '-' for stdout"},
    {"--merge-tolerance", "X", "curve points closer than X times the network's bounding-box diagonal are one network "
                               "vertex"},
    {"--quiet", nullptr, "no progress on stderr"},
    {"--threads", "N", "use at most N threads (N >= 1; OpenMP and OpenBLAS); default: every core, or "
                       "OMP_NUM_THREADS / OPENBLAS_NUM_THREADS when set"},
    {"--curves-in-mesh", nullptr, "curve edges inside the output (.ply edge element flagged curve, .obj l lines) "
                                  "instead of OUT.curves.polylines.txt"},
    {"--coarse-only", nullptr, "stop after the coarse level (RBF through the given pairs)"},
    {"--kernel", "K", "RBF basis: linear (phi(r)=r) or cubic (phi(r)=r^3)"},
    {"--curve-density", "D", "refine (every network vertex gets a mesh vertex) or drop (the template keeps its size; "
                             "network vertices that lose their nearest template vertex are dropped and reported)"},
    {"--fine-level", "L", "surface (embed the curves in the coarse surface, then move them into place with a "
                          "thin-plate displacement) or thesis (nearest-vertex RBF, subdivision)"},
    {"--fine-shape", "S", "the surface fine level's shape between the curves: approach (kept from the coarse "
                          "surface brought to the curves), template (the template's bending, in the surface's "
                          "metric: Laplacian editing) or auto (template, unless the curves are sampled more "
                          "densely than the template's edges: approach; approach also when every start "
                          "leaves defects with the template's bending)"},
    {"--no-registration", nullptr, "no further starts from the template warped onto the curves as a whole (a quadratic "
                                   "map fitted by closest-point fits and Coherent Point Drift) when the surface fine "
                                   "level leaves defects"},
    {"--max-rounds", "N", "flip prevention (thesis) or untangling (surface) rounds at most"},
    {"--max-memory", "SIZE", "refuse (exit 3, with the estimate) work whose largest allocation, a dense RBF "
                             "system or reading an input (10 times its size), would exceed SIZE (2G, 512M; "
                             "default RAM / 8, at most 2G)"},
    {"--iterations", "N", "smoothing iterations in all, a fifth mean curvature and the rest Laplacian"},
    {"--mc-iterations", "N", "iterations of the modified mean-curvature flow"},
    {"--laplacian-iterations", "N", "iterations of the modified Laplacian flow"},
    {"--step", "X", "smoothing step lambda in (0, 1]"},
    {"--smooth-tolerance", "X", "a smoothing phase ends after an iteration that moves no vertex farther than X times "
                                "the mean edge length (0: every iteration runs)"},
    {"--allow-defects", nullptr, "write the result even when the final verification finds defects (segments not "
                                 "embedded, folded or degenerate faces, self-intersections); they are still reported"},
    {"--no-self-intersection-check", nullptr, "skip the final self-intersection test (the slowest check)"},
    {"--result", "MESH", "a result to show (repeatable: fit's output, or one per stage, in that order)"},
    {"--result-report", "R.json", "the report of the --result given before it, shown beside it"},
};

struct Command_spec {
  const char* name;
  const char* description;
  std::vector<const char*> required, optional;
};

const std::vector<Command_spec>& command_specs() {
  static const std::vector<const char*> deform_opts{"--kernel", "--curve-density", "--fine-level", "--fine-shape", "--max-rounds",
                                                    "--max-memory", "--no-registration"};
  static const std::vector<const char*> smooth_opts{"--iterations", "--mc-iterations", "--laplacian-iterations",
                                                    "--step", "--smooth-tolerance"};
  auto join = [](std::vector<const char*> a, const std::vector<const char*>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
  };
  // (check and view compute little and on one thread: no --threads.)
  static const std::vector<const char*> common{"--report", "--merge-tolerance", "--quiet", "--curves-in-mesh",
                                               "--threads"};
  static const std::vector<Command_spec> specs{
      {"fit", "Runs the whole pipeline: deform, partition, smooth, verify.",
       {"--template", "--curves", "--correspondences", "--output"},
       join(join(join(common, deform_opts), smooth_opts),
            {"--allow-defects", "--no-self-intersection-check", "--split-regions"})},
      {"deform", "Stage 1: moves the template onto the curves (coarse and fine levels, flip prevention).",
       {"--template", "--curves", "--correspondences", "--output"},
       join(join(common, deform_opts), {"--coarse-only"})},
      {"partition", "Stage 2: makes the network's segments mesh edges and labels the regions they bound.",
       {"--template", "--curves", "--output"},
       join(common, {"--split-regions"})},
      {"smooth", "Stage 3: tangential smoothing (thesis ch. 4); the boundary, curve edges and, with --curves, the "
                 "network's vertices and segments stay fixed.",
       {"--template", "--output"},
       join(join(common, smooth_opts), {"--curves"})},
      {"check", "Validates the inputs against each other and prints a summary.",
       {"--template", "--curves", "--correspondences"},
       {"--merge-tolerance", "--quiet"}},
      {"view", "Writes one self-contained HTML page with the inputs, the pairs and the results.",
       {"--template", "--curves", "--output"},
       {"--correspondences", "--merge-tolerance", "--quiet", "--result", "--result-report"}},
  };
  return specs;
}

// The library's default of an option, as the help says it (empty: none to say). Read from the
// library, so that the help cannot disagree with what a run without the option does.
std::string default_of(const std::string& name) {
  const meshfit::Deform_options deform;
  if (name == "--merge-tolerance") return meshfit::internal::format_number(meshfit::default_merge_tolerance);
  if (name == "--kernel") return meshfit::to_string(deform.rbf_kernel);
  if (name == "--curve-density") return deform.curve_density == meshfit::Curve_density::drop ? "drop" : "refine";
  if (name == "--fine-level") return meshfit::to_string(deform.fine_level);
  if (name == "--fine-shape") return meshfit::to_string(deform.fine_shape);
  if (name == "--max-rounds") return std::to_string(deform.flip_prevention_rounds);
  if (name == "--iterations") return std::to_string(meshfit::internal::default_smoothing_iterations);
  if (name == "--step") return meshfit::internal::format_number(meshfit::internal::Flow_settings().step);
  if (name == "--smooth-tolerance") return meshfit::internal::format_number(meshfit::internal::default_smoothing_tolerance);
  return "";
}

// The option's help with its default.
std::string help_of(const Option_spec& o) {
  const std::string d = default_of(o.name);
  return d.empty() ? o.help : std::string(o.help) + " (default " + d + ")";
}

const Option_spec& option_spec(const std::string& name) {
  for (const Option_spec& o : option_specs)
    if (name == o.name) return o;
  throw std::logic_error("no option " + name);
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

/// The closest of `candidates` to `word` (a typo: a few edits, or a prefix), or "".
std::string suggestion(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const std::string& c : candidates) {
    const std::size_t d = c.compare(0, word.size(), word) == 0 && word.size() >= 4 ? 1 : edit_distance(word, c);
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

struct Parsed {
  bool exit_now = false;  ///< --help or --version was answered
  Command_line cl;
};

// CLI11's application with every command's options, and where the values land until parse()
// puts them in the Command_line. Not movable: CLI11 holds pointers into it.
class Cli_parser {
 public:
  Cli_parser() {
    m_app.set_version_flag("--version", std::string("meshfit ") + MESHFIT_VERSION_STRING);
    m_app.require_subcommand(1, 1);
    m_app.fallthrough(false);
    m_app.get_formatter()->column_width(30);
    for (const Command_spec& c : command_specs()) {
      CLI::App* sub = m_app.add_subcommand(c.name, c.description);
      sub->fallthrough(false);
      for (const char* r : c.required) add_option(sub, c, r, true);
      for (const char* o : c.optional) add_option(sub, c, o, false);
    }
  }
  Cli_parser(const Cli_parser&) = delete;
  Cli_parser& operator=(const Cli_parser&) = delete;

  Parsed parse(int argc, char** argv) {
    Parsed parsed;
    try {
      m_app.parse(argc, argv);
    } catch (const CLI::CallForHelp&) {
      // Help of the command named on the line, or of meshfit.
      const CLI::App* shown = &m_app;
      for (const CLI::App* sub : m_app.get_subcommands()) shown = sub;
      std::cout << (shown == &m_app ? m_app.help() : shown->help("meshfit"));
      parsed.exit_now = true;
      return parsed;
    } catch (const CLI::CallForVersion& e) {
      std::cout << e.what() << "\n";
      parsed.exit_now = true;
      return parsed;
    } catch (const CLI::ParseError& e) {
      throw usage_error(e, argc, argv);
    }
    parsed.cl = command_line();
    return parsed;
  }

 private:
  void add_option(CLI::App* sub, const Command_spec& c, const char* name, bool required) {
    const Option_spec& o = option_spec(name);
    CLI::Option* opt = nullptr;
    const std::string key = std::string(c.name) + " " + name;
    if (!o.value) {
      opt = sub->add_flag(name, m_flags[key], help_of(o));
    } else if (std::string(name) == "--result") {
      // One value per occurrence (repeat the option), so that reports pair with results.
      opt = sub->add_option(name, m_results, help_of(o))->type_name(o.value)->expected(1)->allow_extra_args(false)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    } else if (std::string(name) == "--result-report") {
      opt = sub->add_option(name, m_result_reports, help_of(o))->type_name(o.value)->expected(1)->allow_extra_args(false)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    } else {
      opt = sub->add_option(name, m_holder[key], help_of(o))->type_name(o.value);
      opt->multi_option_policy(CLI::MultiOptionPolicy::Throw);
    }
    if (required) opt->required();
    m_options[c.name][name] = opt;
  }

  // CLI11's error with a suggestion for a typo: an option of the command, or a command.
  Usage_error usage_error(const CLI::ParseError& e, int argc, char** argv) {
    std::string message = e.what(), hint;
    const CLI::App* sub = m_app.get_subcommands().empty() ? nullptr : m_app.get_subcommands().front();
    std::vector<std::string> words;
    for (int i = 1; i < argc; ++i) words.push_back(argv[i]);
    if (sub) {
      std::vector<std::string> names;
      for (const auto& kv : m_options[sub->get_name()]) names.push_back(kv.first);
      names.push_back("--help");
      for (const std::string& w : words) {
        if (w.size() < 3 || w.compare(0, 2, "--") != 0) continue;
        const std::string name = w.substr(0, w.find('='));
        if (std::find(names.begin(), names.end(), name) != names.end()) continue;
        const std::string s = suggestion(name, names);
        hint += "meshfit " + sub->get_name() + " has no option " + name +
                (s.empty() ? std::string() : "; did you mean " + s + "?") + "\n";
      }
      return Usage_error{message + "\n" + hint + "(meshfit " + sub->get_name() + " --help lists its options)"};
    }
    std::vector<std::string> commands;
    for (const Command_spec& c : command_specs()) commands.push_back(c.name);
    if (!words.empty() && words[0].compare(0, 1, "-") != 0) {
      const std::string s = suggestion(words[0], commands);
      hint = "unknown command '" + words[0] + "'" + (s.empty() ? std::string() : "; did you mean " + s + "?") + "\n";
    } else if (words.empty()) {
      hint = "no command given\n";
    }
    return Usage_error{hint + message + "\n(meshfit --help lists the commands)"};
  }

  // The parsed command's values and flags.
  Command_line command_line() {
    Command_line cl;
    const CLI::App* sub = m_app.get_subcommands().front();
    cl.command = sub->get_name();
    for (const auto& kv : m_options[cl.command]) {
      if (kv.second->count() == 0) continue;
      const std::string key = cl.command + " " + kv.first;
      if (m_holder.count(key)) cl.values[kv.first] = m_holder[key];
    }
    cl.quiet = m_flags[cl.command + " --quiet"];
    cl.coarse_only = m_flags[cl.command + " --coarse-only"];
    cl.allow_defects = m_flags[cl.command + " --allow-defects"];
    cl.no_self_intersection_check = m_flags[cl.command + " --no-self-intersection-check"];
    cl.no_registration = m_flags[cl.command + " --no-registration"];
    cl.curves_in_mesh = m_flags[cl.command + " --curves-in-mesh"];
    if (cl.command == "view") pair_results(*sub, cl);
    return cl;
  }

  // A report belongs to the --result given before it.
  void pair_results(const CLI::App& sub, Command_line& cl) const {
    std::size_t r = 0, rr = 0;
    for (const CLI::Option* o : sub.parse_order()) {
      if (o->get_name() == "--result") {
        cl.results.push_back(m_results.at(r++));
      } else if (o->get_name() == "--result-report") {
        if (cl.result_reports.size() >= cl.results.size())
          throw Usage_error{"--result-report " + m_result_reports.at(rr) + " follows no --result of its own"};
        cl.result_reports.resize(cl.results.size());
        cl.result_reports.back() = m_result_reports.at(rr++);
      }
    }
  }

  CLI::App m_app{"meshfit " MESHFIT_VERSION_STRING
                 ": fits a triangle template mesh to a network of 3-D curves; the output is a mesh "
                 "partitioned into the regions the curves bound.\n"
                 "Exit status: 0 success, 1 invalid input, 2 usage error, 3 the algorithm could not complete.",
                 "meshfit"};
  std::map<std::string, std::map<std::string, CLI::Option*>> m_options;  // command -> option -> CLI11's
  std::map<std::string, std::string> m_holder;  // (single values land here, then in cl.values)
  std::vector<std::string> m_results, m_result_reports;
  std::map<std::string, bool> m_flags;
};

Parsed parse(int argc, char** argv) {
  Cli_parser parser;
  return parser.parse(argc, argv);
}

/// --threads N: limits OpenMP's and OpenBLAS's threads (meshfit::set_number_of_threads); called by
/// every command that computes, after the output paths are checked (so a bad value is reported).
void apply_thread_limit(const Command_line& cl) {
  const auto it = cl.values.find("--threads");
  if (it == cl.values.end()) return;
  const std::string& t = it->second;
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(t.c_str(), &end, 10);
  if (end == t.c_str() || *end != '\0' || errno != 0 || v < 1 || v > 4096)
    throw Usage_error{"--threads needs an integer from 1 to 4096, not '" + t + "'"};
  meshfit::set_number_of_threads(static_cast<int>(v));
}

// A number option's value, or `fallback` when it is not given; a usage error saying `range` when
// the value is not a number or `in_range` refuses it.
template <typename In_range>
double number_option(const Command_line& cl, const char* name, double fallback, In_range in_range, const char* range) {
  const auto it = cl.values.find(name);
  if (it == cl.values.end()) return fallback;
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (end == it->second.c_str() || *end != '\0' || !in_range(v))
    throw Usage_error{std::string(name) + " needs a number " + range + ", not '" + it->second + "'"};
  return v;
}

double merge_tolerance(const Command_line& cl) {
  return number_option(cl, "--merge-tolerance", meshfit::default_merge_tolerance,
                       [](double v) { return v >= 1e-15 && v <= 1e-2; }, "from 1e-15 to 1e-2");
}

int run_check(const Command_line& cl) {
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

// ---- progress -----------------------------------------------------------------------------------

/// Progress on stderr: on a terminal one line that rewrites itself (overall percentage, stage,
/// step, elapsed time); otherwise one line each time the step changes (a hundred smoothing
/// iterations are one line).
class Progress_display {
 public:
  void start(const std::string& command, bool quiet) {
    m_command = command;
    m_quiet = quiet;
    m_tty = ::isatty(2) == 1;
    m_start = std::chrono::steady_clock::now();
  }
  bool quiet() const { return m_quiet; }
  /// Where `stage` sits in the command's run, as [begin, end) of the whole.
  std::pair<double, double> span(const std::string& stage) const {
    if (m_command == "fit") {
      if (stage == "deform") return {0.0, 0.45};
      if (stage == "partition") return {0.45, 0.6};
      if (stage == "smooth") return {0.6, 0.95};
      if (stage == "fit") return {0.95, 1.0};
    }
    return {0.0, 1.0};
  }
  void step(const meshfit::Progress_step& s) {
    if (m_quiet) return;
    const double elapsed = seconds();
    if (!m_tty) {
      if (s.stage == m_stage && s.step == m_step) return;
      m_stage = s.stage;
      m_step = s.step;
      std::cerr << "meshfit: " << s.stage << ": " << s.step;
      if (s.total > 1) std::cerr << " (" << s.index + 1 << "/" << s.total << ")";
      std::cerr << "\n";
      return;
    }
    const auto now = std::chrono::steady_clock::now();
    if (s.stage == m_stage && s.step == m_step && s.index + 1 < s.total &&
        now - m_last_draw < std::chrono::milliseconds(100))
      return;
    m_stage = s.stage;
    m_step = s.step;
    m_last_draw = now;
    const auto [begin, end] = span(s.stage);
    double within = s.total > 0 ? double(s.index) / double(s.total) : 0.0;
    // deform numbers its coarse and its fine steps from 0 each: the coarse level is the first fifth.
    if (s.stage == "deform") within = s.step.compare(0, 5, "fine:") == 0 ? 0.2 + 0.8 * within : 0.2 * within;
    m_percent = std::max(m_percent, static_cast<int>(100 * (begin + (end - begin) * within)));
    const int percent = m_percent;
    std::ostringstream line;
    line << "meshfit " << m_command << ' ' << std::setw(3) << percent << "%  " << std::fixed << std::setprecision(1)
         << elapsed << " s  " << s.stage << ": " << s.step;
    if (s.total > 1) line << " (" << s.index + 1 << "/" << s.total << ")";
    std::string text = line.str();
    winsize w{};
    const std::size_t width = ::ioctl(2, TIOCGWINSZ, &w) == 0 && w.ws_col > 10 ? w.ws_col - 1 : 79;
    if (text.size() > width) text.resize(width);
    std::cerr << "\r\033[K" << text << std::flush;
    m_line_shown = true;
  }
  /// Ends the rewriting line, before other output.
  void finish() {
    if (m_line_shown) std::cerr << "\r\033[K" << std::flush;
    m_line_shown = false;
  }
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
  }

 private:
  std::string m_command, m_stage, m_step;
  bool m_quiet = true, m_tty = false, m_line_shown = false;
  int m_percent = 0;  ///< never goes back
  std::chrono::steady_clock::time_point m_start, m_last_draw;
} progress_display;

// ---- the report (nlohmann-json; doc/report-schema.json) -----------------------------------------

using Json = nlohmann::ordered_json;

/// A number, or null when it is not finite (JSON has no NaN or infinity).
Json number(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

/// The report of the running command once its path is checked, so that every exit 1 or 3 after
/// that writes one (main's handlers write a short one when the command did not get to it).
struct Pending_report {
  std::string path, command;
  std::string stage = "read";  ///< the stage running (from the progress callback)
  Json inputs = Json::object(), outputs = Json::object();
  Json warnings = Json::array();  ///< warnings known before the command's figures (reading)
  bool written = false;
} pending_report;

/// A report with every top-level key, the same in every command: what the run did and whether it
/// completed. Commands fill timings_s, counts, quality and details.
Json report_skeleton(const std::string& command, const std::string& failure, const std::string& stage,
                     int exit_status, const std::vector<meshfit::Failure_figure>& figures = {}) {
  Json j;
  j["schema"] = "meshfit-report";
  j["schema_version"] = report_schema_version;
  j["command"] = command;
  j["meshfit_version"] = MESHFIT_VERSION_STRING;
  j["completed"] = failure.empty();
  j["failure"] = failure.empty() ? Json(nullptr) : Json(failure);
  j["stage"] = failure.empty() ? Json(nullptr) : Json(stage);
  // The numbers behind an Algorithm_failure, by name (null when there are none).
  j["failure_figures"] = nullptr;
  for (const meshfit::Failure_figure& f : figures) j["failure_figures"][f.name] = number(f.value);
  j["exit_status"] = exit_status;
  j["verified"] = nullptr;
  j["inputs"] = pending_report.inputs;
  j["outputs"] = pending_report.outputs;
  j["timings_s"] = Json::object();
  j["counts"] = Json::object();
  j["quality"] = Json::object();
  j["details"] = Json::object();
  j["warnings"] = pending_report.warnings;
  return j;
}

/// Whether `a` and `b` name the same file: the same existing file, or the same path once made
/// absolute and normal (as meshfit::check_output_path compares an output with an input).
bool same_file(const std::string& a, const std::string& b) {
  std::error_code e1, e2, e3;
  if (std::filesystem::exists(a, e1) && std::filesystem::exists(b, e2) && std::filesystem::equivalent(a, b, e3))
    return true;
  std::error_code ea, eb;
  const std::filesystem::path ca = std::filesystem::weakly_canonical(a, ea), cb = std::filesystem::weakly_canonical(b, eb);
  return !ea && !eb && ca == cb;
}

/// Checks the output paths before any work: the mesh output's format, that it, its curve file and
/// the report can be written (regular files in existing directories), and that none is an input or
/// another output. Returns the report path ("" when none; "-" for stdout).
std::string check_outputs(const Command_line& cl, const std::vector<std::string>& inputs) {
  const std::string& output = cl.values.at("--output");
  meshfit::mesh_format_of(output);
  meshfit::check_output_path(output, inputs);
  pending_report.inputs = Json::object();
  for (const char* k : {"--template", "--curves", "--correspondences"})
    if (cl.values.count(k)) pending_report.inputs[std::string(k + 2)] = cl.values.at(k);
  pending_report.outputs = Json::object();
  pending_report.outputs["mesh"] = output;
  pending_report.outputs["curves"] = nullptr;
  std::vector<std::string> others = inputs;
  others.push_back(output);
  std::vector<std::pair<std::string, std::string>> outputs{{"the output mesh", output}};
  if (!cl.curves_in_mesh && cl.command != "deform") {
    const std::string curves = meshfit::curve_edges_path(output);
    meshfit::check_output_path(curves, others);
    others.push_back(curves);
    outputs.emplace_back("the curve file written beside the output", curves);
  }
  if (meshfit::mesh_format_of(output) == meshfit::Mesh_format::obj) {
    // The regions' materials, beside an .obj output (write_output).
    const std::string materials = meshfit::material_library_path(output);
    meshfit::check_output_path(materials, others);
    others.push_back(materials);
    outputs.emplace_back("the material library written beside the output", materials);
  }
  pending_report.outputs["regions"] = nullptr;
  std::string report_path;
  if (cl.values.count("--report")) {
    report_path = cl.values.at("--report");
    if (report_path != "-") {
      // The report on an output: a message that names that output (check_output_path's speaks of
      // an input).
      for (const auto& [what, path] : outputs)
        if (same_file(report_path, path))
          throw meshfit::Invalid_input(meshfit::Input_location{report_path, 0, meshfit::Input_location::no_offset},
                                       "the report is " + what + " '" + path + "'; give the report a name of its own");
      meshfit::check_output_path(report_path, others);
      for (const std::string& o : others)
        if (o != report_path) meshfit::check_output_path(o, {report_path});
      others.push_back(report_path);
    }
  }
  // The region meshes' directory, with none of the other paths where a region file would go.
  if (cl.values.count("--split-regions"))
    meshfit::check_region_directory(cl.values.at("--split-regions"), meshfit::mesh_format_of(output), others);
  if (report_path.empty()) return "";
  pending_report.path = report_path;
  pending_report.command = cl.command;
  return report_path;
}

/// The path of the index of the region meshes (`--split-regions DIR`): DIR/regions.json.
std::string regions_index_path(const std::string& dir) { return (std::filesystem::path(dir) / "regions.json").string(); }

/// The warnings of a template read: every attribute the reader read past and the output does not
/// carry, into the report (every report, failures too) and on stderr.
void warn_dropped_attributes(const meshfit::Mesh_read_report& read, const std::string& path, bool quiet) {
  for (const std::string& a : read.dropped_attributes) {
    const std::string w = path + ": " + a + " are read and not carried to the output";
    pending_report.warnings.push_back(w);
    if (!quiet) std::cerr << "meshfit: " << pending_report.command << ": warning: " << w << "\n";
  }
}

/// The per-vertex attributes `data` holds, as the readers name them.
std::vector<std::string> vertex_attribute_names(const meshfit::Mesh_data& data) {
  std::vector<std::string> names;
  if (!data.vertex_uvs.empty()) names.push_back("texture coordinates");
  if (!data.vertex_normals.empty()) names.push_back("vertex normals");
  if (!data.vertex_colors.empty()) names.push_back("vertex colours");
  return names;
}

/// The per-vertex attributes of a template read (Mesh_data::vertex_uvs, …): every command carries
/// them to .obj, .ply, .vtp and .vtk outputs (VTK point data: TCoords, Normals, Colors) and warns
/// that .off and .stl do not hold them. Called before the report is begun (its warnings).
void note_vertex_attributes(const meshfit::Mesh_data& data, const std::string& path, const Command_line& cl) {
  const meshfit::Mesh_format format = meshfit::mesh_format_of(cl.values.at("--output"));
  if (format != meshfit::Mesh_format::off && format != meshfit::Mesh_format::stl) return;
  for (const std::string& a : vertex_attribute_names(data)) {
    const std::string w = path + ": " + a + " are read and not carried to the output (" + meshfit::to_string(format) +
                          " holds no vertex attributes: write .obj, .ply, .vtp or .vtk)";
    pending_report.warnings.push_back(w);
    if (!cl.quiet) std::cerr << "meshfit: " << pending_report.command << ": warning: " << w << "\n";
  }
}

void write_report(const std::string& report_path, const Json& report) {
  if (report_path.empty()) return;
  pending_report.written = true;  // (a failure to write it is not retried)
  const std::string text = report.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
  if (report_path == "-") {
    std::cout << text << std::flush;
    return;
  }
  meshfit::internal::write_file_atomically(report_path, [&](std::ostream& os) { os << text; });
}

/// The report of a command that failed before it could gather its figures (bad input found after
/// the paths were checked, out of memory, an unexpected error): written by main.
void write_failure_report(const std::string& failure, const std::string& stage, int exit_status,
                          const std::vector<meshfit::Failure_figure>& figures = {}) noexcept {
  if (pending_report.path.empty() || pending_report.written) return;
  try {
    write_report(pending_report.path, report_skeleton(pending_report.command, failure, stage, exit_status, figures));
  } catch (const std::exception& e) {
    std::cerr << "meshfit: could not write the report: " << e.what() << "\n";
  }
}

/// Writes the output mesh, never over an input or the report, and its curve edges beside it.
void write_output(const Command_line& cl, const meshfit::Mesh_data& out, const std::vector<std::string>& inputs,
                  const std::string& report_path) {
  meshfit::Write_options options;
  options.protected_paths = inputs;
  options.curves_in_mesh = cl.curves_in_mesh;
  if (!report_path.empty() && report_path != "-") options.protected_paths.push_back(report_path);
  const std::string& output = cl.values.at("--output");
  // An .obj with regions names its material library, written beside it (not for the region files).
  const bool materials = meshfit::mesh_format_of(output) == meshfit::Mesh_format::obj && !out.face_patch.empty();
  const std::string materials_path = meshfit::material_library_path(output);
  if (materials) {
    options.material_library = std::filesystem::path(materials_path).filename().string();
    options.protected_paths.push_back(materials_path);
  }
  options.protected_paths.push_back(meshfit::curve_edges_path(output));
  meshfit::write_mesh_data(output, out, options);
  options.material_library.clear();
  if (materials) {
    meshfit::Write_options m = options;
    m.protected_paths.erase(std::find(m.protected_paths.begin(), m.protected_paths.end(), materials_path));
    m.protected_paths.push_back(output);
    meshfit::write_material_library(materials_path, out, m);
  }
  progress_display.finish();
  if (!cl.quiet)
    std::cerr << "meshfit: " << cl.command << ": wrote " << output << " (" << out.points.size() << " vertices, "
              << out.triangles.size() << " faces)\n";
  if (!cl.curves_in_mesh && !out.curve_edges.empty()) {
    options.protected_paths.back() = output;
    const std::string curves = meshfit::curve_edges_path(output);
    meshfit::write_curve_edges(curves, out, options);
    if (!cl.quiet)
      std::cerr << "meshfit: " << cl.command << ": wrote " << curves << " (" << out.curve_edges.size()
                << " curve edges)\n";
  }
  if (cl.values.count("--split-regions")) {
    // One mesh per region in the output's format, and the index that maps their vertices back.
    const std::string& dir = cl.values.at("--split-regions");
    const meshfit::Mesh_format format = meshfit::mesh_format_of(output);
    options.protected_paths.back() = output;
    if (!cl.curves_in_mesh) options.protected_paths.push_back(meshfit::curve_edges_path(output));
    const std::vector<meshfit::Region_mesh> regions = meshfit::write_region_meshes(dir, out, format, options);
    Json index;
    index["schema"] = "meshfit-regions";
    index["schema_version"] = 1;
    index["mesh"] = output;
    index["vertices"] = out.points.size();
    index["faces"] = out.triangles.size();
    index["regions"] = Json::array();
    for (const meshfit::Region_mesh& r : regions)
      index["regions"].push_back({{"region", r.region},
                                  {"file", meshfit::region_file_name(r.region, format)},
                                  {"faces", r.mesh.triangles.size()},
                                  {"vertices", r.mesh.points.size()},
                                  {"vertex_in_mesh", r.vertex_in_full}});
    const std::string index_path = regions_index_path(dir);
    meshfit::check_output_path(index_path, options.protected_paths);
    // One line per region (its vertex map can be long), the rest as the report is laid out.
    std::string text = "{\n";
    for (auto it = index.begin(); it != index.end(); ++it) {
      text += "  " + Json(it.key()).dump() + ": ";
      if (it.key() != "regions") {
        text += it.value().dump(-1, ' ', false, Json::error_handler_t::replace) + ",\n";
        continue;
      }
      text += "[";
      for (std::size_t k = 0; k < it.value().size(); ++k)
        text += std::string(k ? "," : "") + "\n    " + it.value()[k].dump(-1, ' ', false, Json::error_handler_t::replace);
      text += "\n  ]\n";
    }
    text += "}\n";
    meshfit::internal::write_file_atomically(index_path, [&](std::ostream& os) { os << text; });
    if (!cl.quiet)
      std::cerr << "meshfit: " << cl.command << ": wrote " << regions.size() << " region meshes and " << index_path
                << "\n";
  }
}

/// Fills the report's `outputs.curves` with the curve file the run will write (after work).
void note_curve_output(const Command_line& cl, const meshfit::Mesh_data& out, Json& report) {
  if (!cl.curves_in_mesh && !out.curve_edges.empty())
    report["outputs"]["curves"] = meshfit::curve_edges_path(cl.values.at("--output"));
  if (cl.values.count("--split-regions"))
    report["outputs"]["regions"] = regions_index_path(cl.values.at("--split-regions"));
}

meshfit::Progress_callback progress_printer() {
  return [](const meshfit::Progress_step& s) {
    pending_report.stage = s.stage;
    progress_display.step(s);
    return true;
  };
}

/// The fine level's own figures, the same block in the reports of deform and fit.
Json json_fine_level(const meshfit::Deformation_report& r) {
  Json j;
  j["method"] = meshfit::to_string(r.fine_level);
  if (r.fine_level == meshfit::Fine_level::surface) {
    j["largest_projection_distance"] = number(r.largest_projection_distance);
    j["template_subdivisions"] = r.template_subdivisions;
    j["network_points_added"] = r.network_points_added;
    j["approach"] = meshfit::to_string(r.approach);
    j["shape"] = meshfit::to_string(r.fine_shape);
    j["approach_constraints"] = r.approach_constraints;
    j["approach_scale"] = number(r.approach_scale);
    j["approach_coarse_nodes"] = r.approach_coarse_nodes;
    j["approach_retried"] = r.approach_retried;
    j["segments_embedded"] = r.segments_embedded;
    j["segments_not_embedded"] = r.segments_not_embedded.size();
    j["segments_by_shortest_path"] = r.segments_by_shortest_path;
    j["edges_split_between_curves"] = r.edges_split_between_curves;
    j["projections_off_nearest"] = r.projections_off_nearest;
    j["displacement_free_vertices"] = r.displacement.free_vertices;
    j["displacement_held_beyond_band"] = r.displacement.held_beyond_band;
    j["untangle_rounds"] = r.untangle_rounds;
    j["untangled_vertices"] = r.untangled_vertices;
    Json near = Json::array();
    for (std::size_t k : r.polylines_near_defects) near.push_back(k + 1);
    j["polylines_near_defects"] = near;
    j["remaining_folds"] = r.remaining_folds;
    j["coarse_registered"] = r.coarse_registered;
    j["registration_iterations"] = r.registration.iterations;
    j["registration_turns_over"] = r.registration.turns_over;
    const bool registered = r.registration.iterations > 0;
    j["registration_distance_before"] = registered ? number(r.registration.mean_distance_before) : Json(nullptr);
    const bool warped = registered && !r.registration.turns_over;
    j["registration_distance_after"] = warped ? number(r.registration.mean_distance_after) : Json(nullptr);
    j["registration_closest_point_iterations"] = r.registration.closest_point_iterations;
    j["registration_candidates"] = r.registration.candidates;
    j["registration_candidates_turning_over"] = r.registration.candidates_turning_over;
    j["registration_candidates_keeping_pairs"] = r.registration.candidates_keeping_pairs;
    j["registration_method"] =
        !warped ? Json(nullptr)
                : Json(r.registration.method == meshfit::Registration_method::closest_point ? "closest_point" : "coherent_point_drift");
    j["registration_pair_weight"] = warped ? number(r.registration.pair_weight) : Json(nullptr);
    j["registration_far_matches_left_out"] = warped ? Json(r.registration.far_matches_left_out) : Json(nullptr);
    j["registered_start"] = r.registered_start;
  }
  j["coarse_affine_determinant"] = number(r.coarse_affine_determinant);
  return j;
}

Json json_quality(const meshfit::Mesh_data& out) {
  Json j;
  j["vertices"] = out.points.size();
  j["faces"] = out.triangles.size();
  j["minimum_angle_deg"] = number(meshfit::minimum_angle_degrees(out));
  return j;
}

// `option`'s value, one of the spellings of `choices`, as the value it names; `value` unchanged
// when the option is not given.
template <typename T>
void set_choice(const Command_line& cl, const char* option, std::initializer_list<std::pair<const char*, T>> choices,
                T& value) {
  const auto it = cl.values.find(option);
  if (it == cl.values.end()) return;
  std::string names;
  std::size_t k = 0;
  for (const auto& [name, v] : choices) {
    if (it->second == name) {
      value = v;
      return;
    }
    names += (k == 0 ? "" : k + 1 == choices.size() ? " or " : ", ") + std::string(name);
    ++k;
  }
  throw Usage_error{std::string(option) + " must be " + names + ", not '" + it->second + "'"};
}

// Stage 1's options: the library's defaults (meshfit::Deform_options), changed by the command line.
meshfit::Deform_options deform_options(const Command_line& cl) {
  meshfit::Deform_options o;
  set_choice(cl, "--kernel", {{"linear", meshfit::Rbf_kernel::linear}, {"cubic", meshfit::Rbf_kernel::cubic}}, o.rbf_kernel);
  set_choice(cl, "--curve-density", {{"refine", meshfit::Curve_density::refine}, {"drop", meshfit::Curve_density::drop}},
             o.curve_density);
  set_choice(cl, "--fine-level", {{"surface", meshfit::Fine_level::surface}, {"thesis", meshfit::Fine_level::thesis}},
             o.fine_level);
  set_choice(cl, "--fine-shape",
             {{"auto", meshfit::Fine_shape::automatic},
              {"approach", meshfit::Fine_shape::approach},
              {"template", meshfit::Fine_shape::template_bending}},
             o.fine_shape);
  o.coarse_registration = !cl.no_registration;
  if (cl.values.count("--max-rounds")) {
    const std::string& r = cl.values.at("--max-rounds");
    char* end = nullptr;
    const long v = std::strtol(r.c_str(), &end, 10);
    if (end == r.c_str() || *end != '\0' || v < 1 || v > 1000)
      throw Usage_error{"--max-rounds needs an integer from 1 to 1000, not '" + r + "'"};
    o.flip_prevention_rounds = static_cast<std::size_t>(v);
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
  /// The template as read: its vertex attributes (vertex i is the i-th vertex of tm).
  meshfit::Mesh_data template_data;
  meshfit::Curve_network network;
  std::vector<meshfit::Correspondence> pairs;
  double read_seconds = 0;
};

/// Reading a file takes several times its size in memory (the text, the points, the merge grid:
/// a 57 MB polyline peaked at 10 times): like the dense RBF, refused before it is read when that
/// would exceed --max-memory.
void check_reading_memory(const std::string& path, std::size_t memory_limit) {
  std::error_code ec;
  const double size = static_cast<double>(std::filesystem::file_size(path, ec));
  if (!ec)
    meshfit::check_memory_estimate(10 * size, memory_limit, "read",
                                   "the input file '" + path + "' (" + meshfit::format_bytes(size) +
                                       "; reading takes about 10 times its size)");
}

void read_fit_inputs(const Command_line& cl, Fit_inputs& in) {
  const std::string& template_path = cl.values.at("--template");
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t memory_limit = deform_options(cl).memory_limit;
  for (const char* input : {"--template", "--curves", "--correspondences"})
    check_reading_memory(cl.values.at(input), memory_limit);
  meshfit::Mesh_read_report read;
  in.template_data = meshfit::read_mesh_data(template_path, &read);
  meshfit::build_triangle_mesh(in.template_data, in.tm);
  warn_dropped_attributes(read, template_path, cl.quiet);
  note_vertex_attributes(in.template_data, template_path, cl);
  in.network = meshfit::read_curve_network(cl.values.at("--curves"), merge_tolerance(cl));
  in.pairs = meshfit::read_correspondences(cl.values.at("--correspondences"), in.network);
  const meshfit::Mesh_data& template_data = in.template_data;
  if (template_data.triangles.empty())
    throw meshfit::Invalid_input(meshfit::Input_location{template_path, 0, meshfit::Input_location::no_offset},
                                 "the template has no face");
  // Coplanar template vertices are accepted here: the RBF adds auxiliary pairs off the plane.
  meshfit::validate_correspondences(in.pairs, template_data.points, in.network, true);
  in.read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The input files of deform and fit.
std::vector<std::string> fit_input_paths(const Command_line& cl) {
  return {cl.values.at("--template"), cl.values.at("--curves"), cl.values.at("--correspondences")};
}

/// A stage's failure, reported with the figures gathered so far; no `message`: none.
struct Stage_failure {
  std::string message, stage;
  std::vector<meshfit::Failure_figure> figures;
};

/// Stage 1 on the inputs: what went wrong in it, if anything.
Stage_failure deform_inputs(Fit_inputs& in, const meshfit::Deform_options& options, meshfit::Deformation_report& r) {
  Stage_failure failure{"", "deform", {}};
  try {
    r = meshfit::deform_template(in.tm, in.network, in.pairs, meshfit::deform_parameters(options));
  } catch (const meshfit::Numerical_error& e) {
    failure.message = e.what();
  } catch (const meshfit::Algorithm_failure& e) {
    failure.message = e.stage() == "deform" ? e.reason() : e.what();
    failure.stage = e.stage();
    failure.figures = e.figures();
  }
  return failure;
}

/// What makes a deformation that ran to its end a failure all the same, or "".
std::string deform_result_failure(const meshfit::Deformation_report& r, const meshfit::Deform_options& options) {
  if (r.orientation_reversed) return meshfit::orientation_reversal_message(r.coarse_affine_determinant);
  if (options.curve_density == meshfit::Curve_density::refine && !r.dropped_network_vertices.empty())
    return std::to_string(r.dropped_network_vertices.size()) +
           " network vertices could not be given a mesh vertex of their own (their nearest "
           "surface points are taken by nearer ones); --curve-density drop accepts that";
  if (r.remaining_flips > 0) return meshfit::remaining_flips_message(r);
  return "";
}

/// The counts of the fine level's pairs and of the flips, in the reports of deform and fit.
void add_flip_counts(const meshfit::Deformation_report& r, Json& counts) {
  counts["fine_pairs"] = r.fine_pairs;
  counts["flip_rounds"] = r.flip_rounds;
  counts["flips_found"] = r.flips_found;
  counts["flips_fixed"] = r.flips_found - r.remaining_flips;
  counts["flips_remaining"] = r.remaining_flips;
  counts["coarse_flipped_faces"] = r.coarse_flipped_faces;
}

/// The counts of the faces subdivided and the vertices inserted, in the reports of deform and fit.
void add_insertion_counts(const meshfit::Deformation_report& r, Json& counts) {
  counts["faces_subdivided"] = r.faces_subdivided;
  counts["vertices_inserted_for_density"] = r.vertices_inserted_for_density;
  counts["vertices_inserted_for_flips"] = r.vertices_inserted_for_flips;
}

Json deform_report(const meshfit::Deformation_report& r, const Stage_failure& failure, const Fit_inputs& in,
                   const meshfit::Mesh_data& out) {
  std::size_t embedded = 0;
  for (std::size_t v : r.mesh_vertex_of_network_vertex) embedded += v != meshfit::Closest_point_assignment::unassigned;
  Json js = report_skeleton("deform", failure.message, failure.stage,
                            failure.message.empty() ? success : algorithm_failed, failure.figures);
  js["timings_s"] = {{"read", number(in.read_seconds)}, {"coarse", number(r.coarse_seconds)},
                     {"fine", number(r.fine_seconds)}, {"total", number(progress_display.seconds())}};
  Json& counts = js["counts"];
  counts["correspondences"] = r.user_pairs;
  counts["coarse_auxiliary_pairs"] = r.coarse_fit.auxiliary_pairs;
  add_flip_counts(r, counts);
  counts["orientation_reversed"] = r.orientation_reversed;
  add_insertion_counts(r, counts);
  counts["network_vertices"] = in.network.number_of_vertices();
  counts["network_vertices_embedded"] = embedded;
  counts["network_vertices_dropped"] = r.dropped_network_vertices.size();
  js["quality"] = json_quality(out);
  js["details"]["fine_level"] = json_fine_level(r);
  js["details"]["residuals"] = {{"coarse", number(r.coarse_fit.relative_residual)},
                                {"fine", number(r.fine_fit.relative_residual)}};
  if (r.coarse_flipped_faces > 0)
    js["warnings"].push_back("the coarse level turns " + std::to_string(r.coarse_flipped_faces) +
                             " faces over relative to its affine part");
  return js;
}

int run_deform(const Command_line& cl) {
  const std::vector<std::string> inputs = fit_input_paths(cl);
  const std::string report_path = check_outputs(cl, inputs);
  apply_thread_limit(cl);

  meshfit::Deform_options options = deform_options(cl);
  options.coarse_only = cl.coarse_only;
  options.progress = progress_printer();

  Fit_inputs in;
  read_fit_inputs(cl, in);
  meshfit::Deformation_report r;
  Stage_failure failure = deform_inputs(in, options, r);
  if (failure.message.empty()) failure.message = deform_result_failure(r, options);
  meshfit::Mesh_data out = meshfit::to_mesh_data(in.tm);
  if (failure.message.empty()) meshfit::internal::extend_vertex_attributes(in.template_data, out);

  if (!report_path.empty()) write_report(report_path, deform_report(r, failure, in, out));
  progress_display.finish();
  if (!failure.message.empty()) throw meshfit::Algorithm_failure("deform", failure.message);
  if (!cl.quiet && r.coarse_flipped_faces > 0)
    std::cerr << "meshfit: deform: warning: the coarse level turns " << r.coarse_flipped_faces
              << " faces over relative to its affine part (more or better-spread pairs help)\n";
  write_output(cl, out, inputs, report_path);
  return success;
}

/// How the segments were made mesh edges, in the reports of partition and fit.
void add_segment_counts(const meshfit::Partition_report& r, Json& counts) {
  counts["segments"] = r.segments;
  counts["segments_already_edges"] = r.existing_edges;
  counts["segments_embedded_by_walk"] = r.by_walk;
  counts["segments_embedded_by_fallback"] = r.by_fallback;
  counts["segments_not_embedded"] = r.not_embedded.size();
}

int run_partition(const Command_line& cl) {
  const std::string& mesh_path = cl.values.at("--template");
  const std::string& curves_path = cl.values.at("--curves");
  const std::vector<std::string> inputs{mesh_path, curves_path};
  const std::string report_path = check_outputs(cl, inputs);
  apply_thread_limit(cl);

  Mesh tm;
  const auto t0 = std::chrono::steady_clock::now();
  meshfit::Mesh_read_report read;
  const meshfit::Mesh_data data = meshfit::read_mesh_data(mesh_path, &read);
  meshfit::build_triangle_mesh(data, tm);
  warn_dropped_attributes(read, mesh_path, cl.quiet);
  note_vertex_attributes(data, mesh_path, cl);
  const meshfit::Curve_network network = meshfit::read_curve_network(curves_path, merge_tolerance(cl));
  if (tm.number_of_faces() == 0)
    throw meshfit::Invalid_input(meshfit::Input_location{mesh_path, 0, meshfit::Input_location::no_offset},
                                 "the mesh has no face");
  const double read_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  auto curve = tm.add_property_map<Mesh::Edge_index, bool>("e:meshfit_curve", false).first;
  auto region = tm.add_property_map<Mesh::Face_index, int>("f:meshfit_region", 0).first;
  meshfit::Partition_report r;
  try {
    r = meshfit::partition_mesh(
        tm, network,
        meshfit::parameters::progress(progress_printer()).edge_is_constrained_map(curve).face_patch_map(region));
  } catch (const meshfit::Invalid_input& e) {
    // A network vertex that is not a mesh vertex: name the files.
    throw meshfit::Invalid_input(meshfit::Input_location{curves_path, 0, meshfit::Input_location::no_offset},
                                 std::string(e.what()) + " (mesh " + mesh_path + ")");
  }
  meshfit::Mesh_data out =
      meshfit::to_mesh_data(tm, CGAL::parameters::edge_is_constrained_map(curve).face_patch_map(region));
  // Partitioning adds no vertex and keeps their order: the attributes stay as read.
  out.vertex_uvs = data.vertex_uvs;
  out.vertex_normals = data.vertex_normals;
  out.vertex_colors = data.vertex_colors;

  const std::string failure =
      r.not_embedded.empty() ? "" : std::to_string(r.not_embedded.size()) + " segments could not be made mesh edges";
  Json js = report_skeleton("partition", failure, "partition", failure.empty() ? success : algorithm_failed);
  js["timings_s"] = {{"read", number(read_s)}, {"partition", number(r.seconds)},
                     {"total", number(progress_display.seconds())}};
  Json& counts = js["counts"];
  add_segment_counts(r, counts);
  counts.update(Json{{"walks_failed", r.walks_failed},
                     {"faces_crossed", r.faces_crossed},
                     {"edge_flips", r.edge_flips},
                     {"vertices_moved_onto_segments", r.vertices_moved},
                     {"vertices_moved", r.vertices_moved},  // deprecated (doc/report.md): the same figure
                     {"curve_edges", r.curve_edges},
                     {"regions", r.regions}});
  js["quality"] = json_quality(out);
  js["details"]["not_embedded_segments"] = r.not_embedded;
  if (failure.empty()) note_curve_output(cl, out, js);
  write_report(report_path, js);
  progress_display.finish();

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
  long mean_curvature_iterations = 0, laplacian_iterations = 0;
  double step = meshfit::internal::Flow_settings().step;
  double tolerance = meshfit::internal::default_smoothing_tolerance;
};

Smooth_options smooth_options(const Command_line& cl) {
  Smooth_options o;
  const long total =
      count_option(cl, "--iterations", static_cast<long>(meshfit::internal::default_smoothing_iterations), 100000);
  // The library's split of the total between the phases; a phase's own count replaces its share.
  const auto phases = meshfit::internal::smoothing_phases(CGAL::parameters::number_of_iterations(total));
  o.mean_curvature_iterations = count_option(cl, "--mc-iterations", static_cast<long>(phases.mean_curvature), 100000);
  o.laplacian_iterations = count_option(cl, "--laplacian-iterations", static_cast<long>(phases.laplacian), 100000);
  o.step = number_option(cl, "--step", o.step, [](double v) { return v > 0 && v <= 1; }, "in (0, 1]");
  o.tolerance = number_option(cl, "--smooth-tolerance", o.tolerance,
                              [](double v) { return std::isfinite(v) && v >= 0; }, "not below 0");
  return o;
}

using Edge_flags = Mesh::Property_map<Mesh::Edge_index, bool>;
using Vertex_flags = Mesh::Property_map<Mesh::Vertex_index, bool>;

/// How much of the --curves network smooth found on the mesh (all 0 without --curves).
struct Network_match {
  std::size_t network_vertices = 0, matched_vertices = 0, segments = 0, matched_segments = 0;
};

/// What smooth read and did, for its report and messages.
struct Smooth_run {
  meshfit::Mesh_read_report read_report;
  meshfit::Mesh_data data;
  std::string curves_beside;  ///< the curve-edge file read beside the mesh, if any
  Network_match match;
  std::size_t curve_edges = 0;
  double min_angle_before = 0, read_seconds = 0;
  meshfit::Smoothing_report r;
  std::string failure, ignored_edges;
};

/// Reads smooth's mesh, with the curve edges partition's output keeps beside it.
void read_smooth_mesh(const Command_line& cl, Smooth_run& run) {
  const std::string& template_path = cl.values.at("--template");
  run.data = meshfit::read_mesh_data(template_path, &run.read_report);
  warn_dropped_attributes(run.read_report, template_path, cl.quiet);
  note_vertex_attributes(run.data, template_path, cl);  // smoothing moves vertices only
  // partition's output keeps its curve edges beside it unless --curves-in-mesh: they are the
  // constraints all the same.
  run.curves_beside = meshfit_cli::add_curve_edges_beside(run.data, template_path);
  if (!run.curves_beside.empty()) pending_report.inputs["curve_edges"] = run.curves_beside;
  if (run.data.triangles.empty())
    throw meshfit::Invalid_input(meshfit::Input_location{template_path, 0, meshfit::Input_location::no_offset},
                                 "the template has no face");
}

/// Pins the mesh vertices at the network's vertices and flags the mesh edges along its segments.
Network_match hold_network(const meshfit::Curve_network& network, const Mesh& tm, Edge_flags curve,
                           Vertex_flags pinned) {
  Network_match m;
  m.network_vertices = network.number_of_vertices();
  m.segments = network.number_of_segments();
  std::vector<Mesh::Vertex_index> on(m.network_vertices, Mesh::null_vertex());
  // A vertex of no face (an unused copy) holds no curve: the network is matched to the surface.
  for (auto v : tm.vertices())
    if (const auto nv = tm.is_isolated(v) ? std::nullopt : network.find_vertex(tm.point(v))) {
      if (on[*nv] == Mesh::null_vertex()) ++m.matched_vertices;
      on[*nv] = v;
      pinned[v] = true;
    }
  for (const auto& seg : network.segments()) {
    if (on[seg[0]] == Mesh::null_vertex() || on[seg[1]] == Mesh::null_vertex()) continue;
    const auto h = CGAL::halfedge(on[seg[0]], on[seg[1]], tm);
    if (!h.second) continue;
    curve[tm.edge(h.first)] = true;
    ++m.matched_segments;
  }
  return m;
}

/// Stage 3 on `tm`: the numerical failure's message, or "".
std::string smooth_mesh(Mesh& tm, const Smooth_options& so, Edge_flags curve, Vertex_flags pinned,
                        meshfit::Smoothing_report& r) {
  const meshfit::Progress_callback progress = progress_printer();
  try {
    r = meshfit::smooth_fitted_mesh(tm, meshfit::parameters::mean_curvature_iterations(so.mean_curvature_iterations)
                                            .laplacian_iterations(so.laplacian_iterations)
                                            .step_size(so.step)
                                            .smoothing_tolerance(so.tolerance)
                                            .progress(progress)
                                            .edge_is_constrained_map(curve)
                                            .vertex_is_constrained_map(pinned));
  } catch (const meshfit::Numerical_error& e) {
    return e.what();
  }
  return "";
}

/// The smoothed positions and the curve edges of `tm` in `data` (vertex i of one is vertex i of
/// the other).
void take_smoothed_mesh(const Mesh& tm, Edge_flags curve, meshfit::Mesh_data& data) {
  for (auto v : tm.vertices()) data.points[v.idx()] = tm.point(v);
  data.curve_edges.clear();
  for (auto e : tm.edges())
    if (curve[e]) data.curve_edges.push_back({tm.vertex(e, 0).idx(), tm.vertex(e, 1).idx()});
}

Json smooth_report(const Command_line& cl, const Smooth_options& so, const Smooth_run& run) {
  const meshfit::Smoothing_report& r = run.r;
  const Network_match& m = run.match;
  Json js = report_skeleton("smooth", run.failure, "smooth", run.failure.empty() ? success : algorithm_failed);
  js["timings_s"] = {{"read", number(run.read_seconds)}, {"smooth", number(r.seconds)},
                     {"total", number(progress_display.seconds())}};
  js["counts"] = {{"iterations", r.iterations},
                  {"mean_curvature_iterations", so.mean_curvature_iterations},
                  {"laplacian_iterations", so.laplacian_iterations},
                  {"fixed_vertices", r.fixed_vertices},
                  {"curve_edges", run.curve_edges},
                  {"unflagged_edges_ignored", run.read_report.unflagged_edges_ignored},
                  {"network_vertices", m.network_vertices},
                  {"network_vertices_on_mesh", m.matched_vertices},
                  {"network_segments", m.segments},
                  {"network_segments_on_mesh", m.matched_segments},
                  {"steps_reduced", r.steps_reduced},
                  {"steps_cancelled", r.steps_cancelled},
                  {"clamped_cotangents", r.clamped_cotangents},
                  {"projections_clamped", r.projections_clamped}};
  js["quality"] = json_quality(run.data);
  js["quality"]["minimum_angle_deg_before"] = number(run.min_angle_before);
  js["details"]["displacement"] = {{"mean", number(r.mean_displacement)},
                                   {"max", number(r.max_displacement)},
                                   {"last_iteration_max", number(r.last_step_max_displacement)}};
  if (!run.ignored_edges.empty()) js["warnings"].push_back(run.ignored_edges);
  if (!run.curves_beside.empty()) js["warnings"].push_back("curve edges read from " + run.curves_beside);
  if (m.segments > m.matched_segments)
    js["warnings"].push_back(std::to_string(m.segments - m.matched_segments) + " of " + std::to_string(m.segments) +
                             " network segments are not mesh edges");
  if (run.failure.empty()) note_curve_output(cl, run.data, js);
  return js;
}

/// smooth's lines on stderr after a smoothing that did not fail.
void print_smooth_summary(const Smooth_run& run) {
  const Network_match& m = run.match;
  if (m.segments > m.matched_segments)
    std::cerr << "meshfit: smooth: warning: " << m.segments - m.matched_segments << " of " << m.segments
              << " network segments are not mesh edges (run partition first); their vertices on the mesh are "
                 "still fixed\n";
  std::cerr << "meshfit: smooth: " << run.r.iterations << " iterations, " << run.r.fixed_vertices
            << " vertices fixed, mean displacement " << run.r.mean_displacement << "\n";
}

int run_smooth(const Command_line& cl) {
  const std::string& template_path = cl.values.at("--template");
  std::vector<std::string> inputs{template_path};
  if (cl.values.count("--curves")) inputs.push_back(cl.values.at("--curves"));
  const std::string report_path = check_outputs(cl, inputs);
  apply_thread_limit(cl);
  const Smooth_options so = smooth_options(cl);

  const auto t0 = std::chrono::steady_clock::now();
  Smooth_run run;
  read_smooth_mesh(cl, run);
  Mesh tm;
  auto curve = tm.add_property_map<Mesh::Edge_index, bool>("e:meshfit_curve", false).first;
  // Vertex i of the file is vertex i of tm (build_triangle_mesh keeps the order).
  meshfit::build_triangle_mesh(run.data, tm, CGAL::parameters::edge_is_constrained_map(curve));
  auto pinned = tm.add_property_map<Mesh::Vertex_index, bool>("v:meshfit_pinned", false).first;
  if (cl.values.count("--curves"))
    run.match = hold_network(meshfit::read_curve_network(cl.values.at("--curves"), merge_tolerance(cl)), tm, curve,
                             pinned);
  for (auto e : tm.edges()) run.curve_edges += curve[e];
  run.min_angle_before = meshfit::minimum_angle_degrees(run.data);
  run.read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  run.failure = smooth_mesh(tm, so, curve, pinned, run.r);
  take_smoothed_mesh(tm, curve, run.data);
  // A listed edge without a curve flag (CGAL's write_PLY lists every edge) is not a constraint.
  if (run.read_report.unflagged_edges_ignored != 0)
    run.ignored_edges = std::to_string(run.read_report.unflagged_edges_ignored) + " edges of " + template_path +
                        " carry no curve flag (an integer edge property 'curve'): they are not held as curve edges";
  if (!report_path.empty()) write_report(report_path, smooth_report(cl, so, run));
  progress_display.finish();
  if (!cl.quiet && !run.ignored_edges.empty()) std::cerr << "meshfit: smooth: warning: " << run.ignored_edges << "\n";
  if (!cl.quiet && !run.curves_beside.empty())
    std::cerr << "meshfit: smooth: curve edges read from " << run.curves_beside << "\n";
  if (!run.failure.empty()) throw meshfit::Algorithm_failure("smooth", run.failure);
  if (!cl.quiet) print_smooth_summary(run);
  write_output(cl, run.data, inputs, report_path);
  return success;
}

int run_view(const Command_line& cl) {
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

/// The template's vertex attributes on fit's mesh, which carries them to the vertices it adds
/// (harmonic extension).
struct Attribute_maps {
  Mesh::Property_map<Mesh::Vertex_index, meshfit::Kernel::Point_2> uv;
  Mesh::Property_map<Mesh::Vertex_index, meshfit::Vector_3> normal;
  Mesh::Property_map<Mesh::Vertex_index, CGAL::IO::Color> colour;
};

/// The maps on `tm`, holding the attributes of `td` (vertex i of tm is vertex i of td) when it has any.
Attribute_maps template_attribute_maps(Mesh& tm, const meshfit::Mesh_data& td, bool attributes) {
  Attribute_maps m{tm.add_property_map<Mesh::Vertex_index, meshfit::Kernel::Point_2>("v:meshfit_uv").first,
                   tm.add_property_map<Mesh::Vertex_index, meshfit::Vector_3>("v:meshfit_normal").first,
                   tm.add_property_map<Mesh::Vertex_index, CGAL::IO::Color>("v:meshfit_colour").first};
  if (!attributes) return m;
  std::size_t i = 0;
  for (auto v : tm.vertices()) {
    if (!td.vertex_uvs.empty()) m.uv[v] = {td.vertex_uvs[i][0], td.vertex_uvs[i][1]};
    if (!td.vertex_normals.empty()) m.normal[v] = {td.vertex_normals[i][0], td.vertex_normals[i][1], td.vertex_normals[i][2]};
    if (!td.vertex_colors.empty()) {
      auto byte = [&](int k) { return static_cast<unsigned char>(std::lround(std::clamp(td.vertex_colors[i][k], 0.0, 1.0) * 255)); };
      m.colour[v] = CGAL::IO::Color(byte(0), byte(1), byte(2), byte(3));
    }
    ++i;
  }
  return m;
}

/// Template vertex i is output vertex i and keeps its attributes exactly as read; the vertices
/// fit added take theirs from the maps (colours as bytes).
void take_fitted_attributes(const Mesh& tm, const meshfit::Mesh_data& td, const Attribute_maps& m,
                            meshfit::Mesh_data& out) {
  const std::size_t nt = td.points.size();
  std::size_t i = 0;
  for (auto v : tm.vertices()) {
    if (!td.vertex_uvs.empty())
      out.vertex_uvs.push_back(i < nt ? td.vertex_uvs[i] : std::array<double, 2>{m.uv[v].x(), m.uv[v].y()});
    if (!td.vertex_normals.empty())
      out.vertex_normals.push_back(i < nt ? td.vertex_normals[i]
                                          : std::array<double, 3>{m.normal[v].x(), m.normal[v].y(), m.normal[v].z()});
    if (!td.vertex_colors.empty())
      out.vertex_colors.push_back(i < nt ? td.vertex_colors[i]
                                         : std::array<double, 4>{m.colour[v].r() / 255.0, m.colour[v].g() / 255.0,
                                                                 m.colour[v].b() / 255.0, m.colour[v].a() / 255.0});
    ++i;
  }
}

/// The whole pipeline on the inputs: what went wrong in it, if anything.
Stage_failure fit_inputs(const Command_line& cl, Fit_inputs& in, const meshfit::Deform_options& d,
                         const Smooth_options& so, Edge_flags curve, Mesh::Property_map<Mesh::Face_index, int> region,
                         Attribute_maps* attributes, meshfit::Fit_report& r) {
  Stage_failure failure{"", "fit", {}};
  try {
    const auto np =
        meshfit::deform_parameters(d)
            .mean_curvature_iterations(so.mean_curvature_iterations)
            .laplacian_iterations(so.laplacian_iterations)
            .step_size(so.step)
            .smoothing_tolerance(so.tolerance)
            .check_self_intersections(!cl.no_self_intersection_check)
            .edge_is_constrained_map(curve)
            .face_patch_map(region);
    // Without attributes, no maps: fit would extend them all the same.
    r = attributes ? meshfit::fit_template_to_curves(in.tm, in.network, in.pairs,
                                                     np.vertex_texture_map(attributes->uv)
                                                         .vertex_normal_map(attributes->normal)
                                                         .vertex_color_map(attributes->colour))
                   : meshfit::fit_template_to_curves(in.tm, in.network, in.pairs, np);
  } catch (const meshfit::Numerical_error& e) {
    failure.message = e.what();
    failure.stage = pending_report.stage;
  } catch (const meshfit::Algorithm_failure& e) {
    failure.message = e.what();
    failure.stage = e.stage();
    failure.figures = e.figures();
  }
  return failure;
}

/// The verification's problems in one line.
std::string problem_list(const std::vector<std::string>& problems) {
  std::string list;
  for (std::size_t i = 0; i < problems.size(); ++i) list += (i ? "; " : "") + problems[i];
  return list;
}

Json fit_counts(const meshfit::Fit_report& r) {
  const meshfit::Partition_report& pr = r.partition;
  const meshfit::Smoothing_report& sr = r.smoothing;
  Json counts;
  counts["correspondences"] = r.deformation.user_pairs;
  add_flip_counts(r.deformation, counts);
  add_insertion_counts(r.deformation, counts);
  add_segment_counts(pr, counts);
  counts.update(Json{{"faces_crossed", pr.faces_crossed},
                     {"edge_flips", pr.edge_flips},
                     {"vertices_moved_onto_segments", pr.vertices_moved},
                     {"regions", pr.regions},
                     {"smoothing_iterations", sr.iterations},
                     {"vertices_fixed_in_smoothing", sr.fixed_vertices},
                     {"angle_flips", r.angle_flips},
                     {"chain_vertex_moves", r.chain_vertex_moves}});
  return counts;
}

Json fit_verification(const meshfit::Fit_verification& v, const std::vector<std::string>& problems) {
  return {{"network_vertices_missing", v.network_vertices_missing},
          {"segments_not_chains", v.segments_not_chains},
          {"flips_remaining", v.flips_remaining},
          {"degenerate_faces", v.degenerate_faces},
          {"folded_edges", v.folded_edges},
          {"template_folded_edges", v.template_folded_edges},
          {"self_intersection_checked", v.self_intersection_checked},
          {"self_intersects", v.self_intersects},
          {"template_self_intersects", v.template_self_intersects},
          {"self_intersecting_pairs", v.self_intersecting_pairs},
          {"template_self_intersecting_pairs", v.template_self_intersecting_pairs},
          {"non_finite_coordinates", v.non_finite_coordinates},
          {"regions", v.regions},
          {"expected_regions", v.expected_regions_known ? Json(v.expected_regions) : Json(nullptr)},
          {"problems", problems}};
}

/// `completed`: the pipeline ran to its end (it may have failed verification all the same).
Json fit_report(const Command_line& cl, const meshfit::Fit_report& r, const Stage_failure& failure, bool completed,
                const std::vector<std::string>& problems, double read_seconds, const meshfit::Mesh_data& out) {
  Json js = report_skeleton("fit", failure.message, failure.stage,
                            failure.message.empty() ? success : algorithm_failed, failure.figures);
  js["verified"] = completed && problems.empty();
  js["timings_s"] = {{"read", number(read_seconds)}, {"deform", number(r.deform_seconds)},
                     {"partition", number(r.partition_seconds)}, {"smooth", number(r.smooth_seconds)},
                     {"verify", number(r.verify_seconds)}, {"total", number(r.total_seconds)}};
  js["counts"] = fit_counts(r);
  js["quality"] = {{"template_vertices", r.template_vertices},
                   {"template_faces", r.template_faces},
                   {"vertices", out.points.size()},
                   {"faces", out.triangles.size()},
                   {"minimum_angle_deg", number(completed ? r.minimum_angle_deg : meshfit::minimum_angle_degrees(out))},
                   {"mean_smoothing_displacement", number(r.smoothing.mean_displacement)}};
  js["details"]["fine_level"] = json_fine_level(r.deformation);
  js["details"]["verification"] = fit_verification(r.verification, problems);
  if (completed && !problems.empty())
    for (const std::string& p : problems) js["warnings"].push_back("defect kept (--allow-defects): " + p);
  if (failure.message.empty()) note_curve_output(cl, out, js);
  return js;
}

/// fit's lines on stderr after a run that did not fail.
void print_fit_summary(const meshfit::Fit_report& r, const std::vector<std::string>& problems) {
  const meshfit::Deformation_report& dr = r.deformation;
  const meshfit::Partition_report& pr = r.partition;
  if (!problems.empty())
    std::cerr << "meshfit: fit: warning: defects kept (--allow-defects): " << problem_list(problems) << "\n";
  std::cerr << "meshfit: fit: " << pr.segments << " segments (" << pr.by_walk << " by walk, " << pr.by_fallback
            << " by fallback), " << pr.regions << " regions, " << dr.flips_found << " flips fixed, "
            << r.total_seconds << " s\n";
}

int run_fit(const Command_line& cl) {
  const std::vector<std::string> inputs = fit_input_paths(cl);
  const std::string report_path = check_outputs(cl, inputs);
  apply_thread_limit(cl);
  meshfit::Deform_options d = deform_options(cl);
  d.progress = progress_printer();
  const Smooth_options so = smooth_options(cl);
  Fit_inputs in;
  read_fit_inputs(cl, in);

  auto curve = in.tm.add_property_map<Mesh::Edge_index, bool>("e:meshfit_curve", false).first;
  auto region = in.tm.add_property_map<Mesh::Face_index, int>("f:meshfit_region", 0).first;
  const meshfit::Mesh_data& td = in.template_data;
  const bool attributes = !vertex_attribute_names(td).empty();
  Attribute_maps maps = template_attribute_maps(in.tm, td, attributes);
  meshfit::Fit_report r;
  Stage_failure failure = fit_inputs(cl, in, d, so, curve, region, attributes ? &maps : nullptr, r);
  meshfit::Mesh_data out =
      meshfit::to_mesh_data(in.tm, CGAL::parameters::edge_is_constrained_map(curve).face_patch_map(region));
  if (attributes && failure.message.empty()) take_fitted_attributes(in.tm, td, maps, out);
  const std::vector<std::string> problems = r.verification.problems();
  const bool completed = failure.message.empty();
  if (completed && !problems.empty() && !cl.allow_defects) {
    failure.message = "the result failed verification: " + problem_list(problems);
    // A result turned over, folded or intersecting itself where the fine level left faces turned
    // over or folded: where those are, and what to change.
    const meshfit::Deformation_report& dr = r.deformation;
    if (r.verification.tangled() && dr.fine_level == meshfit::Fine_level::surface &&
        (dr.remaining_flips > 0 || dr.remaining_folds > 0))
      failure.message += "; " + meshfit::remaining_defects_advice(dr);
    failure.message += " (--allow-defects writes it anyway)";
  }

  write_report(report_path, fit_report(cl, r, failure, completed, problems, in.read_seconds, out));
  progress_display.finish();
  if (!failure.message.empty()) throw meshfit::Algorithm_failure("fit", failure.message);
  if (!cl.quiet) print_fit_summary(r, problems);
  write_output(cl, out, inputs, report_path);
  return success;
}

#if defined(__linux__) && defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
// Transparent huge pages for the heap. A fit walks arrays of hundreds of megabytes (sparse
// factors, per-vertex state); in 4 KiB pages every first touch is a page fault and the walks
// miss the TLB. glibc puts its heap in huge pages when the tunable glibc.malloc.hugetlb is 1
// (glibc 2.35 on, where the kernel allows them on request: transparent_hugepage "madvise" or
// "always"), and tunables are read only when a program starts: the command starts itself again
// with the tunable added, once, and the re-started command puts the caller's GLIBC_TUNABLES back
// so that nothing it runs inherits the change. bench/scale (two runs each): 327 680 faces 10.9 s
// -> 9.6 s, 155 000 page faults -> 2 700; 1 310 720 faces 60.2 s -> 46.5 s (user time 64 s ->
// 48 s), peak memory within 0.5 %.
constexpr const char* tunables_before = "MESHFIT_GLIBC_TUNABLES_BEFORE";

void restart_with_huge_pages(char** argv) {
  if (const char* before = std::getenv(tunables_before)) {  // the restarted command
    const std::string was = before;
    if (was.empty()) unsetenv("GLIBC_TUNABLES");
    else setenv("GLIBC_TUNABLES", was.c_str() + 1, 1);
    unsetenv(tunables_before);
    return;
  }
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  if (tunables && std::string(tunables).find("glibc.malloc.hugetlb") != std::string::npos) return;
  std::ifstream thp("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  if (!std::getline(thp, modes) || modes.find("[never]") != std::string::npos) return;
  // "" when there was none, "=" and the value when there was.
  setenv(tunables_before, tunables ? (std::string("=") + tunables).c_str() : "", 1);
  setenv("GLIBC_TUNABLES", tunables ? (std::string(tunables) + ":glibc.malloc.hugetlb=1").c_str() : "glibc.malloc.hugetlb=1", 1);
  execv("/proc/self/exe", argv);
  // Not restarted: go on as before.
  unsetenv(tunables_before);
  if (tunables) setenv("GLIBC_TUNABLES", tunables, 1);
  else unsetenv("GLIBC_TUNABLES");
}
#endif

}  // namespace

int main(int argc, char** argv) {
#if defined(__linux__) && defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
  restart_with_huge_pages(argv);
#endif
#if defined(__GLIBC__)
  // A fit allocates and frees arrays of many megabytes step after step (sparse systems, per-vertex
  // state). glibc serves each from fresh mmap pages and unmaps it when it is freed, so every step
  // pays the kernel to fault its pages in again. Served from the heap and never given back while
  // the command runs, freed memory is reused instead: on the 327 680-face scale case
  // (bench/scale), 336 000 page faults and 3.1-3.7 s of system time in runs of 15.0-17.6 s became
  // 155 000 faults and 1.9-2.2 s in runs of 13.2-14.0 s; peak memory 565 MB -> 630 MB.
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
  try {
    const Parsed parsed = parse(argc, argv);
    if (parsed.exit_now) return success;
    const Command_line& cl = parsed.cl;
    progress_display.start(cl.command, cl.quiet);
    pending_report.command = cl.command;
    if (cl.command == "check") return run_check(cl);
    if (cl.command == "fit") return run_fit(cl);
    if (cl.command == "deform") return run_deform(cl);
    if (cl.command == "partition") return run_partition(cl);
    if (cl.command == "smooth") return run_smooth(cl);
    if (cl.command == "view") return run_view(cl);
    throw Usage_error{"unknown command '" + cl.command + "'"};
  } catch (const Usage_error& e) {
    progress_display.finish();
    std::cerr << "meshfit: " << e.message << "\n";
    // (An option value found wrong after the paths were checked: the report says so too.)
    write_failure_report(e.message, "usage", usage_error);
    return usage_error;
  } catch (const meshfit::Invalid_input& e) {
    progress_display.finish();
    std::cerr << "meshfit: error: " << e.what() << "\n";
    write_failure_report(e.what(), pending_report.stage, invalid_input);
    return invalid_input;
  } catch (const meshfit::Algorithm_failure& e) {
    progress_display.finish();
    std::cerr << "meshfit: failed: " << e.what() << "\n";
    write_failure_report(e.what(), e.stage(), algorithm_failed, e.figures());
    return algorithm_failed;
  } catch (const std::bad_alloc&) {
    progress_display.finish();
    std::cerr << "meshfit: failed: out of memory (in " << pending_report.stage << "; --max-memory bounds the largest allocations)\n";
    write_failure_report("out of memory", pending_report.stage, algorithm_failed);
    return algorithm_failed;
  } catch (const std::exception& e) {
    progress_display.finish();
    std::cerr << "meshfit: failed: " << e.what() << "\n";
    write_failure_report(e.what(), pending_report.stage, algorithm_failed);
    return algorithm_failed;
  }
}
