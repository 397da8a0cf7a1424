// An independent oracle for fitted meshes (issue 15): what the battery's scorer (score_fit.cpp)
// and the tests (test/) check a fit or a partition with, using CGAL alone. It includes no meshfit
// header and calls no meshfit code, so a bug in meshfit's own verification cannot certify
// meshfit's results: score_fit, which links CGAL only, would not compile if it did.
//
// The network is taken as points (polylines of CGAL points, merged within 1e-9 times the
// network's bounding-box diagonal), the result as a CGAL::Surface_mesh over Epick (copy_of
// copies any other FaceGraph). Checked: every network vertex at an output vertex, every segment
// a chain of output edges found greedily along it, regions by flood fill across those chains,
// zero-area faces, folded edges (adjacent faces more than 90 degrees apart) and intersecting face
// pairs (CGAL::Polygon_mesh_processing::self_intersections) against the template's, angles, and,
// for the battery, faces inverted against a ground truth and the Hausdorff distance to it.
#ifndef MESHFIT_BENCH_FIT_ORACLE_H
#define MESHFIT_BENCH_FIT_ORACLE_H

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace fit_oracle {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point_3 = K::Point_3;
using Vector_3 = K::Vector_3;
using Mesh = CGAL::Surface_mesh<Point_3>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_face_graph_triangle_primitive<Mesh>>>;
using Polylines = std::vector<std::vector<Point_3>>;

constexpr double pi = 3.14159265358979323846;

inline double diagonal(const CGAL::Bbox_3& b) {
  return std::sqrt(CGAL::square(b.xmax() - b.xmin()) + CGAL::square(b.ymax() - b.ymin()) +
                   CGAL::square(b.zmax() - b.zmin()));
}

/// Points merged within `tol` (a uniform grid of cell `tol`, 27 neighbouring cells searched).
struct Point_index {
  double cell;
  std::map<std::array<long long, 3>, std::vector<int>> grid;
  std::vector<Point_3> pts;
  explicit Point_index(double c) : cell(c) {}
  std::array<long long, 3> key(const Point_3& p) const {
    // Clamped before the conversion, which is undefined out of range (an unused vertex at 1e80).
    auto k = [this](double x) {
      const double c = std::floor(x / cell);
      return c == c ? (long long)std::clamp(c, -9e18, 9e18) : 0LL;
    };
    return {k(p.x()), k(p.y()), k(p.z())};
  }
  /// The nearest point within `tol` of `p`, -1 if none.
  int find(const Point_3& p, double tol) const {
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
  int insert(const Point_3& p) {
    pts.push_back(p);
    grid[key(p)].push_back(int(pts.size()) - 1);
    return int(pts.size()) - 1;
  }
};

struct Union_find {
  std::vector<int> p;
  explicit Union_find(std::size_t n) : p(n) { for (std::size_t i = 0; i < n; ++i) p[i] = int(i); }
  int find(int x) { while (p[x] != x) x = p[x] = p[p[x]]; return x; }
  void unite(int a, int b) { p[find(a)] = find(b); }
};

/// A copy of any triangulated FaceGraph whose points have x(), y(), z() (Polyhedron_3, a
/// Surface_mesh of another kernel) as an oracle mesh: its vertices in the order of vertices(g).
template <typename FaceGraph>
Mesh copy_of(const FaceGraph& g) {
  Mesh m;
  std::map<typename boost::graph_traits<FaceGraph>::vertex_descriptor, Mesh::Vertex_index> at;
  for (auto v : vertices(g)) {
    const auto& p = get(CGAL::vertex_point, g, v);
    at[v] = m.add_vertex(Point_3(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())));
  }
  for (auto f : faces(g)) {
    std::vector<Mesh::Vertex_index> c;
    for (auto v : CGAL::vertices_around_face(halfedge(f, g), g)) c.push_back(at.at(v));
    m.add_face(c);
  }
  return m;
}

/// The polylines of a CGAL polylines file (`n x1 y1 z1 ... xn yn zn` a line, `#` comments).
/// \throws std::runtime_error when the file cannot be read or a line is short.
inline Polylines read_polylines(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  Polylines out;
  std::string line;
  while (std::getline(in, line)) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream is(line);
    std::size_t n = 0;
    is >> n;
    std::vector<Point_3> pl;
    for (std::size_t i = 0; i < n; ++i) {
      double x, y, z;
      if (!(is >> x >> y >> z)) throw std::runtime_error(path + ": short polyline");
      pl.emplace_back(x, y, z);
    }
    out.push_back(pl);
  }
  return out;
}

