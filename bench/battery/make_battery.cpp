// Stress battery generator for meshfit (issue 11, item 5).
//
//   make_battery OUTDIR [CGAL_MESH_DIR]
//
// Writes one directory per case under OUTDIR, each with template.off, curves.polylines.txt,
// pairs.txt, truth.off and case.txt, and OUTDIR/cases.txt (one line per case: name, quick flag).
// Placement variants (rotation, translation by 1e6, scaling by 1e-4 and 1e4) have their own
// template.off and case.txt; their curves, pairs and truth are symbolic links to the base case's.
//
// Independent of the meshfit library: only CGAL and the standard library. Deterministic (fixed
// seeds, no std::uniform_*_distribution). See README.md beside this file for the cases.

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Surface_mesh_parameterization/Mean_value_coordinates_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Square_border_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using P = K::Point_3;
using V3 = K::Vector_3;
using P2 = K::Point_2;
using Mesh = CGAL::Surface_mesh<P>;
using vd = Mesh::Vertex_index;
using fd = Mesh::Face_index;
using hd = Mesh::Halfedge_index;
using ed = Mesh::Edge_index;
namespace fs = std::filesystem;
namespace PMP = CGAL::Polygon_mesh_processing;
namespace SMP = CGAL::Surface_mesh_parameterization;

constexpr double pi = 3.14159265358979323846;

using Polyline = std::vector<P>;

struct Case {
  std::string name;
  std::string kind = "analytic";  // analytic | real
  std::string family;
  Mesh tmpl;
  Mesh truth;
  std::vector<Polyline> curves;
  std::vector<std::pair<int, P>> pairs;
  long expected_regions = -1;  // -1: not computed (impossible cases)
  std::string regions_note;
  bool impossible = false;
  bool quick = false;
  std::string note;
};

// ---------------------------------------------------------------- small helpers

double len(const V3& v) { return std::sqrt(v.squared_length()); }
V3 unit(const V3& v) { return v / len(v); }
V3 vec(const P& p) { return p - CGAL::ORIGIN; }

double to_unit(std::uint64_t x) { return double(x >> 11) * (1.0 / 9007199254740992.0); }

std::uint64_t fnv(const std::string& s) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) { h ^= c; h *= 1099511628211ull; }
  return h;
}

double mean_edge_length(const Mesh& m) {
  double s = 0;
  for (ed e : m.edges()) s += std::sqrt(CGAL::squared_distance(m.point(m.vertex(e, 0)), m.point(m.vertex(e, 1))));
  return s / double(m.number_of_edges());
}

double bbox_diagonal(const Mesh& m) {
  CGAL::Bbox_3 b;
  for (vd v : m.vertices()) b += m.point(v).bbox();
  return std::sqrt(CGAL::square(b.xmax() - b.xmin()) + CGAL::square(b.ymax() - b.ymin()) +
                   CGAL::square(b.zmax() - b.zmin()));
}

P bbox_center(const Mesh& m) {
  CGAL::Bbox_3 b;
  for (vd v : m.vertices()) b += m.point(v).bbox();
  return P((b.xmin() + b.xmax()) / 2, (b.ymin() + b.ymax()) / 2, (b.zmin() + b.zmax()) / 2);
}

int nearest_vertex(const Mesh& m, const P& q) {
  int best = -1;
  double bd = 1e300;
  for (vd v : m.vertices()) {
    const double d = CGAL::squared_distance(m.point(v), q);
    if (d < bd) { bd = d; best = int(v.idx()); }
  }
  return best;
}

void write_off(const fs::path& path, const Mesh& m) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path.string());
  std::fprintf(f, "OFF\n%zu %zu 0\n", size_t(m.number_of_vertices()), size_t(m.number_of_faces()));
  for (vd v : m.vertices()) {
    const P& p = m.point(v);
    std::fprintf(f, "%.17g %.17g %.17g\n", p.x(), p.y(), p.z());
  }
  for (fd fc : m.faces()) {
    std::fprintf(f, "3");
    for (vd v : m.vertices_around_face(m.halfedge(fc))) std::fprintf(f, " %u", unsigned(v.idx()));
    std::fprintf(f, "\n");
  }
  std::fclose(f);
}

void write_curves(const fs::path& path, const std::vector<Polyline>& curves, const std::string& comment) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path.string());
  std::fprintf(f, "# %s\n", comment.c_str());
  for (const Polyline& pl : curves) {
    std::fprintf(f, "%zu", pl.size());
    for (const P& p : pl) std::fprintf(f, " %.17g %.17g %.17g", p.x(), p.y(), p.z());
    std::fprintf(f, "\n");
  }
  std::fclose(f);
}

void write_pairs(const fs::path& path, const std::vector<std::pair<int, P>>& pairs) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path.string());
  std::fprintf(f, "# template_vertex x y z (network point copied from curves.polylines.txt)\n");
  for (const auto& [i, p] : pairs) std::fprintf(f, "%d %.17g %.17g %.17g\n", i, p.x(), p.y(), p.z());
  std::fclose(f);
}

// ------------------------------------------------------------ network counting

struct Network_counts {
  long V = 0, E = 0, C = 0;
};

using Key = std::array<double, 3>;
Key key(const P& p) { return {p.x(), p.y(), p.z()}; }

struct Union_find {
  std::vector<int> p;
  int add() { p.push_back(int(p.size())); return int(p.size()) - 1; }
  int find(int x) { while (p[x] != x) x = p[x] = p[p[x]]; return x; }
  void unite(int a, int b) { p[find(a)] = find(b); }
};

// Counts the network (points equal bitwise are one vertex) and returns E - V + 1 + C after
// adding `boundary_groups` (one group per boundary loop of the template: the network points on
// that loop; a loop with k >= 1 points adds k segments and joins them), minus `caps` (the number
// of boundary loops capped to close the surface). See README.md.
long genus0_regions(const std::vector<Polyline>& curves, const std::vector<std::vector<P>>& boundary_groups,
                    long caps, Network_counts* out = nullptr) {
  std::map<Key, int> id;
  Union_find uf;
  std::set<std::pair<int, int>> segs;
  auto vid = [&](const P& p) {
    auto [it, fresh] = id.emplace(key(p), 0);
    if (fresh) it->second = uf.add();
    return it->second;
  };
  for (const Polyline& pl : curves)
    for (size_t i = 0; i + 1 < pl.size(); ++i) {
      const int a = vid(pl[i]), b = vid(pl[i + 1]);
      if (a == b) continue;
      segs.emplace(std::min(a, b), std::max(a, b));
      uf.unite(a, b);
    }
  for (const Polyline& pl : curves)
    if (pl.size() == 1) vid(pl[0]);
  long V = long(id.size()), E = long(segs.size());
  for (const auto& g : boundary_groups) {
    std::set<int> ids;
    for (const P& p : g) ids.insert(vid(p));
    V = long(id.size());
    E += long(ids.size());
    for (int x : ids) uf.unite(x, *ids.begin());
  }
  std::set<int> roots;
  for (const auto& kv : id) roots.insert(uf.find(kv.second));
  const long C = long(roots.size());
  if (out) *out = {V, E, C};
  return E - V + 1 + C - caps;
}

// --------------------------------------------------------------- analytic shapes

