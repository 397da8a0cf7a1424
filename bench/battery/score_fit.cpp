// Independent scorer for the meshfit stress battery (issue 11, item 5).
//
//   score_fit CASE_DIR OUTPUT_MESH EXIT_STATUS SECONDS STDERR_FILE LABEL
//
// Reads the output mesh of `meshfit fit` with CGAL's own reader and checks it against the case's
// curves, template and ground truth with CGAL alone (no meshfit code): network vertices present,
// segments embedded as edge chains, regions, faces inverted against the truth, new folded edges,
// new self-intersections, Hausdorff distance to the truth, angles. Prints one Markdown table row;
// exit status 0 when the case passes, 1 when it fails, 2 when the scorer itself cannot run.

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using P = K::Point_3;
using V3 = K::Vector_3;
using Mesh = CGAL::Surface_mesh<P>;
using vd = Mesh::Vertex_index;
using fd = Mesh::Face_index;
using hd = Mesh::Halfedge_index;
using ed = Mesh::Edge_index;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
namespace PMP = CGAL::Polygon_mesh_processing;

constexpr double pi = 3.14159265358979323846;

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

std::vector<std::vector<P>> read_polylines(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Failure("cannot read " + path);
  std::vector<std::vector<P>> out;
  std::string line;
  while (std::getline(in, line)) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream is(line);
    size_t n = 0;
    is >> n;
    std::vector<P> pl;
    for (size_t i = 0; i < n; ++i) {
      double x, y, z;
      if (!(is >> x >> y >> z)) throw Failure(path + ": short polyline");
      pl.emplace_back(x, y, z);
    }
    out.push_back(pl);
  }
  return out;
}

double diagonal(const CGAL::Bbox_3& b) {
  return std::sqrt(CGAL::square(b.xmax() - b.xmin()) + CGAL::square(b.ymax() - b.ymin()) +
                   CGAL::square(b.zmax() - b.zmin()));
}

// Points merged within `tol` (a uniform grid of cell `tol`, 27 neighbouring cells searched).
struct Point_index {
  double cell;
  std::map<std::array<long long, 3>, std::vector<int>> grid;
  std::vector<P> pts;
  explicit Point_index(double c) : cell(c) {}
  std::array<long long, 3> key(const P& p) const {
    return {(long long)std::floor(p.x() / cell), (long long)std::floor(p.y() / cell), (long long)std::floor(p.z() / cell)};
  }
  int find(const P& p, double tol) const {
    const auto k = key(p);
    int best = -1;
    double bd = tol * tol;
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          auto it = grid.find({k[0] + dx, k[1] + dy, k[2] + dz});
          if (it == grid.end()) continue;
          for (int i : it->second) {
            const double d = CGAL::squared_distance(pts[i], p);
            if (d <= bd) { bd = d; best = i; }
          }
        }
    return best;
  }
  int insert(const P& p) {
    pts.push_back(p);
    grid[key(p)].push_back(int(pts.size()) - 1);
    return int(pts.size()) - 1;
  }
};

V3 face_normal(const Mesh& m, fd f) {
  const hd h = m.halfedge(f);
  const P& a = m.point(m.source(h));
  const P& b = m.point(m.target(h));
  const P& c = m.point(m.target(m.next(h)));
  return CGAL::cross_product(b - a, c - a);
}

long folded_edges(const Mesh& m) {
  long n = 0;
  for (ed e : m.edges()) {
    if (m.is_border(e)) continue;
    const hd h = m.halfedge(e);
    if (face_normal(m, m.face(h)) * face_normal(m, m.face(m.opposite(h))) < 0) ++n;
  }
  return n;
}

long self_intersections(const Mesh& m) {
  std::vector<std::pair<fd, fd>> pairs;
  PMP::self_intersections(m, std::back_inserter(pairs));
  return long(pairs.size());
}