/// The network's vertices and segments from its polylines: points merged within 1e-9 times the
/// bounding-box diagonal of all points, each segment once (a closed polyline repeats its first point).
struct Network {
  std::vector<Point_3> points;
  std::set<std::pair<int, int>> segments;  ///< (smaller, larger) index into points
  double diagonal = 0;                     ///< of the points' bounding box
  double tolerance = 0;                    ///< 1e-9 * diagonal: merging, and finding output vertices
};

inline Network network_of(const Polylines& polylines) {
  Network n;
  CGAL::Bbox_3 nb;
  for (auto& pl : polylines)
    for (auto& p : pl) nb += p.bbox();
  n.diagonal = diagonal(nb);
  n.tolerance = 1e-9 * n.diagonal;
  Point_index index(std::max(n.tolerance, 1e-300));
  for (auto& pl : polylines) {
    int prev = -1;
    for (auto& p : pl) {
      int id = index.find(p, n.tolerance);
      if (id < 0) id = index.insert(p);
      if (prev >= 0 && prev != id) n.segments.emplace(std::min(prev, id), std::max(prev, id));
      prev = id;
    }
  }
  n.points = std::move(index.pts);
  return n;
}

/// How the network lies on a mesh.
struct Embedding {
  std::vector<int> vertex_at;   ///< per network vertex, the output vertex within the tolerance (-1: none)
  long missing = 0;             ///< network vertices at no output vertex
  long not_chained = 0;         ///< segments that are no chain of output edges
  std::vector<char> chain_edge; ///< per edge index of the mesh: on a segment's chain
  long regions = 0;             ///< faces joined across edges that are no chain edge
};