Mesh icosphere(int level) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<V3> v = {{-1, t, 0}, {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                       {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (auto& x : v) x = unit(x);
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto m = [&](int a, int b) {
      const auto k = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(k);
      if (it != mid.end()) return it->second;
      v.push_back(unit(v[a] + v[b]));
      return mid[k] = int(v.size()) - 1;
    };
    std::vector<std::array<int, 3>> g;
    for (auto& tr : f) {
      const int a = m(tr[0], tr[1]), b = m(tr[1], tr[2]), c = m(tr[2], tr[0]);
      g.push_back({tr[0], a, c});
      g.push_back({tr[1], b, a});
      g.push_back({tr[2], c, b});
      g.push_back({a, b, c});
    }
    f.swap(g);
  }
  Mesh mesh;
  for (auto& x : v) mesh.add_vertex(CGAL::ORIGIN + x);
  for (auto& tr : f) {
    const V3 n = CGAL::cross_product(v[tr[1]] - v[tr[0]], v[tr[2]] - v[tr[0]]);
    if (n * (v[tr[0]] + v[tr[1]] + v[tr[2]]) > 0)
      mesh.add_face(vd(tr[0]), vd(tr[1]), vd(tr[2]));
    else
      mesh.add_face(vd(tr[0]), vd(tr[2]), vd(tr[1]));
  }
  return mesh;
}

using Radial = std::function<double(const V3&)>;  // radius along a unit direction

double superellipsoid_r(const V3& d) {
  const double p = 3.0;
  const double s = std::pow(std::abs(d.x() / 1.3), p) + std::pow(std::abs(d.y() / 1.0), p) +
                   std::pow(std::abs(d.z() / 0.8), p);
  return std::pow(s, -1.0 / p);
}
double bumpy_r(const V3& d) {
  const double x = d.x(), y = d.y(), z = d.z();
  return 1.0 + 0.15 * (3 * x * x * y - y * y * y) + 0.5 * x * y * z + 0.08 * (5 * z * z * z - 3 * z) / 2;
}
// Cassini-oval peanut along x: r^2 = cos 2t + sqrt(c^4 - sin^2 2t), c^4 = 1.5.
double peanut_r(const V3& d) {
  const double c2 = 2 * d.x() * d.x() - 1, s2sq = 4 * d.x() * d.x() * (1 - d.x() * d.x());
  return std::sqrt(c2 + std::sqrt(1.5 - s2sq));
}
double sphere_r(const V3&) { return 1.0; }

P radial_map(const Radial& r, const P& d) {
  const V3 u = unit(vec(d));
  return CGAL::ORIGIN + r(u) * u;
}

Mesh radial_truth(const Radial& r) {
  Mesh m = icosphere(6);
  for (vd v : m.vertices()) m.point(v) = radial_map(r, m.point(v));
  return m;
}

// A circle on the unit sphere: n . x = h, |n| = 1.
struct Circle {
  V3 n;
  double h;
  V3 u, v;
};
Circle make_circle(V3 n, double h) {
  n = unit(n);
  V3 a = std::abs(n.x()) < 0.9 ? V3(1, 0, 0) : V3(0, 1, 0);
  const V3 u = unit(CGAL::cross_product(n, a));
  const V3 v = CGAL::cross_product(n, u);
  return {n, h, u, v};
}
double circle_angle(const Circle& c, const V3& x) {
  const V3 w = x - c.h * c.n;
  return std::atan2(w * c.v, w * c.u);
}
V3 circle_point(const Circle& c, double t) {
  const double rho = std::sqrt(std::max(0.0, 1 - c.h * c.h));
  return c.h * c.n + rho * (std::cos(t) * c.u + std::sin(t) * c.v);
}

// Builds closed polylines on the unit sphere for `circles`, mapped radially by `r`, with the
// pairwise crossings inserted once (so both circles carry the same double point). Sample spacing
// is `spacing` in radians of arc. When `insert_crossings` is false, samples avoid the crossings.
struct Sphere_network {
  std::vector<Polyline> curves;
  std::vector<V3> crossings;  // unit directions
};

Sphere_network circle_network(const std::vector<Circle>& circles, const Radial& r, double spacing,
                              bool insert_crossings = true) {
  Sphere_network net;
  std::vector<std::vector<std::pair<double, int>>> on(circles.size());
  auto register_crossing = [&](const V3& x) {
    for (size_t k = 0; k < net.crossings.size(); ++k)
      if ((net.crossings[k] - x).squared_length() < 1e-18) return int(k);
    net.crossings.push_back(x);
    return int(net.crossings.size()) - 1;
  };
  for (size_t i = 0; i < circles.size(); ++i)
    for (size_t j = i + 1; j < circles.size(); ++j) {
      const Circle &a = circles[i], &b = circles[j];
      const double g = a.n * b.n;
      const double det = 1 - g * g;
      if (det < 1e-12) continue;
      const double ca = (a.h - g * b.h) / det, cb = (b.h - g * a.h) / det;
      const V3 base = ca * a.n + cb * b.n;
      const V3 dir = CGAL::cross_product(a.n, b.n);
      const double rest = 1 - base.squared_length();
      if (rest <= 0) continue;
      const double s = std::sqrt(rest / dir.squared_length());
      for (double sg : {1.0, -1.0}) {
        V3 x = base + sg * s * dir;
        // Snap coordinates that are zero up to rounding (keeps exactly coplanar cases exact).
        x = V3(std::abs(x.x()) < 1e-15 ? 0.0 : x.x(), std::abs(x.y()) < 1e-15 ? 0.0 : x.y(),
               std::abs(x.z()) < 1e-15 ? 0.0 : x.z());
        const int k = register_crossing(x);
        for (size_t c : {i, j}) {
          bool dup = false;
          for (auto& e : on[c]) dup |= e.second == k;
          if (!dup) on[c].push_back({circle_angle(circles[c], x), k});
        }
      }
    }
  for (size_t c = 0; c < circles.size(); ++c) {
    const double rho = std::sqrt(std::max(0.0, 1 - circles[c].h * circles[c].h));
    const int n = std::max(4, int(std::ceil(2 * pi * rho / spacing)));
    const double step = 2 * pi / n;
    std::vector<std::pair<double, int>> items;  // angle, crossing id or -1
    const double offset = insert_crossings ? 0.0 : 0.5 * step;
    for (int k = 0; k < n; ++k) {
      double t = -pi + offset + k * step + 0.123 * step;
      bool near = false;
      for (auto& e : on[c]) {
        double d = std::remainder(t - e.first, 2 * pi);
        if (std::abs(d) < (insert_crossings ? 0.35 : 0.05) * step) near = true;
      }
      if (!near || !insert_crossings) items.push_back({t, -1});
    }
    if (insert_crossings)
      for (auto& e : on[c]) items.push_back(e);
    for (auto& it : items) it.first = std::remainder(it.first, 2 * pi);
    std::sort(items.begin(), items.end());
    Polyline pl;
    for (auto& it : items) {
      const V3 d = it.second >= 0 ? net.crossings[it.second] : circle_point(circles[c], it.first);
      pl.push_back(radial_map(r, CGAL::ORIGIN + d));
    }
    pl.push_back(pl.front());
    net.curves.push_back(pl);
  }
  return net;
}

// Picks up to `count` crossings spread over the list, each paired with the template vertex
// nearest to its direction (a distinct vertex each).
std::vector<std::pair<int, P>> sphere_pairs(const Mesh& tmpl, const Sphere_network& net, const Radial& r,
                                            size_t count, const P& center = CGAL::ORIGIN, double scale = 1.0) {
  std::vector<std::pair<int, P>> pairs;
  std::set<int> used;
  const size_t n = net.crossings.size();
  std::vector<size_t> order;
  for (size_t k = 0; k < n; ++k) order.push_back((k * 7) % n);  // spread (7 coprime with most sizes)
  std::set<size_t> seen;
  for (size_t k : order) {
    if (pairs.size() >= count) break;
    if (!seen.insert(k).second) continue;
    const int v = nearest_vertex(tmpl, center + scale * net.crossings[k]);
    if (!used.insert(v).second) continue;
    pairs.push_back({v, radial_map(r, CGAL::ORIGIN + net.crossings[k])});
  }
  return pairs;
}

std::vector<Circle> great_circles() {
  return {make_circle({1, 0.05, 0}, 0), make_circle({0, 1, 0.07}, 0), make_circle({0.03, 0, 1}, 0),
          make_circle({1, 1, 1}, 0)};
}
std::vector<Circle> latlong_circles() {
  std::vector<Circle> c = {make_circle({0, 0, 1}, -0.5), make_circle({0, 0, 1}, 0.02), make_circle({0, 0, 1}, 0.5)};
  for (double phi : {0.1, 0.1 + pi / 3, 0.1 + 2 * pi / 3}) c.push_back(make_circle({-std::sin(phi), std::cos(phi), 0}, 0));
  return c;
}

// ----------------------------------------------------------------- plane sections

struct Plane {
  V3 n;
  double d;
  double eval(const P& p) const { return n * vec(p) - d; }
};

struct Section {
  // polyline points, and for each point whether it is a crossing (-1: slicer point on an edge)
  std::vector<std::vector<P>> curves;
  std::vector<P> crossings;
  std::vector<fd> crossing_faces;
  std::vector<std::vector<P>> boundary_groups;  // per template boundary loop: the curve ends on it
  bool ok = false;
  std::string why;
};

struct Chain {
  std::vector<ed> edges;  // crossing edges, in order
  std::vector<fd> faces;  // faces[i] holds the segment edges[i] -> edges[i+1] (closed: last -> first)
  bool closed = false;
};

// Sections of `m` by `planes`, with crossings between sections inserted in both curves.
// `snap` removes slicer points closer than that to an inserted crossing.
Section slice(const Mesh& m, const std::vector<Plane>& planes, double snap) {
  Section out;
  const size_t np = planes.size();
  std::vector<std::vector<double>> s(np, std::vector<double>(m.number_of_vertices()));
  const double diag = bbox_diagonal(m);
  for (size_t k = 0; k < np; ++k)
    for (vd v : m.vertices()) {
      s[k][v.idx()] = planes[k].eval(m.point(v));
      if (std::abs(s[k][v.idx()]) < 1e-9 * diag) { out.why = "vertex on plane"; return out; }
    }
  auto crosses = [&](size_t k, ed e) {
    return (s[k][m.vertex(e, 0).idx()] > 0) != (s[k][m.vertex(e, 1).idx()] > 0);
  };
  auto edge_point = [&](size_t k, ed e) {
    const vd a = m.vertex(e, 0), b = m.vertex(e, 1);
    const double sa = s[k][a.idx()], sb = s[k][b.idx()];
    return m.point(a) + (m.point(b) - m.point(a)) * (sa / (sa - sb));
  };
  // boundary loops
  std::vector<int> loop_of_edge(m.number_of_edges(), -1);
  int nloops = 0;
  for (hd h : m.halfedges())
    if (m.is_border(h) && loop_of_edge[m.edge(h).idx()] < 0) {
      for (hd g : CGAL::halfedges_around_face(h, m)) loop_of_edge[m.edge(g).idx()] = nloops;
      ++nloops;
    }
  out.boundary_groups.resize(nloops);

  std::vector<std::vector<Chain>> chains(np);
  for (size_t k = 0; k < np; ++k) {
    std::vector<char> visited(m.number_of_faces(), 0);
    auto other_edge = [&](fd f, ed e) {
      for (hd h : CGAL::halfedges_around_face(m.halfedge(f), m))
        if (m.edge(h) != e && crosses(k, m.edge(h))) return m.edge(h);
      return ed();
    };
    auto walk = [&](ed e0, fd f0) {
      Chain c;
      ed e = e0;
      fd f = f0;
      c.edges.push_back(e);
      while (true) {
        visited[f.idx()] = 1;
        c.faces.push_back(f);
        const ed e2 = other_edge(f, e);
        hd h2 = m.halfedge(e2);
        if (m.face(h2) == f) h2 = m.opposite(h2);
        const fd g = m.face(h2);
        if (e2 == e0) { c.closed = true; break; }
        c.edges.push_back(e2);
        if (g == Mesh::null_face()) break;
        if (visited[g.idx()]) { c.closed = true; break; }  // should not happen for manifolds
        e = e2;
        f = g;
      }
      return c;
    };
    for (ed e : m.edges())
      if (m.is_border(e) && crosses(k, e)) {
        hd h = m.halfedge(e);
        if (m.is_border(h)) h = m.opposite(h);
        if (!visited[m.face(h).idx()]) chains[k].push_back(walk(e, m.face(h)));
      }
    for (fd f : m.faces()) {
      if (visited[f.idx()]) continue;
      for (hd h : CGAL::halfedges_around_face(m.halfedge(f), m))
        if (crosses(k, m.edge(h))) { chains[k].push_back(walk(m.edge(h), f)); break; }
    }
  }
  // crossings: per (plane, chain, segment) a list of (t, crossing id)
  std::map<std::array<size_t, 3>, std::vector<std::pair<double, int>>> ins;
  for (size_t a = 0; a < np; ++a)
    for (size_t b = a + 1; b < np; ++b) {
      std::map<int, std::pair<size_t, size_t>> seg_b;  // face -> chain, segment
      for (size_t c = 0; c < chains[b].size(); ++c)
        for (size_t i = 0; i < chains[b][c].faces.size(); ++i) seg_b[int(chains[b][c].faces[i].idx())] = {c, i};
      for (size_t c = 0; c < chains[a].size(); ++c) {
        const Chain& ch = chains[a][c];
        for (size_t i = 0; i < ch.faces.size(); ++i) {
          auto it = seg_b.find(int(ch.faces[i].idx()));
          if (it == seg_b.end()) continue;
          const Chain& cb = chains[b][it->second.first];
          const size_t j = it->second.second;
          const P pA = edge_point(a, ch.edges[i]), pB = edge_point(a, ch.edges[(i + 1) % ch.edges.size()]);
          const P qA = edge_point(b, cb.edges[j]), qB = edge_point(b, cb.edges[(j + 1) % cb.edges.size()]);
          const double dA = planes[b].eval(pA), dB = planes[b].eval(pB);
          const double eA = planes[a].eval(qA), eB = planes[a].eval(qB);
          const bool ca = (dA > 0) != (dB > 0), cbx = (eA > 0) != (eB > 0);
          if (ca != cbx) { out.why = "ambiguous crossing"; return out; }
          if (!ca) continue;
          const double t = dA / (dA - dB);
          const P x = pA + (pB - pA) * t;
          const double tb = ((x - qA) * (qB - qA)) / (qB - qA).squared_length();
          const int id = int(out.crossings.size());
          out.crossings.push_back(x);
          out.crossing_faces.push_back(ch.faces[i]);
          ins[{a, c, i}].push_back({t, id});
          ins[{b, it->second.first, j}].push_back({tb, id});
        }
      }
    }
  for (size_t k = 0; k < np; ++k)
    for (size_t c = 0; c < chains[k].size(); ++c) {
      const Chain& ch = chains[k][c];
      std::vector<std::pair<P, bool>> pts;  // point, is crossing
      const size_t nseg = ch.closed ? ch.edges.size() : ch.edges.size() - 1;
      for (size_t i = 0; i < ch.edges.size(); ++i) {
        pts.push_back({edge_point(k, ch.edges[i]), false});
        if (i < nseg) {
          auto it = ins.find({k, c, i});
          if (it != ins.end()) {
            auto v = it->second;
            std::sort(v.begin(), v.end());
            for (auto& e : v) pts.push_back({out.crossings[e.second], true});
          }
        }
      }
      // drop slicer points too close to a neighbouring crossing (never an open chain's ends)
      std::vector<std::pair<P, bool>> kept;
      for (size_t i = 0; i < pts.size(); ++i) {
        const bool end = !ch.closed && (i == 0 || i + 1 == pts.size());
        bool drop = false;
        if (!pts[i].second && !end) {
          const size_t n = pts.size();
          const size_t prev = (i + n - 1) % n, next = (i + 1) % n;
          for (size_t q : {prev, next})
            if (pts[q].second && std::sqrt(CGAL::squared_distance(pts[q].first, pts[i].first)) < snap) drop = true;
        }
        if (!drop) kept.push_back(pts[i]);
      }
      Polyline pl;
      for (auto& e : kept) pl.push_back(e.first);
      if (ch.closed) {
        if (pl.size() < 3) continue;
        pl.push_back(pl.front());
      } else {
        if (pl.size() < 2) continue;
        out.boundary_groups[loop_of_edge[ch.edges.front().idx()]].push_back(pl.front());
        out.boundary_groups[loop_of_edge[ch.edges.back().idx()]].push_back(pl.back());
      }
      out.curves.push_back(pl);
    }
  // Only the boundary loops that carry curve ends matter (an untouched loop changes nothing).
  std::vector<std::vector<P>> groups;
  for (auto& g : out.boundary_groups)
    if (!g.empty()) groups.push_back(g);
  out.boundary_groups = groups;
  out.ok = true;
  return out;
}

// Planes through the centre of `m`: a cross section across the longest axis, two long
// sections, and a fourth cross section off centre; normals tilted slightly. Retries with
// shifted offsets until the slicer has no degenerate configuration.
Section standard_sections(const Mesh& m, int count, double snap) {
  CGAL::Bbox_3 b;
  for (vd v : m.vertices()) b += m.point(v).bbox();
  const double ext[3] = {b.xmax() - b.xmin(), b.ymax() - b.ymin(), b.zmax() - b.zmin()};
  int ax[3] = {0, 1, 2};
  std::sort(ax, ax + 3, [&](int i, int j) { return ext[i] > ext[j]; });
  const P c = bbox_center(m);
  auto axis = [](int i) { return i == 0 ? V3(1, 0, 0) : i == 1 ? V3(0, 1, 0) : V3(0, 0, 1); };
  const V3 L = axis(ax[0]), M = axis(ax[1]), N = axis(ax[2]);
  std::vector<std::pair<V3, double>> spec = {
      {unit(L + 0.06 * M + 0.04 * N), 0.0}, {unit(M + 0.05 * L + 0.03 * N), 0.0},
      {unit(N + 0.04 * L - 0.05 * M), 0.0}, {unit(L - 0.05 * N + 0.03 * M), 0.27 * ext[ax[0]]}};
  spec.resize(size_t(count));
  const double diag = bbox_diagonal(m);
  for (int attempt = 0; attempt < 20; ++attempt) {
    std::vector<Plane> planes;
    for (size_t i = 0; i < spec.size(); ++i)
      planes.push_back({spec[i].first, spec[i].first * vec(c) + spec[i].second + 1.37e-4 * diag * attempt * (i + 1)});
    Section s = slice(m, planes, snap);
    if (s.ok) return s;
  }
  Section s;
  s.why = "no generic plane offsets found";
  return s;
}

// Chooses up to `count` crossings spread over the list, each paired with the template vertex
// nearest to the crossing's preimage (`preimage` maps a crossing index to a template point).
std::vector<std::pair<int, P>> section_pairs(const Mesh& tmpl, const Section& s, size_t count,
                                             const std::function<P(size_t)>& preimage) {
  std::vector<std::pair<int, P>> pairs;
  std::set<int> used;
  std::set<std::array<double, 3>> present;
  for (auto& pl : s.curves)
    for (auto& p : pl) present.insert(key(p));
  const size_t n = s.crossings.size();
  if (n == 0) return pairs;
  std::vector<size_t> order;  // spread first: k n / count, then the rest
  for (size_t i = 0; i < std::min(n, count); ++i) order.push_back(i * n / std::min(n, count));
  for (size_t k = 0; k < n; ++k) order.push_back(k);
  std::set<size_t> tried;
  for (size_t kk : order) {
    if (pairs.size() >= count) break;
    if (!tried.insert(kk).second || !present.count(key(s.crossings[kk]))) continue;
    const int v = nearest_vertex(tmpl, preimage(kk));
    if (!used.insert(v).second) continue;
    pairs.push_back({v, s.crossings[kk]});
  }
  return pairs;
}

P barycentric_preimage(const Mesh& from, const Mesh& to, fd f, const P& x) {
  // barycentric coordinates of x in face f of `from`, applied to the same face of `to`
  std::vector<vd> vs;
  for (vd v : from.vertices_around_face(from.halfedge(f))) vs.push_back(v);
  const P &a = from.point(vs[0]), &b = from.point(vs[1]), &c = from.point(vs[2]);
  const V3 n = CGAL::cross_product(b - a, c - a);
  const double nn = n.squared_length();
  const double wa = CGAL::cross_product(c - b, x - b) * n / nn;
  const double wb = CGAL::cross_product(a - c, x - c) * n / nn;
  const double wc = 1 - wa - wb;
  return CGAL::ORIGIN + wa * vec(to.point(vs[0])) + wb * vec(to.point(vs[1])) + wc * vec(to.point(vs[2]));
}

// ------------------------------------------------------------------ the families

struct Battery {
  std::vector<Case> cases;
  std::vector<std::string> skipped;
};

void analytic_family(Battery& bat) {
  struct Shape {
    const char* name;
    Radial r;
  };
  const std::vector<Shape> shapes = {{"superellipsoid", superellipsoid_r}, {"bumpy", bumpy_r}, {"peanut", peanut_r}};
  const std::vector<std::pair<int, int>> levels = {{2, 162}, {4, 2562}, {5, 10242}};
  for (auto [level, nv] : levels) {
    const Mesh tmpl = icosphere(level);
    const double edge = mean_edge_length(tmpl);  // on the unit sphere: radians, about
    for (const Shape& sh : shapes) {
      const Mesh truth = radial_truth(sh.r);
      for (const char* netname : {"great", "latlong"}) {
        const auto circles = std::string(netname) == "great" ? great_circles() : latlong_circles();
        std::vector<std::pair<std::string, double>> densities = {{"", 1.0}};
        if (level == 4 && std::string(netname) == "latlong")
          densities = {{"", 1.0}, {"-dense3", 1.0 / 3}, {"-dense10", 0.1}, {"-sparse10", 10.0}};
        for (auto& [dname, factor] : densities) {
          Case c;
          c.name = "ico" + std::to_string(nv) + "-" + sh.name + "-" + netname + dname;
          c.family = "icosphere onto analytic";
          c.tmpl = tmpl;
          c.truth = truth;
          const Sphere_network net = circle_network(circles, sh.r, edge * factor);
          c.curves = net.curves;
          c.pairs = sphere_pairs(tmpl, net, sh.r, 8);
          c.expected_regions = genus0_regions(c.curves, {}, 0);
          c.regions_note = "E - V + 1 + C (closed genus 0)";
          c.note = std::string("curve spacing ") + std::to_string(factor) + " x template edge";
          c.quick = (c.name == "ico162-superellipsoid-great" || c.name == "ico2562-bumpy-latlong" ||
                     c.name == "ico2562-peanut-great" || c.name == "ico2562-superellipsoid-latlong-dense3" ||
                     c.name == "ico2562-bumpy-latlong-dense10");
          bat.cases.push_back(std::move(c));
        }
      }
    }
  }
}

void pairs_family(Battery& bat) {
  const Mesh tmpl = icosphere(4);
  const double edge = mean_edge_length(tmpl);
  const Mesh truth = radial_truth(superellipsoid_r);
  {
    Case c;
    c.name = "pairs4";
    c.family = "exactly 4 pairs";
    c.tmpl = tmpl;
    c.truth = truth;
    const Sphere_network net = circle_network(great_circles(), superellipsoid_r, edge);
    c.curves = net.curves;
    // four crossings that span a tetrahedron: the first, then the ones farthest from the span
    std::vector<std::pair<int, P>> all = sphere_pairs(tmpl, net, superellipsoid_r, 12);
    std::vector<size_t> pick = {0};
    while (pick.size() < 4) {
      size_t best = 0;
      double bd = -1;
      for (size_t k = 0; k < all.size(); ++k) {
        double dmin = 1e300;
        for (size_t q : pick) dmin = std::min(dmin, CGAL::squared_distance(all[k].second, all[q].second));
        if (pick.size() == 3) {
          const auto& A = all[pick[0]].second;
          const auto& B = all[pick[1]].second;
          const auto& C = all[pick[2]].second;
          dmin = std::abs(CGAL::cross_product(B - A, C - A) * (all[k].second - A));
        }
        if (dmin > bd) { bd = dmin; best = k; }
      }
      pick.push_back(best);
    }
    for (size_t q : pick) c.pairs.push_back(all[q]);
    c.expected_regions = genus0_regions(c.curves, {}, 0);
    c.regions_note = "E - V + 1 + C (closed genus 0)";
    c.quick = true;
    bat.cases.push_back(std::move(c));
  }
  {
    Case c;
    c.name = "pairs4-coplanar";
    c.family = "4 coplanar pairs on both sides";
    c.tmpl = tmpl;
    c.truth = truth;
    // template vertices on z = 0 (exactly) near 20 and 110 degrees, and their antipodes
    auto on_equator = [&](double ang) {
      int best = -1;
      double bd = 1e300;
      for (vd v : tmpl.vertices()) {
        const P& p = tmpl.point(v);
        if (p.z() != 0.0) continue;
        const double d = CGAL::squared_distance(p, P(std::cos(ang), std::sin(ang), 0));
        if (d < bd) { bd = d; best = int(v.idx()); }
      }
      return best;
    };
    const int w1 = on_equator(20 * pi / 180), w2 = on_equator(110 * pi / 180);
    const int w3 = on_equator(200 * pi / 180), w4 = on_equator(290 * pi / 180);
    const V3 d1 = vec(tmpl.point(vd(w1))), d2 = vec(tmpl.point(vd(w2)));
    std::vector<Circle> circles = {make_circle({0, 0, 1}, 0), make_circle({0, 0, 1}, 0.55),
                                   make_circle({0, 0, 1}, -0.55),
                                   make_circle(CGAL::cross_product(V3(0, 0, 1), d1), 0),
                                   make_circle(CGAL::cross_product(V3(0, 0, 1), d2), 0)};
    const Sphere_network net = circle_network(circles, superellipsoid_r, edge);
    c.curves = net.curves;
    for (int w : {w1, w2, w3, w4}) {
      // the equator crossing nearest the vertex's direction
      size_t best = 0;
      double bd = 1e300;
      for (size_t k = 0; k < net.crossings.size(); ++k) {
        if (net.crossings[k].z() != 0.0) continue;
        const double d = (net.crossings[k] - vec(tmpl.point(vd(w)))).squared_length();
        if (d < bd) { bd = d; best = k; }
      }
      c.pairs.push_back({w, radial_map(superellipsoid_r, CGAL::ORIGIN + net.crossings[best])});
    }
    c.expected_regions = genus0_regions(c.curves, {}, 0);
    c.regions_note = "E - V + 1 + C (closed genus 0)";
    c.note = "template vertices and network points all on z = 0 exactly";
    c.quick = true;
    bat.cases.push_back(std::move(c));
  }
}

void impossible_family(Battery& bat) {
  const Mesh tmpl = icosphere(4);
  const double edge = mean_edge_length(tmpl);
  const Mesh truth = radial_truth(sphere_r);
  {
    Case c;
    c.name = "impossible-crossing";
    c.family = "impossible";
    c.impossible = true;
    c.tmpl = tmpl;
    c.truth = truth;
    const Sphere_network net =
        circle_network({make_circle({1, 0.05, 0}, 0), make_circle({0.03, 0.02, 1}, 0)}, sphere_r, edge, false);
    c.curves = net.curves;
    // two points of each circle
    for (size_t k : {size_t(0), net.curves[0].size() / 3}) c.pairs.push_back({nearest_vertex(tmpl, net.curves[0][k]), net.curves[0][k]});
    for (size_t k : {size_t(2), net.curves[1].size() / 2}) c.pairs.push_back({nearest_vertex(tmpl, net.curves[1][k]), net.curves[1][k]});
    c.note = "two great circles that cross twice without a shared vertex";
    c.quick = true;
    bat.cases.push_back(std::move(c));
  }
  {
    Case c;
    c.name = "impossible-k33";
    c.family = "impossible";
    c.impossible = true;
    c.tmpl = tmpl;
    c.truth = truth;
    std::vector<V3> A, B;
    for (int k = 0; k < 3; ++k) {
      const double pa = k * 2 * pi / 3, pb = pa + pi / 3;
      A.push_back(unit(V3(std::cos(pa), std::sin(pa), 0.35)));  // never antipodal to a B
      B.push_back(unit(V3(std::cos(pb), std::sin(pb), -0.6)));
    }
    int arc = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j, ++arc) {
        Polyline pl;
        const double omega = std::acos(std::clamp(A[i] * B[j], -1.0, 1.0));
        const int n = std::max(4, int(std::ceil(omega / edge)));
        for (int q = 0; q <= n; ++q) {
          const double s = double(q) / n;
          V3 d = q == 0 ? A[i] : q == n ? B[j]
                                        : unit((std::sin((1 - s) * omega) * A[i] + std::sin(s * omega) * B[j]) /
                                               std::sin(omega));
          // lift each arc to its own height so that no two curves meet in space
          const double lift = (q == 0 || q == n) ? 1.0 : 1.0 + 0.03 * (arc + 1) * std::sin(pi * s);
          pl.push_back(CGAL::ORIGIN + lift * d);
        }
        c.curves.push_back(pl);
      }
    for (auto& d : A) c.pairs.push_back({nearest_vertex(tmpl, CGAL::ORIGIN + d), CGAL::ORIGIN + d});
    for (auto& d : B) c.pairs.push_back({nearest_vertex(tmpl, CGAL::ORIGIN + d), CGAL::ORIGIN + d});
    c.note = "K3,3 between 3+3 points of the unit sphere (arcs lifted apart, so no two curves meet)";
    c.quick = true;
    bat.cases.push_back(std::move(c));
  }
  {
    Case c;
    c.name = "impossible-far";
    c.family = "impossible";
    c.impossible = true;
    c.tmpl = tmpl;
    c.truth = truth;
    const Sphere_network net = circle_network(latlong_circles(), sphere_r, edge);
    c.curves = net.curves;
    c.pairs = sphere_pairs(tmpl, net, sphere_r, 8);
    Polyline far;
    for (int k = 0; k < 24; ++k) far.push_back(P(6.0, 0.3 * std::cos(2 * pi * k / 24), 0.3 * std::sin(2 * pi * k / 24)));
    far.push_back(far.front());
    c.curves.push_back(far);
    c.note = "a latitude/longitude network on the unit sphere plus a loop 5 radii away";
    c.quick = true;
    bat.cases.push_back(std::move(c));
  }
}

