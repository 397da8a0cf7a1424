// make_more_example_data.cpp -- generates the further example inputs of meshfit.
//
// Usage: make_more_example_data <data_dir> [<elephant.off>]
//
// <data_dir> is examples/data; it must already hold template.off (written by make_example_data).
// Writes, deterministically:
//   <data_dir>/curves-2.polylines.txt, <data_dir>/pairs-2.txt
//        a second curve network for the same icosphere template: a "peanut" (a surface of
//        revolution about x with a waist, elliptic cross sections), 2 meridians + 3 cross sections;
//   <data_dir>/sheet/template.off, curves.polylines.txt, pairs.txt
//        an open template (a 40 x 40 grid in z = 0 over [0,1]^2) and a saddle-shaped patch over a
//        deformed square: its 4 boundary curves plus 2 inner curves crossing in the middle;
//   <data_dir>/elephant/curves.polylines.txt, pairs.txt   (only with <elephant.off>)
//        CGAL's sample mesh data/meshes/elephant.off (Debian libcgal-demo, data.tar.gz) is the
//        template; the curves are closed edge loops of a smoothly deformed copy of it, keeping every
//        2nd vertex, and the pairs map template vertices to their own deformed positions.
// It uses only the standard library, like make_example_data. Every self-check failure exits
// non-zero with a message. See examples/data/README.md.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "example_data_common.h"

namespace {

using namespace example_data;

// Minimal OFF reader: triangles only, '#' comments skipped.
Mesh read_off(const std::filesystem::path& path) {
  std::ifstream in(path);
  require(static_cast<bool>(in), "cannot read " + path.string());
  std::string text, line;
  while (std::getline(in, line)) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    text += line + '\n';
  }
  std::istringstream s(text);
  std::string header;
  std::size_t nv = 0, nf = 0, ne = 0;
  s >> header >> nv >> nf >> ne;
  require(header == "OFF" && s, path.string() + ": not an OFF file");
  Mesh m;
  m.vertices.resize(nv);
  for (Vec& v : m.vertices) s >> v[0] >> v[1] >> v[2];
  for (std::size_t f = 0; f < nf; ++f) {
    int k = 0;
    std::array<int, 3> t{};
    s >> k >> t[0] >> t[1] >> t[2];
    require(k == 3, path.string() + ": only triangle faces are supported");
    m.faces.push_back(t);
  }
  require(static_cast<bool>(s), path.string() + ": truncated OFF file");
  return m;
}

std::string off_text(const Mesh& m) {
  std::ostringstream off;
  off << "OFF\n" << m.vertices.size() << ' ' << m.faces.size() << " 0\n";
  for (const Vec& v : m.vertices) off << fmt(v) << '\n';
  for (const auto& f : m.faces) off << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  return off.str();
}

std::string polyline_text(const std::vector<Vec>& line) {
  std::string s = std::to_string(line.size());
  for (const Vec& p : line) s += ' ' + fmt(p);
  return s + '\n';
}

// Counts how many polylines use each point (by its text) and checks that exactly the expected
// points are shared; returns the number of distinct points.
std::size_t check_sharing(const std::vector<std::vector<Vec>>& lines, const std::vector<Vec>& shared,
                          bool closed) {
  std::map<std::string, int> uses;
  for (const auto& line : lines) {
    std::set<std::string> in_line;
    for (std::size_t k = 0; k + (closed ? 1 : 0) < line.size(); ++k) {
      require(in_line.insert(fmt(line[k])).second, "a polyline passes twice through " + fmt(line[k]));
      ++uses[fmt(line[k])];
    }
  }
  std::set<std::string> expected;
  for (const Vec& p : shared) expected.insert(fmt(p));
  for (const auto& [p, n] : uses)
    require((n > 1) == (expected.count(p) == 1), "point " + p + " is shared unexpectedly or not shared");
  return uses.size();
}

// ---- a closed curve sampled at roughly uniform arc length -----------------------------------------

struct CurvePoint {
  double t;
  Vec p;
};

