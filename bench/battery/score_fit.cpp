// Independent scorer for the meshfit stress battery (issue 11, item 5).
//
//   score_fit CASE_DIR OUTPUT_MESH EXIT_STATUS SECONDS STDERR_FILE LABEL
//
// Reads the output mesh of `meshfit fit` with CGAL's own reader and checks it against the case's
// curves, template and ground truth with CGAL alone (no meshfit code; the checks are fit_oracle.h,
// which the tests share): network vertices present, segments embedded as edge chains, regions,
// faces inverted against the truth, new folded edges, new self-intersections, Hausdorff distance
// to the truth, angles. Prints one Markdown table row; exit status 0 when the case passes, 1 when
// it fails, 2 when the scorer itself cannot run.

#include "fit_oracle.h"

#include <CGAL/boost/graph/IO/polygon_mesh_io.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

namespace {

using fit_oracle::Mesh;
using fit_oracle::Tree;

struct Failure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::map<std::string, std::string> read_case(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Failure("cannot read " + path);
  std::map<std::string, std::string> m;
  std::string line;
  while (std::getline(in, line)) {
    const auto sp = line.find(' ');
    if (sp == std::string::npos) continue;
    m[line.substr(0, sp)] = line.substr(sp + 1);
  }
  return m;
}

Mesh read_mesh(const std::string& path) {
  Mesh m;
  if (!CGAL::IO::read_polygon_mesh(path, m) || m.is_empty()) throw Failure("CGAL cannot read " + path);
  if (!CGAL::is_triangle_mesh(m)) throw Failure(path + " is not a triangle mesh");
  return m;
}

std::string fmt(const char* f, double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, x);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 7) {
    std::cerr << "usage: score_fit CASE_DIR OUTPUT_MESH EXIT_STATUS SECONDS STDERR_FILE LABEL\n";
    return 2;
  }
  const std::string dir = argv[1], output = argv[2], label = argv[6];
  const int status = std::atoi(argv[3]);
  const double seconds = std::atof(argv[4]);
  try {
    auto cs = read_case(dir + "/case.txt");
    const bool impossible = cs["impossible"] == "1";
    const bool real = cs["kind"] == "real";
    const long expected = std::stol(cs["expected_regions"]);
    const std::string tfaces = cs["template_faces"], nverts = cs["network_vertices"];
    std::vector<std::string> cols = {label, tfaces, nverts, std::to_string(status), fmt("%.2f", seconds)};
    auto row = [&](const std::vector<std::string>& rest, const std::string& verdict) {
      std::string s = "|";
      for (auto& c : cols) s += " " + c + " |";
      for (auto& c : rest) s += " " + c + " |";
      s += " " + verdict + " |";
      std::cout << s << "\n";
    };
    const std::vector<std::string> none(7, "-");
    if (impossible) {
      std::string msg;
      {
        std::ifstream e(argv[5]);
        std::getline(e, msg, '\0');
      }
      std::vector<std::string> why;
      if (status != 3) why.push_back(status == 124 ? "timeout" : "exit " + std::to_string(status) + " (want 3)");
      if (seconds > 5.0) why.push_back("took > 5 s");
      if (msg.find_first_not_of(" \n\t") == std::string::npos) why.push_back("no message");
      // A list of defects after a full run is not a reason (issue 11, item 4).
      else if (status == 3 && msg.find("verification") != std::string::npos) why.push_back("exit 3 from verification, not a reason");
      std::string verdict = "pass";
      if (!why.empty()) {
        verdict = "FAIL (";
        for (size_t i = 0; i < why.size(); ++i) verdict += (i ? ", " : "") + why[i];
        verdict += ")";
      }
      row(none, verdict);
      return why.empty() ? 0 : 1;
    }
    if (status != 0) {
      row(none, status == 124 ? "FAIL (timeout)" : "FAIL (exit " + std::to_string(status) + ")");
      return 1;
    }
    Mesh out;
    try {
      out = read_mesh(output);
    } catch (const Failure& e) {
      row(none, std::string("FAIL (output: ") + e.what() + ")");
      return 1;
    }
    const Mesh tmpl = read_mesh(dir + "/template.off");
    const Mesh truth = read_mesh(dir + "/truth.off");
    const fit_oracle::Network net = fit_oracle::network_of(fit_oracle::read_polylines(dir + "/curves.polylines.txt"));

    // network vertices at output vertices, segments as chains of output edges, regions, zero-area
    // faces, folds and self-intersections against the template's, angles
    const fit_oracle::Fit_check check = fit_oracle::check_fit(out, tmpl, net);
    const long missing = check.embedding.missing, not_chained = check.embedding.not_chained;
    const long regions = check.embedding.regions, degenerate = check.zero_area_faces;
    const long new_folds = check.new_folds(), new_si = check.new_self_intersections();
    const double amin = check.smallest_angle_deg, a5 = check.angle_5th_percentile_deg;

    // faces inverted against the truth (normal vs the truth face's normal at the closest point)
    Tree tree(faces(truth).first, faces(truth).second, truth);
    tree.accelerate_distance_queries();
    const long inverted = fit_oracle::faces_inverted_against(out, truth, tree);

    // symmetric Hausdorff distance (vertices and face centroids of each against the other)
    CGAL::Bbox_3 tb;
    for (auto v : truth.vertices()) tb += truth.point(v).bbox();
    Tree otree(faces(out).first, faces(out).second, out);
    otree.accelerate_distance_queries();
    const fit_oracle::Squared_hausdorff sq = fit_oracle::squared_hausdorff(out, otree, truth, tree);
    const double h1 = sq.out_to_truth, h2 = sq.truth_to_out;
    const double hausdorff = 100.0 * std::sqrt(std::max(h1, h2)) / fit_oracle::diagonal(tb);
    if (std::getenv("SCORE_FIT_DETAIL"))
      std::cerr << "score_fit: " << label << ": output->truth " << 100.0 * std::sqrt(h1) / fit_oracle::diagonal(tb)
                << " %, truth->output " << 100.0 * std::sqrt(h2) / fit_oracle::diagonal(tb) << " %, template folds "
                << check.template_folded_edges << ", output folds " << check.folded_edges
                << ", template self-intersections " << check.template_self_intersecting_pairs << ", output "
                << check.self_intersecting_pairs << ", zero-area faces " << degenerate << ", output vertices "
                << out.number_of_vertices() << "\n";

    std::vector<std::string> why;
    if (missing) why.push_back(std::to_string(missing) + " vertices missing");
    if (not_chained) why.push_back(std::to_string(not_chained) + " segments not chains");
    if (expected >= 0 && regions != expected) why.push_back("regions");
    if (inverted) why.push_back("inverted");
    if (degenerate) why.push_back(std::to_string(degenerate) + " zero-area faces");
    if (new_folds) why.push_back("folds");
    if (new_si) why.push_back("self-intersections");
    if (hausdorff > (real ? 3.0 : 1.0)) {
      // Every segment is a chain of output edges, so the output is at least as far from the truth
      // as the segments are: when that alone exceeds the bound (curves sampled sparsely across a
      // curved surface), no output can pass, and the row says so.
      double floor2 = 0;
      for (const auto& [a, b] : net.segments)
        for (int k = 0; k <= 8; ++k) {
          const auto p = net.points[std::size_t(a)] + (k / 8.0) * (net.points[std::size_t(b)] - net.points[std::size_t(a)]);
          floor2 = std::max(floor2, tree.squared_distance(p));
        }
      const double floor = 100.0 * std::sqrt(floor2) / fit_oracle::diagonal(tb);
      why.push_back(floor > (real ? 3.0 : 1.0) ? "Hausdorff: the segments alone are " + fmt("%.2f", floor) + " %"
                                               : "Hausdorff");
    }
    if (amin < 1.0) why.push_back("min angle");
    std::string verdict = "pass";
    if (!why.empty()) {
      verdict = "FAIL (";
      for (size_t i = 0; i < why.size(); ++i) verdict += (i ? ", " : "") + why[i];
      verdict += ")";
    }
    row({std::to_string(regions) + "/" + (expected >= 0 ? std::to_string(expected) : std::string("-")),
         std::to_string(inverted), std::to_string(new_folds), std::to_string(new_si), fmt("%.3f", hausdorff),
         fmt("%.2f", amin), fmt("%.1f", a5)},
        verdict);
    return why.empty() ? 0 : 1;
  } catch (const std::exception& e) {
    std::cout << "| " << label << " | - | - | " << status << " | " << fmt("%.2f", seconds)
              << " | - | - | - | - | - | - | - | FAIL (scorer: " << e.what() << ") |\n";
    return 2;
  }
}