// Smooth deformation of a model: anisotropic scale, twist about the longest axis, bend.
Mesh deformed_copy(const Mesh& m) {
  CGAL::Bbox_3 b;
  for (vd v : m.vertices()) b += m.point(v).bbox();
  const double ext[3] = {b.xmax() - b.xmin(), b.ymax() - b.ymin(), b.zmax() - b.zmin()};
  int ax[3] = {0, 1, 2};
  std::sort(ax, ax + 3, [&](int i, int j) { return ext[i] > ext[j]; });
  const P c = bbox_center(m);
  const double s = bbox_diagonal(m);
  Mesh out = m;
  for (vd v : out.vertices()) {
    const V3 q = (m.point(v) - c) / s;
    double x[3] = {q.x(), q.y(), q.z()};
    double L = x[ax[0]], M = x[ax[1]], N = x[ax[2]];
    L *= 1.12; M *= 0.9; N *= 1.05;                 // anisotropic scale
    const double a = 0.6 * L;                        // twist about the long axis (up to ~0.3 rad)
    const double M2 = std::cos(a) * M - std::sin(a) * N, N2 = std::sin(a) * M + std::cos(a) * N;
    M = M2; N = N2;
    M += 0.25 * L * L;                               // bend
    x[ax[0]] = L; x[ax[1]] = M; x[ax[2]] = N;
    out.point(v) = c + s * V3(x[0], x[1], x[2]);
  }
  return out;
}