// c(t), t in [0, 2 pi), a closed curve; features are given with their parameters and inserted
// exactly (the same doubles go into every curve through them); samples too close to a feature
// are dropped. Returns a closed polyline (first point repeated).
std::vector<Vec> sample_closed(const std::function<Vec(double)>& c, const std::vector<CurvePoint>& features,
                               double target_spacing) {
  const int fine = 20000;
  std::vector<double> arc(fine + 1, 0.0);
  for (int k = 1; k <= fine; ++k)
    arc[k] = arc[k - 1] + norm(c(2.0 * kPi * k / fine) - c(2.0 * kPi * (k - 1) / fine));
  const int count = std::max(12, static_cast<int>(std::lround(arc[fine] / target_spacing)));
  const double spacing = arc[fine] / count;
  std::vector<CurvePoint> pts = features;
  for (int i = 0, k = 0; i < count; ++i) {
    const double target = i * spacing;
    while (arc[k + 1] < target) ++k;
    const double t = 2.0 * kPi * (k + (target - arc[k]) / (arc[k + 1] - arc[k])) / fine;
    const Vec p = c(t);
    const bool near_feature = std::any_of(features.begin(), features.end(),
                                          [&](const CurvePoint& f) { return norm(f.p - p) < 0.4 * spacing; });
    if (!near_feature) pts.push_back({t, p});
  }
  std::sort(pts.begin(), pts.end(), [](const CurvePoint& a, const CurvePoint& b) { return a.t < b.t; });
  std::vector<Vec> out;
  for (const CurvePoint& q : pts) out.push_back(q.p);
  out.push_back(out.front());
  return out;
}

int nearest_vertex(const Mesh& m, const Vec& dir) {
  int best = 0;
  for (int i = 1; i < static_cast<int>(m.vertices.size()); ++i)
    if (dot(m.vertices[i], dir) > dot(m.vertices[best], dir)) best = i;
  return best;
}

// ---- 1. peanut: a second network for the icosphere ------------------------------------------------

// Surface of revolution about x with elliptic cross sections:
//   (x, kB rho(x) cos phi, kC rho(x) sin phi),  rho(x) = sqrt(1 - (x/kL)^2) g(x),
//   g(x) = (1 + 0.15 x/kL) (1 - 0.3 exp(-(x/0.7)^2))    (a waist at x = 0, the +x lobe bigger).
constexpr double kL = 2.0, kB = 0.9, kC = 0.75;
double g(double x) { return (1.0 + 0.15 * x / kL) * (1.0 - 0.3 * std::exp(-(x / 0.7) * (x / 0.7))); }
double rho(double x) { return std::sqrt(std::max(0.0, 1.0 - (x / kL) * (x / kL))) * g(x); }

// The natural peanut-to-sphere map (x/L, y/(B g), z/(C g)), normalised.
Vec peanut_direction(const Vec& p) { return normalized(Vec{p[0] / kL, p[1] / (kB * g(p[0])), p[2] / (kC * g(p[0]))}); }

