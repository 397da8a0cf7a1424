// make_example_data.cpp -- generates the example input data of meshfit.
//
// Usage: make_example_data <output_dir>
//
// Writes three deterministic text files into <output_dir>:
//   template.off           icosphere of radius 1 (icosahedron subdivided 4 times), the template mesh;
//   curves.polylines.txt   four closed plane sections of a "shoe-last-like" ellipsoid
//                          x^2/2^2 + y^2/0.8^2 + z^2/0.7^2 = 1, as CGAL polylines, sharing their
//                          mutual intersection points bitwise so that they form a curve network;
//   pairs.txt              8 correspondences "template vertex index -> network point".
// The files in examples/data are the committed output of this program (see examples/data/README.md).
// It uses only the standard library on purpose, so that the data can be regenerated without the
// dependencies of meshfit itself. Every self-check failure exits non-zero with a message.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
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

Vec cross(const Vec& p, const Vec& q) {
  return {p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]};
}
Vec times(const Vec& p, const Vec& q) { return {p[0] * q[0], p[1] * q[1], p[2] * q[2]}; }
Vec divided(const Vec& p, const Vec& q) { return {p[0] / q[0], p[1] / q[1], p[2] / q[2]}; }

// Semi-axes of the target ellipsoid (length along x, width along y, height along z).
const Vec kAxes{2.0, 0.8, 0.7};
constexpr std::size_t kPairCount = 8;

// ---- template mesh ------------------------------------------------------------------------------