/// Where the network's vertices are on `out`, which segments are chains of its edges and the
/// regions those chains bound. A segment ab is a chain when, from a's vertex, stepping each time
/// to the neighbour on the segment (within 1e-6 |ab| + the network's tolerance) nearest along
/// it but further than the current vertex (greedy, monotone) reaches b's vertex.
inline Embedding embedding(const Mesh& out, const Network& net) {
  using vd = Mesh::Vertex_index;
  using hd = Mesh::Halfedge_index;
  using ed = Mesh::Edge_index;
  Embedding r;
  const double tol = net.tolerance;
  // every network vertex at an output vertex
  Point_index outpts(std::max(tol, 1e-300));
  for (vd v : out.vertices()) outpts.insert(out.point(v));
  std::vector<vd> vertex_of;
  for (vd v : out.vertices()) vertex_of.push_back(v);
  r.vertex_at.assign(net.points.size(), -1);
  for (std::size_t i = 0; i < net.points.size(); ++i) {
    const int k = outpts.find(net.points[i], tol);
    r.vertex_at[i] = k < 0 ? -1 : int(vertex_of[std::size_t(k)].idx());
    if (k < 0) ++r.missing;
  }
  // every segment a chain of output edges on the segment, monotone from a to b
  r.chain_edge.assign(out.number_of_edges() + out.number_of_removed_edges(), 0);
  for (auto [ia, ib] : net.segments) {
    if (r.vertex_at[ia] < 0 || r.vertex_at[ib] < 0) { ++r.not_chained; continue; }
    const Point_3 a = net.points[ia], b = net.points[ib];
    const Vector_3 ab = b - a;
    const double l2 = ab.squared_length(), l = std::sqrt(l2);
    const double line_tol = 1e-6 * l + 1e-9 * net.diagonal;
    vd cur = vd(unsigned(r.vertex_at[ia]));
    const vd goal = vd(unsigned(r.vertex_at[ib]));
    double tcur = 0;
    std::vector<ed> chain;
    bool ok = true;
    while (cur != goal) {
      hd best;
      double bt = 1e300;
      for (hd h : CGAL::halfedges_around_source(cur, out)) {
        const Point_3& w = out.point(out.target(h));
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
    if (!ok) { ++r.not_chained; continue; }
    for (ed e : chain) r.chain_edge[e.idx()] = 1;
  }
  // regions: faces connected across edges that are not chain edges
  Union_find uf(out.number_of_faces() + out.number_of_removed_faces());
  for (ed e : out.edges()) {
    if (out.is_border(e) || r.chain_edge[e.idx()]) continue;
    const hd h = out.halfedge(e);
    uf.unite(int(out.face(h).idx()), int(out.face(out.opposite(h)).idx()));
  }
  std::set<int> roots;
  for (auto f : out.faces()) roots.insert(uf.find(int(f.idx())));
  r.regions = long(roots.size());
  return r;
}

/// The cross product of a face's edges from its halfedge's source (twice its area, along its normal).
inline Vector_3 face_normal(const Mesh& m, Mesh::Face_index f) {
  const auto h = m.halfedge(f);
  const Point_3& a = m.point(m.source(h));
  const Point_3& b = m.point(m.target(h));
  const Point_3& c = m.point(m.target(m.next(h)));
  return CGAL::cross_product(b - a, c - a);
}

/// Faces whose face_normal is the null vector.
inline long zero_area_faces(const Mesh& m) {
  long n = 0;
  for (auto f : m.faces()) n += face_normal(m, f).squared_length() == 0;
  return n;
}

/// Interior edges whose two faces' normals make more than 90 degrees.
inline long folded_edges(const Mesh& m) {
  long n = 0;
  for (auto e : m.edges()) {
    if (m.is_border(e)) continue;
    const auto h = m.halfedge(e);
    if (face_normal(m, m.face(h)) * face_normal(m, m.face(m.opposite(h))) < 0) ++n;
  }
  return n;
}

/// Pairs of faces that intersect (CGAL::Polygon_mesh_processing::self_intersections).
inline long self_intersections(const Mesh& m) {
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(m, std::back_inserter(pairs));
  return long(pairs.size());
}

/// Coordinates that are not finite.
inline long non_finite_coordinates(const Mesh& m) {
  long n = 0;
  for (auto v : m.vertices()) {
    const Point_3& p = m.point(v);
    n += !(std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()));
  }
  return n;
}

/// Every angle of every face in degrees, sorted (a corner on a zero-length edge counts 0).
inline std::vector<double> sorted_angles_deg(const Mesh& m) {
  std::vector<double> angles;
  for (auto f : m.faces()) {
    const auto h = m.halfedge(f);
    const Point_3 p[3] = {m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h)))};
    for (int k = 0; k < 3; ++k) {
      const Vector_3 u = p[(k + 1) % 3] - p[k], w = p[(k + 2) % 3] - p[k];
      const double lu = std::sqrt(u.squared_length()), lw = std::sqrt(w.squared_length());
      angles.push_back(lu == 0 || lw == 0 ? 0.0 : std::acos(std::clamp((u * w) / (lu * lw), -1.0, 1.0)) * 180 / pi);
    }
  }
  std::sort(angles.begin(), angles.end());
  return angles;
}

/// The centroid of a face.
inline Point_3 face_centroid(const Mesh& m, Mesh::Face_index f) {
  const auto h = m.halfedge(f);
  return CGAL::centroid(m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h))));
}

/// Faces of `out` (zero-area ones left out) whose normal points against that of the face of
/// `truth` closest to their centroid; `tree` is built on `truth`.
inline long faces_inverted_against(const Mesh& out, const Mesh& truth, const Tree& tree) {
  long inverted = 0;
  for (auto f : out.faces()) {
    const Vector_3 n = face_normal(out, f);
    if (n.squared_length() == 0) continue;
    const auto cp = tree.closest_point_and_primitive(face_centroid(out, f));
    if (face_normal(truth, cp.second) * n < 0) ++inverted;
  }
  return inverted;
}

/// Squared one-sided distances: the largest from `out`'s vertices and face centroids to the
/// truth (`truth_tree`), and the largest from the truth's vertices to `out` (`out_tree`).
struct Squared_hausdorff {
  double out_to_truth = 0, truth_to_out = 0;
};