void make_peanut(const std::filesystem::path& dir) {
  const Mesh sphere = read_off(dir / "template.off");
  require(sphere.vertices.size() == 2562, "template.off is not the 2562-vertex icosphere");
  const std::vector<double> cuts{-1.1, 0.0, 1.1};
  // Meridian in the plane y = 0 (axis 2) or z = 0 (axis 1): theta in [0, 2 pi), x = L cos theta.
  auto meridian = [](int axis) {
    return [axis](double t) {
      const double x = kL * std::cos(t);
      Vec p{x, 0.0, 0.0};
      p[axis] = (axis == 1 ? kB : kC) * std::sin(t) * g(x);
      return p;
    };
  };
  const Vec tip_plus{kL, 0, 0}, tip_minus{-kL, 0, 0};
  std::vector<Vec> features{tip_plus, tip_minus};
  std::vector<std::vector<CurvePoint>> on(2 + cuts.size());
  for (int m = 0; m < 2; ++m) {
    on[m].push_back({0.0, tip_plus});
    on[m].push_back({kPi, tip_minus});
  }
  for (std::size_t i = 0; i < cuts.size(); ++i) {
    const double x = cuts[i], r = rho(x), th = std::acos(x / kL);
    // Cross section i: phi = 0, pi/2, pi, 3pi/2 meet the z = 0 meridian (m = 0) and the y = 0 one (m = 1).
    const Vec py{x, kB * r, 0}, my{x, -kB * r, 0}, pz{x, 0, kC * r}, mz{x, 0, -kC * r};
    for (const Vec& p : {py, my, pz, mz}) features.push_back(p);
    on[0].push_back({th, py});
    on[0].push_back({2 * kPi - th, my});
    on[1].push_back({th, pz});
    on[1].push_back({2 * kPi - th, mz});
    on[2 + i] = {{0.0, py}, {0.5 * kPi, pz}, {kPi, my}, {1.5 * kPi, mz}};
  }
  std::vector<std::vector<Vec>> lines;
  lines.push_back(sample_closed(meridian(1), on[0], 0.15));
  lines.push_back(sample_closed(meridian(2), on[1], 0.15));
  for (std::size_t i = 0; i < cuts.size(); ++i) {
    const double x = cuts[i], r = rho(x);
    lines.push_back(sample_closed([x, r](double t) { return Vec{x, kB * r * std::cos(t), kC * r * std::sin(t)}; },
                                  on[2 + i], 0.15));
  }
  // On the surface: (y/(B rho))^2 + (z/(C rho))^2 = 1.
  for (const auto& line : lines)
    for (const Vec& p : line) {
      const double r = rho(p[0]);
      if (r == 0.0) continue;
      const double f = (p[1] / (kB * r)) * (p[1] / (kB * r)) + (p[2] / (kC * r)) * (p[2] / (kC * r));
      require(std::abs(f - 1.0) < 1e-9, "peanut point off the surface");
    }
  const std::size_t points = check_sharing(lines, features, true);

  std::ostringstream curves;
  curves << "# meshfit example curve network 2: a peanut (x, 0.9 rho(x) cos t, 0.75 rho(x) sin t),\n"
         << "# rho(x) = sqrt(1 - (x/2)^2) (1 + 0.075 x) (1 - 0.3 exp(-(x/0.7)^2)), x in [-2, 2]\n"
         << "# in this order: meridian z=0, meridian y=0, cross sections x=-1.1, x=0 (waist), x=1.1\n"
         << "# closed polylines sharing their " << features.size() << " intersection points bitwise\n";
  for (const auto& line : lines) curves << polyline_text(line);

  // Pairs: every feature point, template vertex nearest to its image under the natural map.
  std::ostringstream pairs;
  pairs << "# template_vertex_index x y z (a point of curves-2.polylines.txt, same text); the " << features.size()
        << " feature points,\n# each with the icosphere vertex nearest to normalised (x/2, y/(0.9 g(x)), z/(0.75 g(x)))\n";
  std::set<int> used;
  for (const Vec& p : features) {
    const int v = nearest_vertex(sphere, peanut_direction(p));
    require(used.insert(v).second, "two pairs map to the same template vertex");
    pairs << v << ' ' << fmt(p) << '\n';
  }
  write_file(dir / "curves-2.polylines.txt", curves.str());
  write_file(dir / "pairs-2.txt", pairs.str());
  std::cout << "peanut: " << lines.size() << " polylines, " << points << " network points, " << features.size()
            << " feature points, " << features.size() << " pairs\n";
}

// ---- 2. sheet: an open template and a network including its boundary ------------------------------

constexpr int kGrid = 40;   // template squares per side
constexpr int kBoundarySteps = 40;  // boundary curve points per side: one per template boundary vertex
constexpr int kInnerSteps = 20;     // inner curve points (spacing 1/20 in parameter space)

// The target patch over a deformed square, a saddle: S(u, v), (u, v) in [0,1]^2.
Vec patch(double u, double v) {
  return {1.1 * u + 0.1 * std::sin(kPi * v), 0.9 * v - 0.08 * std::sin(kPi * u),
          0.8 * (u - 0.5) * (u - 0.5) - 0.8 * (v - 0.5) * (v - 0.5)};
}