bool load_model(const std::string& dir, const std::string& name, Mesh& m, Battery& bat) {
  const std::string path = dir + "/" + name + ".off";
  if (dir.empty() || !fs::exists(path)) {
    bat.skipped.push_back(name + ": " + path + " not found (CGAL data from libcgal-demo)");
    return false;
  }
  if (!CGAL::IO::read_polygon_mesh(path, m) || m.is_empty() || !CGAL::is_triangle_mesh(m)) {
    bat.skipped.push_back(name + ": " + path + " is not read as a triangle mesh by CGAL");
    return false;
  }
  return true;
}

void real_family(Battery& bat, const std::string& dir) {
  for (const char* name : {"camel", "bunny00", "pig", "dino", "mannequin-devil", "lion-head"}) {
    Mesh m;
    if (!load_model(dir, name, m, bat)) continue;
    const Mesh truth = deformed_copy(m);
    const Section s = standard_sections(truth, 4, 0.25 * mean_edge_length(truth));
    if (!s.ok) { bat.skipped.push_back(std::string(name) + ": slicing failed (" + s.why + ")"); continue; }
    Case c;
    c.name = std::string("real-") + name;
    c.kind = "real";
    c.family = "model onto sections of its deformed copy";
    c.tmpl = m;
    c.truth = truth;
    c.curves = s.curves;
    c.pairs = section_pairs(m, s, 8, [&](size_t k) { return barycentric_preimage(truth, m, s.crossing_faces[k], s.crossings[k]); });
    const long b = long(s.boundary_groups.size());
    c.expected_regions = genus0_regions(c.curves, s.boundary_groups, b);
    // genus check of the template: chi = V - E + F, boundary loops
    long loops = 0;
    {
      std::set<int> seen;
      for (hd h : m.halfedges())
        if (m.is_border(h) && !seen.count(int(h.idx()))) {
          ++loops;
          for (hd g : CGAL::halfedges_around_face(h, m)) seen.insert(int(g.idx()));
        }
    }
    const long chi = long(m.number_of_vertices()) - long(m.number_of_edges()) + long(m.number_of_faces());
    const long genus2 = 2 - chi - loops;  // 2g
    if (genus2 != 0) {
      c.regions_note = "template genus " + std::to_string(genus2 / 2.0) + " with " + std::to_string(loops) +
                       " boundaries: the genus-0 count does not apply; regions not checked";
      c.expected_regions = -1;
    } else {
      c.regions_note = "E' - V' + 1 + C' - b with the " + std::to_string(b) +
                       " template boundary loops that curves end on added to the network and capped";
    }
    c.note = "4 plane sections of a bent, twisted, anisotropically scaled copy; " + std::to_string(s.crossings.size()) + " crossings";
    c.quick = std::string(name) == "dino";
    bat.cases.push_back(std::move(c));
  }
  for (const char* name : {"pig", "bull", "mannequin-devil"}) {
    Mesh m;
    if (!load_model(dir, name, m, bat)) continue;
    const Section s = standard_sections(m, 3, 0.25 * mean_edge_length(m));
    if (!s.ok) { bat.skipped.push_back(std::string("ico onto ") + name + ": slicing failed (" + s.why + ")"); continue; }
    Case c;
    c.name = std::string("ico2562-onto-") + name;
    c.kind = "real";
    c.family = "icosphere onto sections of a real model";
    const P ctr = bbox_center(m);
    const double rad = 0.5 * bbox_diagonal(m);
    c.tmpl = icosphere(4);
    for (vd v : c.tmpl.vertices()) c.tmpl.point(v) = ctr + rad * vec(c.tmpl.point(v));
    c.truth = m;
    c.curves = s.curves;
    c.pairs = section_pairs(c.tmpl, s, 8, [&](size_t k) { return ctr + rad * unit(s.crossings[k] - ctr); });
    c.expected_regions = genus0_regions(c.curves, {}, 0);
    c.regions_note = "E - V + 1 + C on the closed genus-0 template (curves ending at the model's holes dangle)";
    c.note = "3 plane sections of the model itself; template = icosphere around its bounding box";
    bat.cases.push_back(std::move(c));
  }
}