inline Squared_hausdorff squared_hausdorff(const Mesh& out, const Tree& out_tree, const Mesh& truth,
                                           const Tree& truth_tree) {
  Squared_hausdorff d;
  for (auto v : out.vertices()) d.out_to_truth = std::max(d.out_to_truth, truth_tree.squared_distance(out.point(v)));
  for (auto f : out.faces()) d.out_to_truth = std::max(d.out_to_truth, truth_tree.squared_distance(face_centroid(out, f)));
  for (auto v : truth.vertices()) d.truth_to_out = std::max(d.truth_to_out, out_tree.squared_distance(truth.point(v)));
  return d;
}

/// The oracle's verdict on a fitted (or partitioned) mesh: the network on it, and what it adds
/// to the template's defects.
struct Fit_check {
  Embedding embedding;
  long network_vertices = 0, segments = 0;
  long expected_regions = -1;  ///< -1: not checked
  long zero_area_faces = 0;
  long folded_edges = 0, template_folded_edges = 0;
  bool self_intersections_checked = false;
  long self_intersecting_pairs = 0, template_self_intersecting_pairs = 0;
  long non_finite_coordinates = 0;
  double smallest_angle_deg = 0, angle_5th_percentile_deg = 0;  ///< over all corners

  long new_folds() const { return std::max(0L, folded_edges - template_folded_edges); }
  long new_self_intersections() const { return std::max(0L, self_intersecting_pairs - template_self_intersecting_pairs); }

  /// What is wrong, one sentence each; empty when everything holds.
  std::vector<std::string> problems() const {
    std::vector<std::string> p;
    auto n = [](long k) { return std::to_string(k); };
    if (embedding.missing)
      p.push_back(n(embedding.missing) + " of " + n(network_vertices) + " network vertices at no mesh vertex");
    if (embedding.not_chained)
      p.push_back(n(embedding.not_chained) + " of " + n(segments) + " segments not chains of mesh edges");
    if (expected_regions >= 0 && embedding.regions != expected_regions)
      p.push_back(n(embedding.regions) + " regions, not " + n(expected_regions));
    if (zero_area_faces) p.push_back(n(zero_area_faces) + " zero-area faces");
    if (new_folds()) p.push_back(n(folded_edges) + " folded edges (the template has " + n(template_folded_edges) + ")");
    if (new_self_intersections())
      p.push_back(n(self_intersecting_pairs) + " intersecting face pairs (the template has " +
                  n(template_self_intersecting_pairs) + ")");
    if (non_finite_coordinates) p.push_back(n(non_finite_coordinates) + " vertices with non-finite coordinates");
    return p;
  }
  bool passed() const { return problems().empty(); }
};

/// Checks `out` against the network and the template it was fitted from. `expected_regions` < 0
/// leaves the region count unchecked; `check_self_intersections` false leaves the pairs at 0.
inline Fit_check check_fit(const Mesh& out, const Mesh& tmpl, const Network& net, long expected_regions = -1,
                           bool check_self_intersections = true) {
  Fit_check c;
  c.embedding = embedding(out, net);
  c.network_vertices = long(net.points.size());
  c.segments = long(net.segments.size());
  c.expected_regions = expected_regions;
  c.zero_area_faces = zero_area_faces(out);
  c.folded_edges = folded_edges(out);
  c.template_folded_edges = folded_edges(tmpl);
  c.self_intersections_checked = check_self_intersections;
  if (check_self_intersections) {
    c.self_intersecting_pairs = self_intersections(out);
    c.template_self_intersecting_pairs = self_intersections(tmpl);
  }
  c.non_finite_coordinates = non_finite_coordinates(out);
  const std::vector<double> angles = sorted_angles_deg(out);
  c.smallest_angle_deg = angles.empty() ? 0 : angles.front();
  c.angle_5th_percentile_deg = angles.empty() ? 0 : angles[angles.size() / 20];
  return c;
}

}  // namespace fit_oracle

#endif  // MESHFIT_BENCH_FIT_ORACLE_H