struct Union_find {
  std::vector<int> p;
  explicit Union_find(size_t n) : p(n) { for (size_t i = 0; i < n; ++i) p[i] = int(i); }
  int find(int x) { while (p[x] != x) x = p[x] = p[p[x]]; return x; }
  void unite(int a, int b) { p[find(a)] = find(b); }
};

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
    const auto curves = read_polylines(dir + "/curves.polylines.txt");

    // network vertices, merged within 1e-9 x the network's bounding-box diagonal
    CGAL::Bbox_3 nb;
    for (auto& pl : curves)
      for (auto& p : pl) nb += p.bbox();
    const double ndiag = diagonal(nb);
    const double tol = 1e-9 * ndiag;
    Point_index net(std::max(tol, 1e-300));
    std::set<std::pair<int, int>> segments;
    for (auto& pl : curves) {
      int prev = -1;
      for (auto& p : pl) {
        int id = net.find(p, tol);
        if (id < 0) id = net.insert(p);
        if (prev >= 0 && prev != id) segments.emplace(std::min(prev, id), std::max(prev, id));
        prev = id;
      }
    }
    // every network vertex at an output vertex
    Point_index outpts(std::max(tol, 1e-300));
    for (vd v : out.vertices()) outpts.insert(out.point(v));  // index == vertex index
    std::vector<int> at(net.pts.size(), -1);
    long missing = 0;
    for (size_t i = 0; i < net.pts.size(); ++i) {
      at[i] = outpts.find(net.pts[i], tol);
      if (at[i] < 0) ++missing;
    }
    // every segment a chain of output edges on the segment, monotone from a to b
    std::vector<char> cut(out.number_of_edges(), 0);
    long not_chained = 0;
    for (auto [ia, ib] : segments) {
      if (at[ia] < 0 || at[ib] < 0) { ++not_chained; continue; }
      const P a = net.pts[ia], b = net.pts[ib];
      const V3 ab = b - a;
      const double l2 = ab.squared_length(), l = std::sqrt(l2);
      const double line_tol = 1e-6 * l + 1e-9 * ndiag;
      vd cur = vd(unsigned(at[ia]));
      const vd goal = vd(unsigned(at[ib]));
      double tcur = 0;
      std::vector<ed> chain;
      bool ok = true;
      while (cur != goal) {
        hd best;
        double bt = 1e300;
        for (hd h : CGAL::halfedges_around_source(cur, out)) {
          const P& w = out.point(out.target(h));
          const double t = ((w - a) * ab) / l2;
          if (t <= tcur || t > 1 + 1e-9) continue;
          if (std::sqrt(CGAL::squared_distance(w, a + t * ab)) > line_tol) continue;
          if (t < bt) { bt = t; best = h; }
        }
        if (bt == 1e300) { ok = false; break; }
        chain.push_back(out.edge(best));
        cur = out.target(best);
        tcur = bt;
      }
      if (!ok) { ++not_chained; continue; }
      for (ed e : chain) cut[e.idx()] = 1;
    }
    // regions: faces connected across edges that are not chain edges
    Union_find uf(out.number_of_faces());
    for (ed e : out.edges()) {
      if (out.is_border(e) || cut[e.idx()]) continue;
      const hd h = out.halfedge(e);
      uf.unite(int(out.face(h).idx()), int(out.face(out.opposite(h)).idx()));
    }
    std::set<int> roots;
    for (fd f : out.faces()) roots.insert(uf.find(int(f.idx())));
    const long regions = long(roots.size());

    // faces inverted against the truth (normal vs the truth face's normal at the closest point)
    Tree tree(faces(truth).first, faces(truth).second, truth);
    tree.accelerate_distance_queries();
    long inverted = 0, degenerate = 0;
    for (fd f : out.faces()) {
      const V3 n = face_normal(out, f);
      if (n.squared_length() == 0) { ++degenerate; continue; }
      const hd h = out.halfedge(f);
      const P c = CGAL::centroid(out.point(out.source(h)), out.point(out.target(h)), out.point(out.target(out.next(h))));
      const auto cp = tree.closest_point_and_primitive(c);
      if (face_normal(truth, cp.second) * n < 0) ++inverted;
    }
    // folds and self-intersections, output against template
    const long folds_out = folded_edges(out), folds_tmpl = folded_edges(tmpl);
    const long si_out = self_intersections(out), si_tmpl = self_intersections(tmpl);
    const long new_folds = std::max(0L, folds_out - folds_tmpl), new_si = std::max(0L, si_out - si_tmpl);

    // symmetric Hausdorff distance (vertices and face centroids of each against the other)
    CGAL::Bbox_3 tb;
    for (vd v : truth.vertices()) tb += truth.point(v).bbox();
    double h1 = 0, h2 = 0;
    for (vd v : out.vertices()) h1 = std::max(h1, tree.squared_distance(out.point(v)));
    for (fd f : out.faces()) {
      const hd h = out.halfedge(f);
      h1 = std::max(h1, tree.squared_distance(CGAL::centroid(out.point(out.source(h)), out.point(out.target(h)),
                                                               out.point(out.target(out.next(h))))));
    }
    Tree otree(faces(out).first, faces(out).second, out);
    otree.accelerate_distance_queries();
    for (vd v : truth.vertices()) h2 = std::max(h2, otree.squared_distance(truth.point(v)));
    const double hausdorff = 100.0 * std::sqrt(std::max(h1, h2)) / diagonal(tb);
    if (std::getenv("SCORE_FIT_DETAIL"))
      std::cerr << "score_fit: " << label << ": output->truth " << 100.0 * std::sqrt(h1) / diagonal(tb)
                << " %, truth->output " << 100.0 * std::sqrt(h2) / diagonal(tb) << " %, template folds " << folds_tmpl
                << ", output folds " << folds_out << ", template self-intersections " << si_tmpl << ", output "
                << si_out << ", zero-area faces " << degenerate << ", output vertices " << out.number_of_vertices()
                << "\n";

    // angles
    std::vector<double> angles;
    for (fd f : out.faces()) {
      const hd h = out.halfedge(f);
      const P p[3] = {out.point(out.source(h)), out.point(out.target(h)), out.point(out.target(out.next(h)))};
      for (int k = 0; k < 3; ++k) {
        const V3 u = p[(k + 1) % 3] - p[k], w = p[(k + 2) % 3] - p[k];
        const double lu = std::sqrt(u.squared_length()), lw = std::sqrt(w.squared_length());
        angles.push_back(lu == 0 || lw == 0 ? 0.0 : std::acos(std::clamp((u * w) / (lu * lw), -1.0, 1.0)) * 180 / pi);
      }
    }
    std::sort(angles.begin(), angles.end());
    const double amin = angles.empty() ? 0 : angles.front();
    const double a5 = angles.empty() ? 0 : angles[angles.size() / 20];

    std::vector<std::string> why;
    if (missing) why.push_back(std::to_string(missing) + " vertices missing");
    if (not_chained) why.push_back(std::to_string(not_chained) + " segments not chains");
    if (expected >= 0 && regions != expected) why.push_back("regions");
    if (inverted) why.push_back("inverted");
    if (degenerate) why.push_back(std::to_string(degenerate) + " zero-area faces");
    if (new_folds) why.push_back("folds");
    if (new_si) why.push_back("self-intersections");
    if (hausdorff > (real ? 3.0 : 1.0)) why.push_back("Hausdorff");
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