// Midpoint (1-to-4) subdivision of a mesh with a uv map, carrying uv.
void subdivide_uv(std::vector<P2>& uv, std::vector<std::array<int, 3>>& f) {
  std::map<std::pair<int, int>, int> mid;
  auto m = [&](int a, int b) {
    const auto k = std::make_pair(std::min(a, b), std::max(a, b));
    auto it = mid.find(k);
    if (it != mid.end()) return it->second;
    uv.push_back(CGAL::midpoint(uv[a], uv[b]));
    return mid[k] = int(uv.size()) - 1;
  };
  std::vector<std::array<int, 3>> g;
  for (auto& t : f) {
    const int a = m(t[0], t[1]), b = m(t[1], t[2]), c = m(t[2], t[0]);
    g.push_back({t[0], a, c});
    g.push_back({t[1], b, a});
    g.push_back({t[2], c, b});
    g.push_back({a, b, c});
  }
  f.swap(g);
}

void open_family(Battery& bat, const std::string& dir) {
  for (const char* name : {"plane", "mesh_with_border", "patch-01"}) {
    Mesh m;
    if (!load_model(dir, name, m, bat)) continue;
    const hd bh = PMP::longest_border(m).first;
    auto uvmap = m.add_property_map<vd, P2>("v:uv").first;
    using Border = SMP::Square_border_arc_length_parameterizer_3<Mesh>;
    using Param = SMP::Mean_value_coordinates_parameterizer_3<Mesh, Border>;
    if (SMP::parameterize(m, Param(), bh, uvmap) != SMP::OK) {
      bat.skipped.push_back(std::string(name) + ": parameterization failed");
      continue;
    }
    long nb = 0;
    for (hd h : CGAL::halfedges_around_face(bh, m)) { (void)h; ++nb; }
    const double S = bbox_diagonal(m) / std::sqrt(2.0);
    const P ctr = bbox_center(m);
    const double uvedge = 1.0 / std::sqrt(double(m.number_of_vertices()));
    struct Height {
      const char* name;
      std::function<double(double, double)> h;
    };
    const std::vector<Height> heights = {
        {"saddle", [](double u, double v) { return 0.7 * ((u - 0.5) * (u - 0.5) - (v - 0.5) * (v - 0.5)); }},
        {"wave", [](double u, double v) { return 0.07 * std::sin(2 * pi * u) * std::cos(1.5 * pi * v); }}};
    for (const Height& H : heights) {
      auto lift = [&](double u, double v) { return ctr + S * V3(u - 0.5, v - 0.5, H.h(u, v)); };
      // truth: the template's uv mesh, subdivided twice, lifted
      std::vector<P2> uv;
      for (vd v : m.vertices()) uv.push_back(get(uvmap, v));
      std::vector<std::array<int, 3>> f;
      for (fd fc : m.faces()) {
        std::array<int, 3> t;
        int k = 0;
        for (vd v : m.vertices_around_face(m.halfedge(fc))) t[k++] = int(v.idx());
        f.push_back(t);
      }
      subdivide_uv(uv, f);
      subdivide_uv(uv, f);
      Mesh truth;
      for (auto& q : uv) truth.add_vertex(lift(q.x(), q.y()));
      for (auto& t : f) truth.add_face(vd(t[0]), vd(t[1]), vd(t[2]));
      // orientation: keep the template's; the lifted normal should point like the template's
      for (bool with_boundary : {true, false}) {
        Case c;
        c.name = std::string("open-") + name + "-" + H.name + (with_boundary ? "-boundary" : "-inner");
        c.family = "open template onto a height field";
        c.tmpl = m;
        {
          auto pm = c.tmpl.property_map<vd, P2>("v:uv").first;
          c.tmpl.remove_property_map(pm);
        }
        c.truth = truth;
        const std::vector<double> us = {0.33, 0.67}, vs = {0.3, 0.7};
        const double lo = with_boundary ? 0.0 : 0.12, hi = with_boundary ? 1.0 : 0.88;
        auto iso = [&](bool along_v, double c0, const std::vector<double>& cross) {
          std::vector<double> ts;
          const int n = std::max(2, int(std::ceil((hi - lo) / uvedge)));
          for (int k = 0; k <= n; ++k) ts.push_back(lo + (hi - lo) * k / n);
          for (double x : cross)
            ts.erase(std::remove_if(ts.begin(), ts.end(), [&](double t) { return std::abs(t - x) < 0.35 * (hi - lo) / n; }),
                     ts.end());
          for (double x : cross) ts.push_back(x);
          std::sort(ts.begin(), ts.end());
          ts.front() = lo;
          ts.back() = hi;
          Polyline pl;
          for (double t : ts) pl.push_back(along_v ? lift(c0, t) : lift(t, c0));
          return pl;
        };
        for (double u : us) c.curves.push_back(iso(true, u, vs));
        for (double v : vs) c.curves.push_back(iso(false, v, us));
        if (with_boundary) {
          // the square's boundary, sampled about 3x coarser than the template's boundary,
          // through the corners and the iso-lines' ends
          const int per_side = std::max(2, int(nb / 4 / 3));
          Polyline pl;
          auto side = [&](int s, double t) {
            switch (s) {
              case 0: return std::make_pair(t, 0.0);
              case 1: return std::make_pair(1.0, t);
              case 2: return std::make_pair(1.0 - t, 1.0);
              default: return std::make_pair(0.0, 1.0 - t);
            }
          };
          for (int sd = 0; sd < 4; ++sd) {
            std::vector<double> ts;
            for (int k = 0; k < per_side; ++k) ts.push_back(double(k) / per_side);
            const std::vector<double>& cr = (sd % 2 == 0) ? us : vs;
            for (double x : cr) {
              const double t = sd < 2 ? x : 1.0 - x;
              ts.erase(std::remove_if(ts.begin() + 1, ts.end(), [&](double q) { return std::abs(q - t) < 0.3 / per_side; }), ts.end());
              ts.push_back(t);
            }
            std::sort(ts.begin(), ts.end());
            for (double t : ts) {
              auto [u, v] = side(sd, t);
              // exact values at the iso-line ends so that they match bitwise
              for (double x : us) if (std::abs(u - x) < 1e-12) u = x;
              for (double x : vs) if (std::abs(v - x) < 1e-12) v = x;
              pl.push_back(lift(u, v));
            }
          }
          pl.push_back(pl.front());
          c.curves.push_back(pl);
        }
        // pairs: the 4 inner crossings and the 4 iso-line ends on v = lo / u = lo, hi
        std::vector<std::pair<double, double>> pts;
        for (double u : us) for (double v : vs) pts.push_back({u, v});
        pts.push_back({us[0], lo}); pts.push_back({us[1], hi}); pts.push_back({lo, vs[1]}); pts.push_back({hi, vs[0]});
        std::set<int> used;
        for (auto [u, v] : pts) {
          int best = -1;
          double bd = 1e300;
          for (vd x : m.vertices()) {
            const double d = CGAL::squared_distance(get(uvmap, x), P2(u, v));
            if (d < bd && !used.count(int(x.idx()))) { bd = d; best = int(x.idx()); }
          }
          used.insert(best);
          c.pairs.push_back({best, lift(u, v)});
        }
        c.expected_regions = genus0_regions(c.curves, {}, with_boundary ? 1 : 0);
        c.regions_note = with_boundary ? "E - V + C (network contains the disc's boundary)" : "E - V + 1 + C (curves inside the disc)";
        c.note = std::string("height field ") + H.name + " over the template's mean-value parameterisation onto the unit square";
        c.quick = c.name == "open-plane-saddle-boundary" || c.name == "open-patch-01-wave-inner" ||
                  c.name == "open-mesh_with_border-wave-boundary";
        bat.cases.push_back(std::move(c));
      }
    }
  }
}