void make_sheet(const std::filesystem::path& dir) {
  Mesh grid;
  const int n = kGrid + 1;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) grid.vertices.push_back({double(i) / kGrid, double(j) / kGrid, 0.0});
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
      // Counter-clockwise seen from +z; the diagonal alternates so the grid has no preferred direction.
      if ((i + j) % 2 == 0) {
        grid.faces.push_back({a, b, c});
        grid.faces.push_back({a, c, d});
      } else {
        grid.faces.push_back({a, b, d});
        grid.faces.push_back({b, c, d});
      }
    }
  // Curves: u = 0, u = 1, v = 0, v = 1 (the boundary, corner to corner), u = 1/2 and v = 1/2 (inner,
  // boundary to boundary). Points are S at parameters k / 40 (boundary) or k / 20 (inner), so shared points are bitwise equal.
  auto line_u = [](double u, int steps) {  // u fixed, v from 0 to 1
    std::vector<Vec> l;
    for (int k = 0; k <= steps; ++k) l.push_back(patch(u, double(k) / steps));
    return l;
  };
  auto line_v = [](double v, int steps) {
    std::vector<Vec> l;
    for (int k = 0; k <= steps; ++k) l.push_back(patch(double(k) / steps, v));
    return l;
  };
  const std::vector<std::vector<Vec>> lines{line_v(0.0, kBoundarySteps), line_u(1.0, kBoundarySteps),
                                            line_v(1.0, kBoundarySteps), line_u(0.0, kBoundarySteps),
                                            line_u(0.5, kInnerSteps),    line_v(0.5, kInnerSteps)};
  const std::vector<Vec> shared{patch(0, 0), patch(1, 0), patch(0, 1), patch(1, 1), patch(0.5, 0),
                                patch(0.5, 1), patch(0, 0.5), patch(1, 0.5), patch(0.5, 0.5)};
  const std::size_t points = check_sharing(lines, shared, false);
  std::ostringstream curves;
  curves << "# meshfit example: a saddle patch S(u,v) = (1.1u + 0.1 sin(pi v), 0.9v - 0.08 sin(pi u), "
            "0.8(u-1/2)^2 - 0.8(v-1/2)^2)\n"
         << "# open polylines: v=0, u=1, v=1, u=0 (the boundary, parameters k/40), u=1/2, v=1/2 (inner, parameters k/20)\n";
  for (const auto& line : lines) curves << polyline_text(line);
  // Pairs: the 9 shared points, template vertex (i, j) <-> S(i/40, j/40).
  std::ostringstream pairs;
  pairs << "# template_vertex_index x y z; grid vertex (i, j) = index 41 j + i at (i/40, j/40, 0) <-> S(i/40, j/40):\n"
        << "# the 4 corners, the 4 boundary midpoints and the centre\n";
  for (const auto& [i, j] : std::vector<std::pair<int, int>>{{0, 0}, {40, 0}, {0, 40}, {40, 40}, {20, 0}, {20, 40}, {0, 20}, {40, 20}, {20, 20}})
    pairs << j * n + i << ' ' << fmt(patch(double(i) / kGrid, double(j) / kGrid)) << '\n';
  write_file(dir / "template.off", off_text(grid));
  write_file(dir / "curves.polylines.txt", curves.str());
  write_file(dir / "pairs.txt", pairs.str());
  std::cout << "sheet: template " << grid.vertices.size() << " vertices " << grid.faces.size() << " faces; "
            << lines.size() << " polylines, " << points << " network points, 9 pairs\n";
}

// ---- 3. elephant: a CGAL sample mesh fitted to curves from a deformed copy of itself --------------

// A smooth deformation: anisotropic scale, then a twist about the y axis (up to +-0.2 rad at the
// ends of the y range [-0.5, 0.5]), then a bend (a parabola in x lifts y).
Vec deform(const Vec& p) {
  const Vec q{1.15 * p[0], 0.95 * p[1], 1.1 * p[2]};
  const double a = 0.4 * q[1], c = std::cos(a), s = std::sin(a);
  return {c * q[0] + s * q[2], q[1] + 0.6 * q[0] * q[0], -s * q[0] + c * q[2]};
}