Mesh make_icosphere(int subdivisions) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  Mesh m;
  for (const Vec& v : std::vector<Vec>{{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                       {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                       {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}})
    m.vertices.push_back(normalized(v));
  m.faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    // Keyed by the sorted pair so that both faces sharing an edge get the same midpoint vertex.
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int i, int j) {
      const auto key = std::minmax(i, j);
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      m.vertices.push_back(normalized(m.vertices[i] + m.vertices[j]));
      const int id = static_cast<int>(m.vertices.size()) - 1;
      midpoint.emplace(key, id);
      return id;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& f : m.faces) {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      // Same cyclic order as the parent face, so the orientation is inherited.
      finer.push_back({f[0], ab, ca});
      finer.push_back({f[1], bc, ab});
      finer.push_back({f[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    m.faces = std::move(finer);
  }
  return m;
}

// Closed, edge-manifold, consistently and outward oriented, genus 0, all on the unit sphere.
void check_template(const Mesh& m) {
  require(m.vertices.size() == 2562 && m.faces.size() == 5120, "icosphere has unexpected size");
  std::set<std::pair<int, int>> directed;
  std::vector<bool> used(m.vertices.size(), false);
  for (const auto& f : m.faces) {
    for (int k = 0; k < 3; ++k) {
      require(directed.insert({f[k], f[(k + 1) % 3]}).second, "directed edge used twice");
      used[f[k]] = true;
    }
    const Vec& a = m.vertices[f[0]];
    const Vec n = cross(m.vertices[f[1]] - a, m.vertices[f[2]] - a);
    require(dot(n, a + m.vertices[f[1]] + m.vertices[f[2]]) > 0.0, "face is not oriented outward");
  }
  for (const auto& e : directed)
    require(directed.count({e.second, e.first}) == 1, "border or inconsistently oriented edge");
  const long euler = static_cast<long>(m.vertices.size()) - static_cast<long>(directed.size() / 2) +
                     static_cast<long>(m.faces.size());
  require(euler == 2, "Euler characteristic is not 2");
  require(std::all_of(used.begin(), used.end(), [](bool u) { return u; }), "isolated vertex");
  for (const Vec& v : m.vertices) require(std::abs(norm(v) - 1.0) < 1e-12, "vertex off the sphere");
}

// ---- curve network ------------------------------------------------------------------------------

// Plane n.x = d with |n| = 1, and an exact parameterisation of its section of the ellipsoid.
// In scaled coordinates u = x / axes the ellipsoid is the unit sphere and the section a circle,
// so x(t) = axes * (u0 + r (cos t e1 + sin t e2)) is exact and its parameter is recoverable.
struct Section {
  std::string name;
  Vec n;
  double d;
  Vec u0, e1, e2;
  double r;

  Section(std::string name_, const Vec& normal, const Vec& through)
      : name(std::move(name_)), n(normalized(normal)), d(dot(n, through)) {
    const Vec m = times(n, kAxes);  // plane normal in scaled coordinates: m.u = d
    const double mm = dot(m, m);
    require(d * d < mm, name + " plane misses the ellipsoid");
    u0 = (d / mm) * m;
    r = std::sqrt(1.0 - d * d / mm);
    const Vec mh = normalized(m);
    const Vec helper = std::abs(mh[0]) < 0.9 ? Vec{1, 0, 0} : Vec{0, 1, 0};
    e1 = normalized(cross(mh, helper));
    e2 = cross(mh, e1);
  }
  // The final projection removes the rounding off the plane, so that e.g. every sole point has
  // z == -0.25 exactly; it moves the point by ~1e-16, far inside the ellipsoid tolerance.
  Vec at(double t) const {
    const Vec p = times(kAxes, u0 + r * (std::cos(t) * e1 + std::sin(t) * e2));
    return p - (dot(n, p) - d) * n;
  }
  double param(const Vec& p) const {  // in [0, 2 pi)
    const Vec w = divided(p, kAxes) - u0;
    const double t = std::atan2(dot(w, e2), dot(w, e1));
    return t < 0.0 ? t + 2.0 * kPi : t;
  }
};

void check_on_section(const Vec& p, const Section& s) {
  const double f = dot(divided(p, kAxes), divided(p, kAxes));
  require(std::abs(f - 1.0) <= 1e-12, "point " + fmt(p) + " is off the ellipsoid");
  require(std::abs(dot(s.n, p) - s.d) <= 1e-12 * std::max(1.0, norm(p)),
          "point " + fmt(p) + " is off the " + s.name + " plane");
}

// The 0 or 2 points where the line common to both planes pierces the ellipsoid.
std::vector<Vec> intersect(const Section& s1, const Section& s2) {
  const Vec dir = cross(s1.n, s2.n);
  const double dd = dot(dir, dir);
  if (dd < 1e-20) return {};  // parallel planes
  const Vec p0 = (1.0 / dd) * (s1.d * cross(s2.n, dir) + s2.d * cross(dir, s1.n));
  const Vec q = divided(p0, kAxes), w = divided(dir, kAxes);
  const double A = dot(w, w), B = 2.0 * dot(q, w), C = dot(q, q) - 1.0;
  const double disc = B * B - 4.0 * A * C;
  if (disc <= 0.0) return {};
  // A near-tangency would make the two points (almost) coincide: not a usable network vertex.
  require(disc > 1e-8 * (B * B + std::abs(4.0 * A * C)), s1.name + " and " + s2.name + " nearly tangent");
  // Cancellation-free quadratic roots.
  const double h = -0.5 * (B + std::copysign(std::sqrt(disc), B));
  return {p0 + (h / A) * dir, p0 + (C / h) * dir};
}

struct CurvePoint {
  double t;
  Vec p;
};

// Roughly uniform arc-length samples (target spacing 0.15, 48..72 points) with the intersection
// points inserted and the samples too close to them dropped, ordered along the curve.
std::vector<Vec> sample(const Section& s, const std::vector<Vec>& features) {
  const int fine = 20000;
  std::vector<double> arc(fine + 1, 0.0);
  for (int k = 1; k <= fine; ++k)
    arc[k] = arc[k - 1] + norm(s.at(2.0 * kPi * k / fine) - s.at(2.0 * kPi * (k - 1) / fine));
  const int count = std::clamp(static_cast<int>(std::lround(arc[fine] / 0.15)), 48, 72);
  const double spacing = arc[fine] / count;
  std::vector<CurvePoint> pts;
  for (const Vec& f : features) pts.push_back({s.param(f), f});
  for (int i = 0, k = 0; i < count; ++i) {
    const double target = i * spacing;
    while (arc[k + 1] < target) ++k;
    const double t = 2.0 * kPi * (k + (target - arc[k]) / (arc[k + 1] - arc[k])) / fine;
    const Vec p = s.at(t);
    const bool near_feature = std::any_of(features.begin(), features.end(),
                                          [&](const Vec& f) { return norm(f - p) < 0.25 * spacing; });
    if (!near_feature) pts.push_back({t, p});
  }
  std::sort(pts.begin(), pts.end(), [](const CurvePoint& a, const CurvePoint& b) { return a.t < b.t; });
  std::vector<Vec> out;
  for (const CurvePoint& c : pts) out.push_back(c.p);
  out.push_back(out.front());  // closed polyline
  return out;
}

// ---- correspondences ----------------------------------------------------------------------------

// The natural ellipsoid-to-sphere map: nearest template vertex to the direction of p / axes.
int nearest_vertex(const Mesh& m, const Vec& p) {
  const Vec dir = normalized(divided(p, kAxes));
  int best = 0;
  for (int i = 1; i < static_cast<int>(m.vertices.size()); ++i)
    if (dot(m.vertices[i], dir) > dot(m.vertices[best], dir)) best = i;
  return best;
}

// Non-coplanar with a margin (1e-3 of the extent), because near-coplanar pairs are as useless
// for anchoring a fit as exactly coplanar ones.
bool coplanar(const std::vector<Vec>& pts) {
  auto farthest = [&](auto dist) {
    return *std::max_element(pts.begin(), pts.end(), [&](const Vec& a, const Vec& b) { return dist(a) < dist(b); });
  };
  const Vec a = pts[0];
  const Vec b = farthest([&](const Vec& p) { return norm(p - a); });
  const double extent = norm(b - a);
  const Vec c = farthest([&](const Vec& p) { return norm(cross(p - a, b - a)); });
  const Vec n = cross(b - a, c - a);
  if (norm(n) < 1e-3 * extent * extent) return true;  // all collinear
  const Vec d = farthest([&](const Vec& p) { return std::abs(dot(p - a, normalized(n))); });
  return std::abs(dot(d - a, normalized(n))) < 1e-3 * extent;
}

int run(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);

  const Mesh mesh = make_icosphere(4);
  check_template(mesh);
  std::ostringstream off;
  off << "OFF\n" << mesh.vertices.size() << ' ' << mesh.faces.size() << " 0\n";
  for (const Vec& v : mesh.vertices) off << fmt(v) << '\n';
  for (const auto& f : mesh.faces) off << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';

  const std::vector<Section> sections{
      {"sole", {0, 0, 1}, {0, 0, -0.25}},
      {"collar", {-0.12, 0, 1}, {-0.9, 0, 0.45}},
      {"centre line", {0, 1, 0}, {0, 0, 0}},
      {"cross section", {1, 0, 0}, {0.3, 0, 0}}};

  // Each intersection point is computed once and the same double triple goes into both curves.
  std::vector<Vec> features;
  std::vector<std::vector<Vec>> on_curve(sections.size());
  for (std::size_t i = 0; i < sections.size(); ++i)
    for (std::size_t j = i + 1; j < sections.size(); ++j)
      for (const Vec& p : intersect(sections[i], sections[j])) {
        check_on_section(p, sections[i]);
        check_on_section(p, sections[j]);
        features.push_back(p);
        on_curve[i].push_back(p);
        on_curve[j].push_back(p);
      }
  // Triple points would be computed twice, slightly differently: this generator does not handle them.
  for (std::size_t i = 0; i < features.size(); ++i)
    for (std::size_t j = i + 1; j < features.size(); ++j)
      require(norm(features[i] - features[j]) > 1e-6, "two intersection points (almost) coincide");

  std::ostringstream curves;
  curves << "# meshfit example curve network: closed plane sections of the ellipsoid x^2/2^2 + y^2/0.8^2 + z^2/0.7^2 = 1\n"
         << "# in this order: sole z=-0.25, collar (plane through (-0.9,0,0.45), normal (-0.12,0,1)), centre line y=0, cross section x=0.3\n"
         << "# one closed polyline per line (first point repeated); curves share their " << features.size()
         << " intersection points bitwise\n";
  std::map<std::string, int> uses;  // point text -> number of polylines containing it
  std::vector<std::vector<Vec>> polylines;
  for (std::size_t i = 0; i < sections.size(); ++i) {
    polylines.push_back(sample(sections[i], on_curve[i]));
    const std::vector<Vec>& line = polylines.back();
    curves << line.size();
    for (const Vec& p : line) {
      check_on_section(p, sections[i]);
      curves << ' ' << fmt(p);
    }
    curves << '\n';
    for (std::size_t k = 0; k + 1 < line.size(); ++k) ++uses[fmt(line[k])];
  }
  for (const Vec& f : features) require(uses[fmt(f)] == 2, "intersection point not shared by exactly 2 curves");
  require(uses.size() == static_cast<std::size_t>(std::count_if(uses.begin(), uses.end(), [](const auto& u) {
            return u.second == 1;
          })) + features.size(),
          "a non-intersection point appears in several curves");

  // Pairs: greedy farthest-point choice among the feature points (the network's corners), then
  // among curve extremes if there are too few; a candidate mapping to a used vertex is skipped.
  std::vector<Vec> extremes;
  for (const auto& line : {polylines[2], polylines[3]})
    for (int axis = 0; axis < 3; ++axis) {
      auto cmp = [axis](const Vec& p, const Vec& q) { return p[axis] < q[axis]; };
      extremes.push_back(*std::max_element(line.begin(), line.end(), cmp));
      extremes.push_back(*std::min_element(line.begin(), line.end(), cmp));
    }
  std::vector<Vec> chosen;
  std::vector<int> chosen_vertex;
  for (std::vector<Vec> pool : {features, extremes}) {
    while (chosen.size() < kPairCount && !pool.empty()) {
      auto score = [&](const Vec& p) {  // first pick: largest x; then farthest from the chosen
        double s = chosen.empty() ? p[0] : std::numeric_limits<double>::infinity();
        for (const Vec& c : chosen) s = std::min(s, norm(p - c));
        return s;
      };
      auto best = std::max_element(pool.begin(), pool.end(),
                                   [&](const Vec& p, const Vec& q) { return score(p) < score(q); });
      const Vec p = *best;
      pool.erase(best);
      const int v = nearest_vertex(mesh, p);
      if (std::find(chosen_vertex.begin(), chosen_vertex.end(), v) != chosen_vertex.end()) continue;
      chosen.push_back(p);
      chosen_vertex.push_back(v);
    }
  }
  require(chosen.size() == kPairCount, "could not choose 8 pairs with distinct template vertices");
  std::vector<Vec> template_points;
  for (int v : chosen_vertex) template_points.push_back(mesh.vertices[v]);
  require(!coplanar(chosen), "the chosen network points are coplanar");
  require(!coplanar(template_points), "the chosen template vertices are coplanar");
  std::ostringstream pairs;
  pairs << "# template_vertex_index x y z (a point of curves.polylines.txt, same text); " << kPairCount
        << " pairs, nearest icosphere vertex to normalised (x/2, y/0.8, z/0.7)\n";
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    require(uses.count(fmt(chosen[k])) == 1, "pair point is not a network point");
    pairs << chosen_vertex[k] << ' ' << fmt(chosen[k]) << '\n';
  }

  write_file(dir / "template.off", off.str());
  write_file(dir / "curves.polylines.txt", curves.str());
  write_file(dir / "pairs.txt", pairs.str());
  std::cout << "make_example_data: template " << mesh.vertices.size() << " vertices " << mesh.faces.size()
            << " faces; " << polylines.size() << " polylines, " << uses.size() << " network points, "
            << features.size() << " intersection points; " << chosen.size() << " pairs\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_example_data <output_dir>\n";
    return 2;
  }
  try {
    return run(argv[1]);
  } catch (const std::exception& e) {
    std::cerr << "make_example_data: " << e.what() << '\n';
    return 1;
  }
}