Mesh torus_mesh(int nphi, int ntheta, const std::function<P(double, double)>& f) {
  Mesh m;
  for (int i = 0; i < nphi; ++i)
    for (int j = 0; j < ntheta; ++j) m.add_vertex(f(2 * pi * i / nphi, 2 * pi * j / ntheta));
  auto id = [&](int i, int j) { return vd(unsigned(((i + nphi) % nphi) * ntheta + (j + ntheta) % ntheta)); };
  for (int i = 0; i < nphi; ++i)
    for (int j = 0; j < ntheta; ++j) {
      m.add_face(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      m.add_face(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  return m;
}

void torus_family(Battery& bat) {
  auto base = [](double phi, double th) {
    const double R = 1.0, r = 0.35;
    return P((R + r * std::cos(th)) * std::cos(phi), (R + r * std::cos(th)) * std::sin(phi), r * std::sin(th));
  };
  auto deformed = [](double phi, double th) {
    const double R = 1.0, r = 0.35 * (1 + 0.25 * std::cos(3 * phi));
    return P(1.2 * (R + r * std::cos(th)) * std::cos(phi), 0.9 * (R + r * std::cos(th)) * std::sin(phi),
             1.1 * r * std::sin(th) + 0.1 * std::sin(2 * phi));
  };
  Case c;
  c.name = "torus";
  c.family = "torus onto a deformed torus";
  c.tmpl = torus_mesh(48, 16, base);
  c.truth = torus_mesh(240, 80, deformed);
  {  // outward orientation (checked on face 0); the truth is built the same way
    const fd f0 = *c.tmpl.faces().begin();
    std::vector<P> p;
    for (vd v : c.tmpl.vertices_around_face(c.tmpl.halfedge(f0))) p.push_back(c.tmpl.point(v));
    const V3 n = CGAL::cross_product(p[1] - p[0], p[2] - p[0]);
    const P ctr = CGAL::centroid(p[0], p[1], p[2]);
    const double phi = std::atan2(ctr.y(), ctr.x());
    const V3 out = ctr - P(std::cos(phi), std::sin(phi), 0);
    if (n * out < 0) {
      PMP::reverse_face_orientations(c.tmpl);
      PMP::reverse_face_orientations(c.truth);
    }
  }
  const std::vector<double> phis = {0.3, 0.3 + 2 * pi / 3, 0.3 + 4 * pi / 3}, thetas = {0.2, 0.2 + pi};
  const double step = 2 * pi / 48;
  for (double phi : phis) {  // meridian loops (around the tube)
    Polyline pl;
    std::vector<double> ts;
    const int n = 16;
    for (int k = 0; k < n; ++k) ts.push_back(0.05 + 2 * pi * k / n);
    for (double t : thetas) ts.erase(std::remove_if(ts.begin(), ts.end(), [&](double q) { return std::abs(std::remainder(q - t, 2 * pi)) < 0.3 * 2 * pi / n; }), ts.end());
    for (double t : thetas) ts.push_back(t);
    std::sort(ts.begin(), ts.end());
    for (double t : ts) pl.push_back(deformed(phi, t));
    pl.push_back(pl.front());
    c.curves.push_back(pl);
  }
  for (double th : thetas) {  // longitude loops (around the axis)
    Polyline pl;
    std::vector<double> ts;
    for (int k = 0; k < 48; ++k) ts.push_back(0.01 + k * step);
    for (double t : phis) ts.erase(std::remove_if(ts.begin(), ts.end(), [&](double q) { return std::abs(std::remainder(q - t, 2 * pi)) < 0.3 * step; }), ts.end());
    for (double t : phis) ts.push_back(t);
    std::sort(ts.begin(), ts.end());
    for (double t : ts) pl.push_back(deformed(t, th));
    pl.push_back(pl.front());
    c.curves.push_back(pl);
  }
  for (double phi : phis)
    for (double th : thetas) {
      // template vertex nearest in parameter space
      const int i = int(std::lround(phi / (2 * pi / 48))) % 48, j = int(std::lround(th / (2 * pi / 16))) % 16;
      c.pairs.push_back({i * 16 + j, deformed(phi, th)});
    }
  Network_counts nc;
  genus0_regions(c.curves, {}, 0, &nc);
  c.expected_regions = nc.E - nc.V;  // torus, cellular embedding: V - E + F = 0
  c.regions_note = "torus: V - E + F = 0 for a cellular embedding (3 meridians x 2 longitudes cut it into 3 x 2 = 6 discs), F = E - V = " +
                   std::to_string(nc.E - nc.V);
  c.note = "48x16 torus (R=1, r=0.35) onto a torus with varying tube radius, scaled and warped";
  c.quick = true;
  bat.cases.push_back(std::move(c));
}

// ---------------------------------------------------------------------- variants

struct Variant {
  std::string suffix;
  std::string what;
  std::function<P(const P&)> map;
};

std::vector<Variant> variants_for(const std::string& name, size_t index) {
  std::vector<Variant> v;
  if (index % 2 == 0) {
    std::mt19937_64 rng(fnv(name));
    // uniform random rotation (Shoemake)
    const double u1 = to_unit(rng()), u2 = to_unit(rng()), u3 = to_unit(rng());
    const double a = std::sqrt(1 - u1) * std::sin(2 * pi * u2), b = std::sqrt(1 - u1) * std::cos(2 * pi * u2);
    const double cc = std::sqrt(u1) * std::sin(2 * pi * u3), d = std::sqrt(u1) * std::cos(2 * pi * u3);
    const double w = d, x = a, y = b, z = cc;
    const double R[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    std::ostringstream os;
    os << "random rotation (quaternion " << w << " " << x << " " << y << " " << z << ")";
    v.push_back({"rot", os.str(), [R](const P& p) {
                   return P(R[0][0] * p.x() + R[0][1] * p.y() + R[0][2] * p.z(),
                            R[1][0] * p.x() + R[1][1] * p.y() + R[1][2] * p.z(),
                            R[2][0] * p.x() + R[2][1] * p.y() + R[2][2] * p.z());
                 }});
  } else {
    const int axis = int((index / 2) % 3);
    v.push_back({"rot", std::string("exact 180-degree turn about the ") + "xyz"[axis] + " axis", [axis](const P& p) {
                   if (axis == 0) return P(p.x(), -p.y(), -p.z());
                   if (axis == 1) return P(-p.x(), p.y(), -p.z());
                   return P(-p.x(), -p.y(), p.z());
                 }});
  }
  v.push_back({"t1e6", "translated by (1e6, 1e6, 1e6)", [](const P& p) { return P(p.x() + 1e6, p.y() + 1e6, p.z() + 1e6); }});
  v.push_back({"s1e-4", "scaled by 1e-4 about the origin", [](const P& p) { return P(p.x() * 1e-4, p.y() * 1e-4, p.z() * 1e-4); }});
  v.push_back({"s1e4", "scaled by 1e4 about the origin", [](const P& p) { return P(p.x() * 1e4, p.y() * 1e4, p.z() * 1e4); }});
  return v;
}

void write_case_txt(const fs::path& dir, const Case& c, const std::string& variant, const std::string& base) {
  std::ofstream o(dir / "case.txt");
  Network_counts nc;
  genus0_regions(c.curves, {}, 0, &nc);
  o << "name " << dir.filename().string() << "\n"
    << "base " << base << "\n"
    << "kind " << c.kind << "\n"
    << "family " << c.family << "\n"
    << "expected_regions " << c.expected_regions << "\n"
    << "impossible " << (c.impossible ? 1 : 0) << "\n"
    << "template_vertices " << c.tmpl.number_of_vertices() << "\n"
    << "template_faces " << c.tmpl.number_of_faces() << "\n"
    << "network_vertices " << nc.V << "\n"
    << "network_segments " << nc.E << "\n"
    << "network_components " << nc.C << "\n"
    << "pairs " << c.pairs.size() << "\n"
    << "variant " << (variant.empty() ? "none" : variant) << "\n"
    << "regions_note " << c.regions_note << "\n"
    << "note " << c.note << "\n";
}

// A known answer for the scorer: an icosphere whose network runs along its own edges (the 30
// subdivided edges of the icosahedron, 20 regions). The template itself must pass; the same mesh
// with the positions of two vertices of one face swapped must show an inverted face.
void write_selftest(const fs::path& out) {
  const Mesh tmpl = icosphere(4);
  const Mesh base = icosphere(0);
  std::vector<Polyline> curves;
  for (ed e : base.edges()) {
    const V3 a = vec(base.point(base.vertex(e, 0))), b = vec(base.point(base.vertex(e, 1)));
    const V3 n = unit(CGAL::cross_product(a, b));
    const double ang = std::acos(a * b);
    std::vector<std::pair<double, P>> on;
    for (vd v : tmpl.vertices()) {
      const V3 p = vec(tmpl.point(v));
      if (std::abs(p * n) > 1e-9) continue;
      const double ta = std::acos(std::clamp(p * a, -1.0, 1.0)), tb = std::acos(std::clamp(p * b, -1.0, 1.0));
      if (std::abs(ta + tb - ang) < 1e-9) on.push_back({ta, tmpl.point(v)});
    }
    std::sort(on.begin(), on.end(), [](auto& x, auto& y) { return x.first < y.first; });
    Polyline pl;
    for (auto& q : on) pl.push_back(q.second);
    curves.push_back(pl);
  }
  Case c;
  c.name = "selftest";
  c.family = "scorer self-test";
  c.tmpl = tmpl;
  c.truth = radial_truth(sphere_r);
  c.curves = curves;
  c.expected_regions = genus0_regions(curves, {}, 0);
  c.regions_note = "E - V + 1 + C: the icosahedron's 20 faces";
  c.note = "network along the template's own edges";
  const fs::path d = out / "selftest";
  fs::create_directories(d);
  write_off(d / "template.off", c.tmpl);
  write_off(d / "truth.off", c.truth);
  write_curves(d / "curves.polylines.txt", c.curves, c.note);
  write_pairs(d / "pairs.txt", {});
  write_case_txt(d, c, "", c.name);
  Mesh swapped = tmpl;
  const fd f0 = *swapped.faces().begin();
  const hd h = swapped.halfedge(f0);
  const vd b = swapped.target(h), cc = swapped.target(swapped.next(h));
  std::swap(swapped.point(b), swapped.point(cc));
  write_off(d / "swapped.off", swapped);
}

// A base case's files in `d`: template, truth, curves, pairs and case.txt.
void write_case(const fs::path& d, const Case& c) {
  fs::create_directories(d);
  write_off(d / "template.off", c.tmpl);
  write_off(d / "truth.off", c.truth);
  write_curves(d / "curves.polylines.txt", c.curves, c.name + ": " + c.note);
  write_pairs(d / "pairs.txt", c.pairs);
  write_case_txt(d, c, "", c.name);
}

// Scale cases (issue 12): icosphere templates of 81 920, 327 680 and 1 310 720 faces onto the bumpy
// blob with a latitude/longitude network of about 2 000, 6 000 and 20 000 vertices, the template
// under a random rotation. Written by `make_battery --scale OUTDIR`.
void scale_family(Battery& bat) {
  const std::vector<std::pair<int, std::size_t>> sizes = {{6, 2000}, {7, 6000}, {8, 20000}};
  const auto circles = latlong_circles();
  for (auto [level, target] : sizes) {
    Case c;
    c.tmpl = icosphere(level);
    c.name = "scale-ico" + std::to_string(c.tmpl.number_of_faces()) + "-bumpy-latlong" + std::to_string(target);
    c.family = "scale: icosphere onto the bumpy blob";
    c.truth = radial_truth(bumpy_r);
    // The spacing that gives about `target` network vertices: count at a first spacing, rescale.
    auto vertices_at = [&](double spacing) {
      Network_counts nc;
      genus0_regions(circle_network(circles, bumpy_r, spacing).curves, {}, 0, &nc);
      return static_cast<double>(nc.V);
    };
    const double first = 0.05, spacing = first * vertices_at(first) / static_cast<double>(target);
    const Sphere_network net = circle_network(circles, bumpy_r, spacing);
    c.curves = net.curves;
    c.pairs = sphere_pairs(c.tmpl, net, bumpy_r, 8);
    c.expected_regions = genus0_regions(c.curves, {}, 0);
    c.regions_note = "E - V + 1 + C (closed genus 0)";
    const Variant rotation = variants_for(c.name, 0).front();
    for (vd x : c.tmpl.vertices()) c.tmpl.point(x) = rotation.map(c.tmpl.point(x));
    c.note = "curve spacing " + std::to_string(spacing) + " rad; template " + rotation.what;
    bat.cases.push_back(std::move(c));
  }
}

}  // namespace

int main(int argc, char** argv) {
  const char* usage = "usage: make_battery OUTDIR [CGAL_MESH_DIR]\n       make_battery --scale OUTDIR\n";
  // An option other than --scale (--help, say) is not taken for the folder to write 270 cases in.
  if (argc < 2 || argc > 3 || (argv[1][0] == '-' && std::string(argv[1]) != "--scale")) {
    std::cerr << usage;
    return argc > 1 && std::string(argv[1]) == "--help" ? 0 : 2;
  }
  try {
    if (std::string(argv[1]) == "--scale") {
      if (argc != 3) {
        std::cerr << usage;
        return 2;
      }
      const fs::path out = argv[2];
      fs::create_directories(out);
      Battery bat;
      scale_family(bat);
      std::ofstream list(out / "cases.txt");
      for (const Case& c : bat.cases) {
        write_case(out / c.name, c);
        list << c.name << "\n";
        std::cerr << "make_battery: " << c.name << "\n";
      }
      return 0;
    }
    const fs::path out = argv[1];
    const std::string meshes = argc == 3 ? argv[2] : "";
    fs::create_directories(out);
    Battery bat;
    analytic_family(bat);
    pairs_family(bat);
    torus_family(bat);
    impossible_family(bat);
    real_family(bat, meshes);
    open_family(bat, meshes);
    write_selftest(out);
    std::ofstream list(out / "cases.txt");
    list << "# name quick base variant\n";
    for (size_t i = 0; i < bat.cases.size(); ++i) {
      const Case& c = bat.cases[i];
      write_case(out / c.name, c);
      list << c.name << " " << (c.quick ? 1 : 0) << " " << c.name << " none\n";
      for (const Variant& v : variants_for(c.name, i)) {
        const std::string vn = c.name + "@" + v.suffix;
        const fs::path vd_ = out / vn;
        fs::create_directories(vd_);
        Mesh t = c.tmpl;
        for (vd x : t.vertices()) t.point(x) = v.map(t.point(x));
        write_off(vd_ / "template.off", t);
        for (const char* f : {"curves.polylines.txt", "pairs.txt", "truth.off"}) {
          fs::remove(vd_ / f);
          fs::create_symlink(fs::path("..") / c.name / f, vd_ / f);
        }
        Case meta;
        meta.kind = c.kind;
        meta.family = c.family;
        meta.expected_regions = c.expected_regions;
        meta.regions_note = c.regions_note;
        meta.impossible = c.impossible;
        meta.curves = c.curves;
        meta.pairs = c.pairs;
        meta.tmpl = t;
        meta.note = c.note + "; template " + v.what;
        write_case_txt(vd_, meta, v.what, c.name);
        const bool quick = (c.name == "ico162-superellipsoid-great" && (v.suffix == "rot" || v.suffix == "s1e-4")) ||
                           (c.name == "ico2562-bumpy-latlong" && v.suffix == "t1e6");
        list << vn << " " << (quick ? 1 : 0) << " " << c.name << " " << v.suffix << "\n";
      }
      std::cerr << "make_battery: " << c.name << " (" << c.tmpl.number_of_faces() << " faces, " << c.curves.size()
                << " polylines, " << c.pairs.size() << " pairs, expected regions " << c.expected_regions << ")\n";
    }
    for (const std::string& s : bat.skipped) std::cerr << "make_battery: skipped " << s << "\n";
    std::ofstream sk(out / "skipped.txt");
    for (const std::string& s : bat.skipped) sk << s << "\n";
  } catch (const std::exception& e) {
    std::cerr << "make_battery: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