// The closed edge cycles bounding the set of faces whose centroid is on the positive side of the
// plane n.x = d; each cycle is a list of vertex indices, oriented like the faces inside. A cycle
// through a vertex twice (two boundary edges leave it) is dropped and counted in `non_simple`.
std::vector<std::vector<int>> plane_cycles(const Mesh& m, const Vec& n, double d, int& non_simple) {
  std::map<std::pair<int, int>, int> face_of;  // directed edge -> face
  for (int f = 0; f < static_cast<int>(m.faces.size()); ++f)
    for (int k = 0; k < 3; ++k) face_of[{m.faces[f][k], m.faces[f][(k + 1) % 3]}] = f;
  auto positive = [&](int f) {
    const auto& t = m.faces[f];
    const Vec c = (1.0 / 3.0) * (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]);
    return dot(n, c) > d;
  };
  std::map<int, std::vector<int>> next;  // boundary edges leaving each vertex
  for (const auto& [e, f] : face_of) {
    auto twin = face_of.find({e.second, e.first});
    require(twin != face_of.end(), "the mesh has a border edge");
    if (positive(f) && !positive(twin->second)) next[e.first].push_back(e.second);
  }
  std::set<int> bad;
  for (const auto& [v, out] : next)
    if (out.size() != 1) bad.insert(v);
  std::set<int> seen;
  std::vector<std::vector<int>> cycles;
  non_simple = 0;
  for (const auto& [start, out] : next) {
    if (seen.count(start)) continue;
    std::vector<int> cycle;
    bool simple = true;
    int v = start;
    do {
      if (!seen.insert(v).second) { simple = false; break; }
      cycle.push_back(v);
      if (bad.count(v)) simple = false;
      v = next[v].front();
    } while (v != start);
    if (simple) cycles.push_back(cycle);
    else ++non_simple;
  }
  return cycles;
}

}  // namespace

int elephant_main(const std::filesystem::path& mesh, const std::filesystem::path& dir);

int main(int argc, char** argv) {
  if (argc != 2 && argc != 3) {
    std::cerr << "usage: make_more_example_data <data_dir> [<elephant.off>]\n";
    return 2;
  }
  try {
    const std::filesystem::path dir = argv[1];
    make_peanut(dir);
    make_sheet(dir / "sheet");
    if (argc == 3) return elephant_main(argv[2], dir / "elephant");
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "make_more_example_data: " << e.what() << '\n';
    return 1;
  }
}

struct Cut {
  const char* name;
  int axis;     // plane x[axis] = d, in the deformed copy
  double d;
};

int elephant_main(const std::filesystem::path& path, const std::filesystem::path& dir) {
  const Mesh original = read_off(path);
  require(original.vertices.size() == 2775 && original.faces.size() == 5558,
          path.string() + " is not CGAL's data/meshes/elephant.off (2775 vertices, 5558 faces)");
  Mesh m = original;
  for (Vec& v : m.vertices) v = deform(v);
  // Chosen by trying offsets: many nearby planes give loops that share a mesh edge with the
  // sagittal loop (refused below), and cross sections at x = 0.1 gave a segment that partition
  // could not embed (see examples/data/README.md).
  const std::vector<Cut> cuts{
      {"sagittal z=0.069", 2, 0.069},
      {"cross section x=-0.21", 0, -0.21},
      {"cross section x=-0.045", 0, -0.045},
      {"cross section x=0.3", 0, 0.3},
  };
  std::vector<std::vector<int>> loops;
  for (const Cut& c : cuts) {
    Vec n{0, 0, 0};
    n[c.axis] = 1;
    int non_simple = 0;
    auto cycles = plane_cycles(m, n, c.d, non_simple);
    require(!cycles.empty(), std::string(c.name) + ": no simple cycle");
    // The longest cycle, ties broken by the smallest vertex index (deterministic).
    auto best = std::max_element(cycles.begin(), cycles.end(), [](const auto& a, const auto& b) {
      return a.size() != b.size() ? a.size() < b.size() : *std::min_element(a.begin(), a.end()) > *std::min_element(b.begin(), b.end());
    });
    loops.push_back(*best);
  }
  // Crossings: vertices shared by two loops; loops must share no edge.
  std::map<int, int> loops_through;
  std::set<std::pair<int, int>> edges;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    for (int v : loops[i]) ++loops_through[v];
    for (std::size_t k = 0; k < loops[i].size(); ++k) {
      const auto e = std::minmax(loops[i][k], loops[i][(k + 1) % loops[i].size()]);
      require(edges.insert(e).second, std::string(cuts[i].name) + " shares an edge with an earlier loop");
    }
  }
  std::vector<int> features;
  for (const auto& [v, n] : loops_through) {
    require(n <= 2, "three loops through one vertex");
    if (n == 2) features.push_back(v);
  }
  // Subsample: keep the crossings, and between them every 2nd vertex (a loop without crossings
  // starts at its smallest vertex index). Segments then span 1 or 2 mesh edges.
  std::vector<std::vector<int>> kept_loops;
  for (const auto& loop : loops) {
    const std::size_t n = loop.size();
    std::size_t start = std::min_element(loop.begin(), loop.end()) - loop.begin();
    for (std::size_t k = 0; k < n; ++k)
      if (loops_through[loop[k]] == 2) { start = k; break; }
    std::vector<int> kept;
    std::size_t since = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const int v = loop[(start + k) % n];
      const bool mandatory = loops_through[v] == 2 || k == 0;
      const int next = loop[(start + k + 1) % n];
      // keep every 2nd vertex, but never the one just before a mandatory vertex (its segment would be short)
      if (mandatory || (since >= 1 && loops_through[next] != 2 && k + 1 != n)) {
        kept.push_back(v);
        since = 0;
      } else {
        ++since;
      }
    }
    kept.push_back(kept.front());
    kept_loops.push_back(kept);
  }
  std::vector<std::vector<Vec>> lines;
  std::set<int> kept_vertices;
  for (const auto& kl : kept_loops) {
    std::vector<Vec> line;
    for (int v : kl) line.push_back(m.vertices[v]);
    for (std::size_t k = 0; k + 1 < kl.size(); ++k) kept_vertices.insert(kl[k]);
    lines.push_back(line);
  }
  std::vector<Vec> shared;
  for (int v : features) shared.push_back(m.vertices[v]);
  const std::size_t points = check_sharing(lines, shared, true);
  require(points == kept_vertices.size(), "two kept vertices have the same deformed position");

  // Pairs: farthest-point choice among the kept vertices (deformed positions), starting with the
  // kept vertex of largest deformed x.
  std::vector<int> chosen;
  std::vector<int> pool(kept_vertices.begin(), kept_vertices.end());
  const std::size_t pair_count = 12;
  while (chosen.size() < pair_count) {
    auto score = [&](int v) {
      double s = chosen.empty() ? m.vertices[v][0] : std::numeric_limits<double>::infinity();
      for (int c : chosen) s = std::min(s, norm(m.vertices[v] - m.vertices[c]));
      return s;
    };
    const int best = *std::max_element(pool.begin(), pool.end(), [&](int a, int b) { return score(a) < score(b); });
    chosen.push_back(best);
    pool.erase(std::find(pool.begin(), pool.end(), best));
  }

  std::ostringstream curves;
  curves << "# meshfit example: closed edge loops of a deformed copy of CGAL's data/meshes/elephant.off\n"
         << "# deformation: (x,y,z) -> scale (1.15, 0.95, 1.1), twist about y by 0.4 y' rad, y += 0.6 x'^2\n"
         << "# loops (boundary of the faces whose centroid is on the + side of the plane, longest cycle):";
  for (const Cut& c : cuts) curves << ' ' << c.name << ';';
  curves << "\n# every 2nd loop vertex kept; the loops cross at " << features.size() << " shared vertices\n";
  for (std::size_t i = 0; i < lines.size(); ++i) {
    curves << "# " << cuts[i].name << ": mesh vertices";
    for (std::size_t k = 0; k + 1 < kept_loops[i].size(); ++k) curves << ' ' << kept_loops[i][k];
    curves << '\n' << polyline_text(lines[i]);
  }
  std::ostringstream pairs;
  pairs << "# template_vertex_index x y z: elephant.off vertex i <-> its deformed position (a point of curves.polylines.txt)\n"
        << "# " << pair_count << " loop vertices chosen farthest-point first\n";
  for (int v : chosen) pairs << v << ' ' << fmt(m.vertices[v]) << '\n';
  write_file(dir / "curves.polylines.txt", curves.str());
  write_file(dir / "pairs.txt", pairs.str());
  std::cout << "elephant: " << lines.size() << " loops (" ;
  for (const auto& l : loops) std::cout << l.size() << ' ';
  std::cout << "mesh vertices), " << points << " network points, " << features.size() << " crossings, "
            << pair_count << " pairs\n";
  return 0;
}
