// Stage 3 (smooth.h): the thesis's comparison (figs. 4.13, 4.14) as numbers, constraints, guards.
#include <meshfit/io.h>
#include <meshfit/smooth.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/graph_traits_Polyhedron_3.h>
#include <CGAL/boost/graph/properties_Polyhedron_3.h>

#include "test_helpers.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <functional>
#include <tuple>
#include <sstream>

namespace meshfit_smooth_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;
using meshfit::Point_3;
using meshfit::Vector_3;
namespace mp = meshfit::parameters;

namespace {

// ---- generated shapes ----------------------------------------------------------------------------

/// An icosphere of radius 1: the icosahedron, each triangle split in four `levels` times, new
/// vertices pushed onto the sphere.
meshfit::Mesh_data icosphere(int levels) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  meshfit::Mesh_data m;
  m.points = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
              {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  m.triangles = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  auto unit = [](const Point_3& p) {
    const double l = std::sqrt((p - CGAL::ORIGIN).squared_length());
    return Point_3(p.x() / l, p.y() / l, p.z() / l);
  };
  for (auto& p : m.points) p = unit(p);
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::size_t, std::size_t>, std::size_t> mid;
    auto middle = [&](std::size_t a, std::size_t b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.points.push_back(unit(CGAL::midpoint(m.points[a], m.points[b])));
      return mid[key] = m.points.size() - 1;
    };
    std::vector<std::array<std::size_t, 3>> next;
    for (const auto& t : m.triangles) {
      const std::size_t a = middle(t[0], t[1]), b = middle(t[1], t[2]), c = middle(t[2], t[0]);
      next.push_back({t[0], a, c});
      next.push_back({t[1], b, a});
      next.push_back({t[2], c, b});
      next.push_back({a, b, c});
    }
    m.triangles = next;
  }
  return m;
}

constexpr double torus_R = 1.0, torus_r = 0.4;

/// A torus (major radius 1, minor 0.4) as a nu × nv grid, two triangles per cell.
meshfit::Mesh_data torus(std::size_t nu, std::size_t nv) {
  meshfit::Mesh_data m;
  for (std::size_t i = 0; i < nu; ++i)
    for (std::size_t j = 0; j < nv; ++j) {
      const double u = 2 * CGAL_PI * double(i) / double(nu), v = 2 * CGAL_PI * double(j) / double(nv);
      m.points.emplace_back((torus_R + torus_r * std::cos(v)) * std::cos(u), (torus_R + torus_r * std::cos(v)) * std::sin(u),
                            torus_r * std::sin(v));
    }
  auto id = [&](std::size_t i, std::size_t j) { return (i % nu) * nv + (j % nv); };
  for (std::size_t i = 0; i < nu; ++i)
    for (std::size_t j = 0; j < nv; ++j) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

enum class Shape { sphere, torus };

/// Signed distance of p to the exact noise-free surface (positive outside).
double exact_distance(Shape s, const Point_3& p) {
  if (s == Shape::sphere) return std::sqrt((p - CGAL::ORIGIN).squared_length()) - 1;
  const double rho = std::sqrt(p.x() * p.x() + p.y() * p.y()) - torus_R;
  return std::sqrt(rho * rho + p.z() * p.z()) - torus_r;
}

/// The outward normal of the exact surface at (the direction of) p.
Vector_3 exact_normal(Shape s, const Point_3& p) {
  if (s == Shape::sphere) return (p - CGAL::ORIGIN) / std::sqrt((p - CGAL::ORIGIN).squared_length());
  const double l = std::sqrt(p.x() * p.x() + p.y() * p.y());
  const Vector_3 d(p.x() - torus_R * p.x() / l, p.y() - torus_R * p.y() / l, p.z());
  return d / std::sqrt(d.squared_length());
}

double mean_edge_length(const Mesh& tm) {
  double s = 0;
  for (auto e : tm.edges()) s += std::sqrt(CGAL::squared_distance(tm.point(tm.vertex(e, 0)), tm.point(tm.vertex(e, 1))));
  return s / double(tm.number_of_edges());
}

/// The shape with seeded noise: every vertex moves along the normal (σ = 0.25 h̄, the distortion
/// to remove) and in the tangent plane (σ = 0.08 h̄, the uneven triangles to even out; more would
/// flip faces of the input itself).
Mesh noisy(Shape s, const Mesh& clean, double normal_sigma = 0.25, double tangent_sigma = 0.08, unsigned seed = 2007) {
  Mesh tm = clean;
  const double h = mean_edge_length(clean);
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  for (auto v : tm.vertices()) {
    const Point_3 p = tm.point(v);
    const Vector_3 n = exact_normal(s, p);
    Vector_3 a = CGAL::cross_product(n, std::abs(n.x()) < 0.9 ? Vector_3(1, 0, 0) : Vector_3(0, 1, 0));
    a = a / std::sqrt(a.squared_length());
    const Vector_3 b = CGAL::cross_product(n, a);
    const double dn = normal_sigma * h * g(rng), da = tangent_sigma * h * g(rng), db = tangent_sigma * h * g(rng);
    tm.point(v) = p + dn * n + da * a + db * b;
  }
  return tm;
}

/// The sphere (icosphere, 2562 vertices), or the torus: a grid torus remeshed isotropically (a
/// grid's cells are 2.3 times longer on the outer equator than on the inner one, an unevenness
/// that no smoothing at fixed connectivity removes), its vertices put back on the exact torus.
Mesh make(Shape s) {
  Mesh tm;
  meshfit::build_triangle_mesh(s == Shape::sphere ? icosphere(4) : torus(96, 32), tm);
  if (s == Shape::torus) {
    CGAL::Polygon_mesh_processing::isotropic_remeshing(faces(tm), 0.06, tm,
                                                       CGAL::parameters::number_of_iterations(5));
    tm.collect_garbage();
    for (auto v : tm.vertices()) {
      const Point_3 p = tm.point(v);
      const double l = std::sqrt(p.x() * p.x() + p.y() * p.y());
      const Point_3 c(torus_R * p.x() / l, torus_R * p.y() / l, 0);
      tm.point(v) = c + torus_r * ((p - c) / std::sqrt((p - c).squared_length()));
    }
  }
  return tm;
}

// ---- measures ------------------------------------------------------------------------------------

struct Measures {
  double volume_ratio = 0;  ///< volume / volume of the noise-free mesh
  double distance = 0;      ///< mean |distance| of the vertices to the exact surface, / h̄
  double offset = 0;        ///< mean signed distance / h̄ (negative: shrunk)
  double roughness = 0;     ///< standard deviation of the signed distance / h̄: the noise left
  double area_spread = 0;   ///< coefficient of variation of the face areas (evenness of the faces)
  double angle_spread = 0;  ///< standard deviation of the faces' smallest angles (degrees)
  double min_angle = 0;     ///< smallest angle (degrees)
};

double smallest_angle(const Point_3 p[3]) {
  double best = 180;
  for (int k = 0; k < 3; ++k) {
    const Vector_3 a = p[(k + 1) % 3] - p[k], b = p[(k + 2) % 3] - p[k];
    const double c = a * b / std::sqrt(a.squared_length() * b.squared_length());
    best = std::min(best, std::acos(std::max(-1.0, std::min(1.0, c))) * 180 / CGAL_PI);
  }
  return best;
}

/// Mean and standard deviation.
std::pair<double, double> mean_sd(const std::vector<double>& x) {
  double s = 0, s2 = 0;
  for (double v : x) {
    s += v;
    s2 += v * v;
  }
  const double n = double(x.size()), m = s / n;
  return {m, std::sqrt(std::max(0.0, s2 / n - m * m))};
}

Measures measure(Shape s, const Mesh& tm, const Mesh& clean) {
  Measures m;
  const double h = mean_edge_length(clean);
  m.volume_ratio = CGAL::Polygon_mesh_processing::volume(tm) / CGAL::Polygon_mesh_processing::volume(clean);
  std::vector<double> d, area, angle;
  for (auto v : tm.vertices()) d.push_back(exact_distance(s, tm.point(v)) / h);
  for (double x : d) m.distance += std::abs(x) / double(d.size());
  std::tie(m.offset, m.roughness) = mean_sd(d);
  m.min_angle = 180;
  for (auto f : tm.faces()) {
    Point_3 p[3];
    int k = 0;
    for (auto v : CGAL::vertices_around_face(tm.halfedge(f), tm)) p[k++] = tm.point(v);
    angle.push_back(smallest_angle(p));
    area.push_back(std::sqrt(CGAL::squared_area(p[0], p[1], p[2])));
    m.min_angle = std::min(m.min_angle, angle.back());
  }
  m.angle_spread = mean_sd(angle).second;
  const auto a = mean_sd(area);
  m.area_spread = a.second / a.first;
  return m;
}

/// Faces whose normal turned by 90° or more between `before` and `after` (same connectivity).
std::size_t flipped_faces(const Mesh& before, const Mesh& after) {
  std::size_t n = 0;
  for (auto f : before.faces()) {
    Point_3 a[3], b[3];
    int k = 0;
    for (auto v : CGAL::vertices_around_face(before.halfedge(f), before)) {
      a[k] = before.point(v);
      b[k++] = after.point(v);
    }
    const Vector_3 na = CGAL::cross_product(a[1] - a[0], a[2] - a[0]), nb = CGAL::cross_product(b[1] - b[0], b[2] - b[0]);
    n += !(na * nb > 0);
  }
  return n;
}

/// Interior edges whose two faces turn 90° or more apart in `after` but not in `before` (same
/// connectivity): folds the smoothing made. Normals in double, compared with zero.
std::size_t new_folds(const Mesh& before, const Mesh& after) {
  auto normal = [](const Mesh& m, Mesh::Face_index f) {
    const auto h = m.halfedge(f);
    const Point_3 a = m.point(m.source(h)), b = m.point(m.target(h)), c = m.point(m.target(m.next(h)));
    return CGAL::cross_product(b - a, c - a);
  };
  std::size_t n = 0;
  for (auto e : before.edges()) {
    if (before.is_border(e)) continue;
    const auto f = before.face(before.halfedge(e, 0)), g = before.face(before.halfedge(e, 1));
    n += normal(before, f) * normal(before, g) > 0 && !(normal(after, f) * normal(after, g) > 0);
  }
  return n;
}

std::string shape_name(Shape s) { return s == Shape::sphere ? "sphere" : "torus"; }

}  // namespace


// The thesis's comparison (§4.4, figs. 4.13, 4.14): 20 iterations of Laplacian flow (λ = 1), 60 of
// mean-curvature flow, 100 of the combined method, on a noisy sphere and a noisy torus. The
// mean-curvature flow runs at λ = 0.1 (τ = 0.1 h̄²): at λ = 1 it shrinks the sphere to 66% of its
// volume in 60 iterations, more than the Laplacian flow does in 20, while the thesis reports it
// shrinks less; at 0.1 it does, and it still removes the noise.
TEST_CASE("smooth: the combined method keeps the volume, removes the noise and evens out the triangles",
          "[smooth][thesis]") {
  for (Shape s : {Shape::sphere, Shape::torus}) {
    SECTION(shape_name(s)) {
      const Mesh clean = make(s);
      const Mesh input = noisy(s, clean);
      REQUIRE(flipped_faces(clean, input) == 0);
      Mesh lap = input, mc = input, ours = input;
      const auto rl = meshfit::laplacian_flow(lap, CGAL::parameters::number_of_iterations(20));
      const auto rm = meshfit::mean_curvature_flow(mc, mp::step_size(0.1).number_of_iterations(60));
      const auto ro = meshfit::smooth_fitted_mesh(ours, mp::smoothing_tolerance(0.0).number_of_iterations(100));
      const Measures mi = measure(s, input, clean), ml = measure(s, lap, clean), mm = measure(s, mc, clean),
                     mo = measure(s, ours, clean), m0 = measure(s, clean, clean);
      auto line = [](const char* name, const Measures& m) {
        std::ostringstream os;
        os << "| " << name << " | " << m.volume_ratio << " | " << m.offset << " | " << m.roughness << " | "
           << m.area_spread << " | " << m.angle_spread << " | " << m.min_angle << " |";
        return os.str();
      };
      const std::string table = shape_name(s) + ": | method | volume / noise-free | mean signed distance to the "
                                "exact surface / h | its std-dev (noise) / h | face area std-dev / mean | std-dev of the "
                                "faces' smallest angle (deg) | smallest angle (deg) |\n" +
                                line("noise-free", m0) + "\n" + line("noisy input", mi) + "\n" +
                                line("Laplacian 20, lambda 1", ml) + "\n" + line("mean curvature 60, lambda 0.1", mm) +
                                "\n" + line("combined 100 (20 + 80)", mo);
      WARN(table);
      INFO(table);
      CHECK(rl.iterations == 20);
      CHECK(rm.iterations == 60);
      CHECK(ro.iterations == 100);
      CHECK(ro.mean_curvature_iterations == 20);
      CHECK(ro.laplacian_iterations == 80);
      // Laplacian flow shrinks; the combined method shrinks far less (a tenth as much).
      CHECK(ml.volume_ratio < 0.9);
      CHECK(std::abs(1 - mo.volume_ratio) < 0.1 * std::abs(1 - ml.volume_ratio));
      // The thesis: mean-curvature flow shrinks less than the Laplacian flow.
      CHECK(mm.volume_ratio > ml.volume_ratio);
      // The noise is removed: the spread of the distances to the exact surface falls by more than
      // half (what is left of the distance is the small shrinkage, measured by the volume).
      CHECK(mo.roughness < 0.5 * mi.roughness);
      CHECK(mm.roughness < 0.5 * mi.roughness);
      // The combined method's triangles are more even than the mean-curvature flow's and the input's.
      // (Face areas are not evened out: uniform weights put each vertex at its neighbours' centroid,
      // which on vertices of irregular valence, like the remeshed torus's, makes areas uneven;
      // the area spread is reported above, not asserted.)
      CHECK(mo.angle_spread < mm.angle_spread);
      CHECK(mo.angle_spread < mi.angle_spread);
      // No face turns over.
      CHECK(flipped_faces(input, ours) == 0);
      CHECK(flipped_faces(input, mc) == 0);
      CHECK(flipped_faces(input, lap) == 0);
    }
  }
}

TEST_CASE("smooth: the modified Laplacian flow keeps every vertex on the original surface", "[smooth]") {
  const Mesh clean = make(Shape::sphere);
  const Mesh input = noisy(Shape::sphere, clean);
  Mesh tm = input;
  const auto r = meshfit::modified_laplacian_flow(tm, CGAL::parameters::number_of_iterations(50));
  CHECK(r.iterations == 50);
  CHECK(r.mean_displacement > 0.05 * mean_edge_length(clean));  // it does move the vertices
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<meshfit::Kernel, Primitive>>;
  Tree tree(faces(input).first, faces(input).second, input);
  double worst = 0;
  for (auto v : tm.vertices()) worst = std::max(worst, std::sqrt(tree.squared_distance(tm.point(v))));
  CHECK(worst < 1e-12);
  CHECK(std::abs(1 - CGAL::Polygon_mesh_processing::volume(tm) / CGAL::Polygon_mesh_processing::volume(input)) < 0.01);
  CHECK(measure(Shape::sphere, tm, clean).angle_spread < measure(Shape::sphere, input, clean).angle_spread);
  CHECK(measure(Shape::sphere, tm, clean).area_spread < measure(Shape::sphere, input, clean).area_spread);
  CHECK(flipped_faces(input, tm) == 0);
}

namespace {

/// A path of edges between vertices a and b (breadth-first), as a list of vertices.
std::vector<Mesh::Vertex_index> edge_path(const Mesh& tm, Mesh::Vertex_index a, Mesh::Vertex_index b) {
  std::map<Mesh::Vertex_index, Mesh::Vertex_index> from{{a, a}};
  std::vector<Mesh::Vertex_index> queue{a};
  for (std::size_t k = 0; k < queue.size() && !from.count(b); ++k)
    for (auto w : CGAL::vertices_around_target(tm.halfedge(queue[k]), tm))
      if (from.emplace(w, queue[k]).second) queue.push_back(w);
  std::vector<Mesh::Vertex_index> path{b};
  while (path.back() != a) path.push_back(from.at(path.back()));
  return path;
}

}  // namespace

TEST_CASE("smooth: constrained vertices, curve vertices and the boundary do not move, curve edges stay edges",
          "[smooth][constraints]") {
  const Mesh clean = make(Shape::sphere);
  const Mesh input = noisy(Shape::sphere, clean);
  // A curve across the sphere and a few vertices pinned by the caller.
  const auto path = edge_path(input, Mesh::Vertex_index(0), Mesh::Vertex_index(3));
  REQUIRE(path.size() > 5);
  using Run = std::function<meshfit::Smoothing_report(Mesh&, Mesh::Property_map<Mesh::Vertex_index, bool>,
                                                      Mesh::Property_map<Mesh::Edge_index, bool>)>;
  const std::vector<std::pair<std::string, Run>> runs = {
      {"laplacian", [](Mesh& m, auto vc, auto ec) {
         return meshfit::laplacian_flow(m, CGAL::parameters::vertex_is_constrained_map(vc).edge_is_constrained_map(ec));
       }},
      {"mean curvature", [](Mesh& m, auto vc, auto ec) {
         return meshfit::mean_curvature_flow(m, CGAL::parameters::vertex_is_constrained_map(vc).edge_is_constrained_map(ec));
       }},
      {"modified mean curvature", [](Mesh& m, auto vc, auto ec) {
         return meshfit::modified_mean_curvature_flow(m, CGAL::parameters::vertex_is_constrained_map(vc).edge_is_constrained_map(ec));
       }},
      {"modified laplacian", [](Mesh& m, auto vc, auto ec) {
         return meshfit::modified_laplacian_flow(m, CGAL::parameters::vertex_is_constrained_map(vc).edge_is_constrained_map(ec));
       }},
      {"combined", [](Mesh& m, auto vc, auto ec) {
         return meshfit::smooth_fitted_mesh(m, CGAL::parameters::vertex_is_constrained_map(vc).edge_is_constrained_map(ec));
       }}};
  for (const auto& [name, run] : runs) {
    SECTION(name) {
      Mesh tm = input;
      auto vc = tm.add_property_map<Mesh::Vertex_index, bool>("v:c", false).first;
      auto ec = tm.add_property_map<Mesh::Edge_index, bool>("e:c", false).first;
      for (std::size_t k = 0; k + 1 < path.size(); ++k) ec[tm.edge(tm.halfedge(path[k], path[k + 1]))] = true;
      std::vector<Mesh::Vertex_index> pinned;
      for (auto v : tm.vertices())
        if (v.idx() % 37 == 5) {
          vc[v] = true;
          pinned.push_back(v);
        }
      const auto r = run(tm, vc, ec);
      std::size_t fixed = path.size();
      for (auto v : pinned) fixed += std::find(path.begin(), path.end(), v) == path.end();
      CHECK(r.fixed_vertices == fixed);
      CHECK(r.mean_displacement > 0);
      for (auto v : pinned) CHECK(tm.point(v) == input.point(v));
      for (auto v : path) CHECK(tm.point(v) == input.point(v));
      for (std::size_t k = 0; k + 1 < path.size(); ++k) CHECK(CGAL::halfedge(path[k], path[k + 1], tm).second);
      CHECK(flipped_faces(input, tm) == 0);
    }
  }
  SECTION("the boundary of an open template") {
    Mesh tm;
    meshfit::Mesh_data g = meshfit_test::grid(12);
    std::mt19937 rng(7);
    std::normal_distribution<double> d(0, 0.15);
    for (auto& p : g.points) p = Point_3(p.x() + d(rng), p.y() + d(rng), 0.3 * d(rng));
    meshfit::build_triangle_mesh(g, tm);
    const Mesh before = tm;
    const auto r = meshfit::smooth_fitted_mesh(tm);
    CHECK(r.fixed_vertices == 48);
    for (auto v : tm.vertices())
      if (CGAL::is_border(v, tm)) CHECK(tm.point(v) == before.point(v));
      else CHECK(tm.point(v) != before.point(v));
    CHECK(flipped_faces(before, tm) == 0);
  }
}

// The faces on the two sides of a curve move independently (the flows do not couple them), so
// the guard must judge folds across curve edges too: seen in a fit of a 162-vertex sphere onto a
// peanut, where smoothing folded one curve edge. Here: a rough sphere (normal noise 0.6 h̄) cut by
// twelve curves, every flow at its default settings.
TEST_CASE("smooth: no edge folds, across curves either", "[smooth][constraints]") {
  const Mesh clean = make(Shape::sphere);
  const Mesh input = noisy(Shape::sphere, clean, 0.6, 0.08, 11);
  Mesh tm = input;
  auto ec = tm.add_property_map<Mesh::Edge_index, bool>("e:c", false).first;
  std::size_t curve_edges = 0;
  for (std::uint32_t k = 0; k < 12; ++k) {
    const auto path = edge_path(input, Mesh::Vertex_index(k), Mesh::Vertex_index(2561 - 97 * k));
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      const auto e = tm.edge(tm.halfedge(path[i], path[i + 1]));
      curve_edges += !ec[e];
      ec[e] = true;
    }
  }
  REQUIRE(curve_edges > 200);
  const auto np = CGAL::parameters::edge_is_constrained_map(ec);
  SECTION("combined") { meshfit::smooth_fitted_mesh(tm, np); }
  SECTION("laplacian") { meshfit::laplacian_flow(tm, np.number_of_iterations(100)); }
  SECTION("mean curvature") { meshfit::mean_curvature_flow(tm, np.number_of_iterations(100)); }
  SECTION("modified mean curvature") { meshfit::modified_mean_curvature_flow(tm, np.number_of_iterations(100)); }
  SECTION("modified laplacian") { meshfit::modified_laplacian_flow(tm, np.number_of_iterations(100)); }
  CHECK(new_folds(input, tm) == 0);
  CHECK(flipped_faces(input, tm) == 0);
}

TEST_CASE("smooth: needles, caps and a zero-area face give finite output and no error", "[smooth][degenerate]") {
  meshfit::Mesh_data g = meshfit_test::grid(8);
  std::mt19937 rng(11);
  std::normal_distribution<double> d(0, 0.05);
  for (auto& p : g.points) p = Point_3(p.x(), p.y(), d(rng));
  auto at = [](std::size_t i, std::size_t j) { return j * 9 + i; };
  // A zero-area face: corner (3,3) moved onto the line of its face's edge (2,2)-(3,2)... made exact
  // by putting the three points on the x axis line z = 0, y = 2.
  g.points[at(2, 2)] = Point_3(2, 2, 0);
  g.points[at(3, 2)] = Point_3(3, 2, 0);
  g.points[at(3, 3)] = Point_3(2.5, 2, 0);
  // A needle: (6,5) a hair away from (6,6)'s position.
  g.points[at(6, 5)] = Point_3(g.points[at(6, 6)].x(), g.points[at(6, 6)].y() - 1e-9, g.points[at(6, 6)].z());
  // A cap: (5,2) almost on the segment between (4,2) and (6,2)... (4,1), (6,3) diagonal.
  g.points[at(5, 2)] = CGAL::midpoint(g.points[at(4, 1)], g.points[at(6, 3)]) + Vector_3(0, 0, 1e-10);
  // And two coincident vertices.
  g.points[at(2, 6)] = g.points[at(3, 6)];
  Mesh base;
  meshfit::build_triangle_mesh(g, base);
  auto finite_mesh = [](const Mesh& tm) {
    for (auto v : tm.vertices()) {
      const Point_3& p = tm.point(v);
      if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z())) return false;
    }
    return true;
  };
  for (int kind = 0; kind < 7; ++kind) {
    Mesh tm = base;
    meshfit::Smoothing_report r;
    const auto np = CGAL::parameters::number_of_iterations(30);
    switch (kind) {
      case 0: r = meshfit::laplacian_flow(tm, np); break;
      case 1: r = meshfit::laplacian_flow(tm, mp::laplacian_weights(meshfit::Laplacian_weights::inverse_distance, np)); break;
      case 2: r = meshfit::mean_curvature_flow(tm, np); break;
      case 3: r = meshfit::modified_mean_curvature_flow(tm, np); break;
      case 4: r = meshfit::modified_laplacian_flow(tm, np); break;
      case 5: r = meshfit::laplacian_flow(tm, mp::laplacian_variant(meshfit::Laplacian_variant::alpha_original,
                                                                    mp::laplacian_weights(meshfit::Laplacian_weights::inverse_distance, np))); break;
      default: r = meshfit::smooth_fitted_mesh(tm); break;
    }
    INFO("flow " << kind << ": clamped cotangents " << r.clamped_cotangents << ", steps reduced " << r.steps_reduced);
    CHECK(finite_mesh(tm));
    CHECK(std::isfinite(r.mean_displacement));
    CHECK(std::isfinite(r.max_displacement));
    CHECK(r.max_displacement < 3);
    if (kind == 2 || kind == 3) CHECK(r.clamped_cotangents > 0);
  }
}

TEST_CASE("smooth: Vollmer's variants (eq. 4.5, 4.6) and inverse-distance weights", "[smooth]") {
  const Mesh clean = make(Shape::sphere);
  const Mesh input = noisy(Shape::sphere, clean);
  auto volume_after = [&](auto np) {
    Mesh tm = input;
    meshfit::laplacian_flow(tm, np);
    return CGAL::Polygon_mesh_processing::volume(tm) / CGAL::Polygon_mesh_processing::volume(clean);
  };
  const auto n = CGAL::parameters::number_of_iterations(20);
  const double none = volume_after(n);
  const double current = volume_after(mp::laplacian_variant(meshfit::Laplacian_variant::alpha_current, n));
  const double original = volume_after(mp::laplacian_variant(meshfit::Laplacian_variant::alpha_original, n));
  const double inverse = volume_after(mp::laplacian_weights(meshfit::Laplacian_weights::inverse_distance, n));
  INFO("volume ratios: none " << none << ", eq 4.5 " << current << ", eq 4.6 " << original << ", inverse distance " << inverse);
  // Eq. 4.5 still shrinks (the thesis: "the shrinkage problem cannot be solved"), more slowly;
  // eq. 4.6 is anchored to p^0 and shrinks least.
  CHECK(current < 0.97);
  CHECK(current > none);
  CHECK(original > current);
  CHECK(inverse < 0.97);
  // α = 1 keeps every vertex where it is (eq. 4.5: at p^k, eq. 4.6: at p^0).
  for (auto variant : {meshfit::Laplacian_variant::alpha_current, meshfit::Laplacian_variant::alpha_original}) {
    Mesh tm = input;
    const auto r = meshfit::laplacian_flow(tm, mp::laplacian_variant(variant, mp::laplacian_alpha(1.0, n)));
    CHECK(r.max_displacement == 0);
  }
}

TEST_CASE("smooth: the same result on Polyhedron_3", "[smooth][generic]") {
  const Mesh input = noisy(Shape::torus, make(Shape::torus));
  Mesh a = input;
  CGAL::Polyhedron_3<meshfit::Kernel> b;
  meshfit::build_triangle_mesh(meshfit::to_mesh_data(input), b);
  const auto ra = meshfit::smooth_fitted_mesh(a);
  const auto rb = meshfit::smooth_fitted_mesh(b);
  CHECK(ra.mean_displacement == rb.mean_displacement);
  const auto pa = meshfit::to_mesh_data(a).points, pb = meshfit::to_mesh_data(b).points;
  REQUIRE(pa.size() == pb.size());
  std::size_t same = 0;
  for (std::size_t i = 0; i < pa.size(); ++i) same += pa[i] == pb[i];
  CHECK(same == pa.size());
}

// The oracle: the same run with every iteration made (tolerance 0), measured against the exact
// surface by measure(). A phase ends once an iteration moves no vertex farther than the tolerance
// times the mean edge: what the remaining iterations would still do is that small, and the
// triangles' shape and the distance to the surface stay as they were.
TEST_CASE("smooth: smoothing_tolerance ends a phase once an iteration moves little, with the same triangles",
          "[smooth]") {
  for (Shape s : {Shape::sphere, Shape::torus}) {
    const Mesh clean = make(s), input = noisy(s, clean);
    Mesh all = input, stopped = input;
    const auto ra = meshfit::smooth_fitted_mesh(all, mp::smoothing_tolerance(0.0));
    const auto rs = meshfit::smooth_fitted_mesh(stopped);
    const Measures ma = measure(s, all, clean), ms = measure(s, stopped, clean);
    const double h = mean_edge_length(clean);
    INFO(shape_name(s) << ": " << rs.iterations << " of 100 iterations, last move " << rs.last_step_max_displacement / h
                       << " h; smallest angle " << ms.min_angle << " (all: " << ma.min_angle << "), angle spread "
                       << ms.angle_spread << " (" << ma.angle_spread << "), distance " << ms.distance << " h ("
                       << ma.distance << ")");
    CHECK(ra.iterations == 100);
    // The sphere's flows settle; on the torus the last iterations still move vertices 0.04 h: all 100 are made.
    if (s == Shape::sphere) CHECK(rs.iterations < 100);
    CHECK((rs.iterations == 100 ||
           rs.last_step_max_displacement <= meshfit::internal::default_smoothing_tolerance * mean_edge_length(input)));
    CHECK(ms.min_angle > ma.min_angle - 1);
    CHECK(ms.angle_spread < ma.angle_spread + 0.5);
    CHECK(ms.distance < ma.distance + 0.01);
    CHECK(std::abs(ms.volume_ratio - ma.volume_ratio) < 0.002);
  }
}

// smooth_fitted_mesh's two phases share their work arrays (run_flows): the second must start as it
// would with fresh ones, so running both in one call gives, bit for bit, what two calls give; in
// either order, with fixed vertices and constrained edges, and on strong noise, where the flip
// guard halves steps (its counters are state that must not carry over).
TEST_CASE("smooth: flows run together share nothing but their arrays' memory", "[smooth]") {
  namespace mi = meshfit::internal;
  for (Shape s : {Shape::sphere, Shape::torus}) {
    const Mesh input = noisy(s, make(s), 0.6, 0.3, 11);
    mi::Smoothing_arrays a;
    for (auto v : input.vertices())
      for (double c : {input.point(v).x(), input.point(v).y(), input.point(v).z()}) a.points.push_back(c);
    for (auto f : input.faces()) {
      std::array<std::uint32_t, 3> t{};
      int k = 0;
      for (auto v : CGAL::vertices_around_face(input.halfedge(f), input)) t[std::size_t(k++)] = std::uint32_t(v.idx());
      a.triangles.push_back(t);
    }
    a.fixed.assign(input.number_of_vertices(), 0);
    for (std::size_t i = 0; i < a.fixed.size(); i += 9) a.fixed[i] = 1;
    for (auto e : input.edges())
      if (e.idx() % 13 == 0)
        a.constrained_edges.push_back({std::uint32_t(input.vertex(e, 0).idx()), std::uint32_t(input.vertex(e, 1).idx())});
    a.orientation_points = a.points;
    mi::Flow_settings mc, lap;
    mc.kind = mi::Flow_kind::modified_mean_curvature;
    lap.kind = mi::Flow_kind::modified_laplacian;
    mc.iterations = 12;
    lap.iterations = 30;
    for (bool mc_first : {true, false}) {
      const std::vector<mi::Flow_settings> order = mc_first ? std::vector{mc, lap} : std::vector{lap, mc};
      mi::Smoothing_arrays together = a, apart = a;
      meshfit::Smoothing_report rt, r0, r1;
      mi::run_flows(together, order, rt);
      mi::run_flow(apart, order[0], r0);
      mi::run_flow(apart, order[1], r1);
      INFO(shape_name(s) << (mc_first ? ", mean curvature first" : ", Laplacian first") << ": steps halved "
                         << rt.steps_reduced << ", cancelled " << rt.steps_cancelled);
      CHECK(rt.steps_reduced > 0);  // the guard was at work
      CHECK(rt.iterations == r0.iterations + r1.iterations);
      CHECK(rt.steps_reduced == r0.steps_reduced + r1.steps_reduced);
      CHECK(rt.steps_cancelled == r0.steps_cancelled + r1.steps_cancelled);
      CHECK(rt.projections_clamped == r0.projections_clamped + r1.projections_clamped);
      CHECK(together.points != a.points);
      CHECK(together.points == apart.points);
    }
  }
}

// A mesh numbered without regard to place (here at random) is smoothed on a copy renumbered
// along its edges (run_flows): the positions must come back to their own vertices, and the result
// must be the one the mesh gets numbered by place, up to the order of floating-point sums.
TEST_CASE("smooth: a mesh numbered at random gives the result of the same mesh numbered by place", "[smooth]") {
  meshfit::Mesh_data placed = icosphere(6);  // 40 962 vertices
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.004);  // about a sixth of an edge
  for (auto& p : placed.points) {  // moved along the sphere: the walks meet no sharp ridge
    const Point_3 q(p.x() + noise(rng), p.y() + noise(rng), p.z() + noise(rng));
    p = CGAL::ORIGIN + (q - CGAL::ORIGIN) / std::sqrt((q - CGAL::ORIGIN).squared_length());
  }
  std::vector<std::size_t> new_of(placed.points.size());
  std::iota(new_of.begin(), new_of.end(), std::size_t(0));
  std::shuffle(new_of.begin(), new_of.end(), rng);
  meshfit::Mesh_data shuffled;
  shuffled.points.resize(placed.points.size());
  for (std::size_t i = 0; i < placed.points.size(); ++i) shuffled.points[new_of[i]] = placed.points[i];
  for (const auto& t : placed.triangles) shuffled.triangles.push_back({new_of[t[0]], new_of[t[1]], new_of[t[2]]});
  std::shuffle(shuffled.triangles.begin(), shuffled.triangles.end(), rng);
  Mesh a, b;
  meshfit::build_triangle_mesh(placed, a);
  meshfit::build_triangle_mesh(shuffled, b);
  const auto np = mp::smoothing_tolerance(0.0).number_of_iterations(30);
  meshfit::smooth_fitted_mesh(a, np);
  meshfit::smooth_fitted_mesh(b, np);
  const auto pa = meshfit::to_mesh_data(a).points, pb = meshfit::to_mesh_data(b).points;
  const double h = mean_edge_length(a);
  std::vector<double> difference;
  double moved = 0;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    difference.push_back(std::sqrt(CGAL::squared_distance(pa[i], pb[new_of[i]])) / h);
    moved = std::max(moved, std::sqrt(CGAL::squared_distance(pa[i], placed.points[i])) / h);
  }
  std::sort(difference.begin(), difference.end());
  const double median = difference[difference.size() / 2], p99 = difference[difference.size() * 99 / 100];
  INFO("differences (h): median " << median << ", 99th percentile " << p99 << ", largest " << difference.back()
                                  << "; largest motion " << moved << " h");
  CHECK(moved > 0.5);  // the smoothing did move the vertices
  // The guards' thresholds turn differences of rounding into a halved step here and there, which
  // spreads a little: the numbering changes the result by a small fraction of an edge, and a
  // position written back to another vertex would be far off.
  CHECK(median < 0.01);
  CHECK(p99 < 0.05);
  CHECK(difference.back() < 0.5);
}

TEST_CASE("smooth: bad parameters are Invalid_input, a cancelled run leaves the mesh unchanged", "[smooth]") {
  const Mesh input = make(Shape::sphere);
  Mesh tm = input;
  meshfit_test::require_invalid([&] { meshfit::laplacian_flow(tm, mp::step_size(0.0)); }, 0, "step_size");
  meshfit_test::require_invalid([&] { meshfit::mean_curvature_flow(tm, mp::step_size(1.5)); }, 0, "step_size");
  meshfit_test::require_invalid([&] { meshfit::smooth_fitted_mesh(tm, mp::step_size(std::nan(""))); }, 0, "step_size");
  meshfit_test::require_invalid([&] { meshfit::laplacian_flow(tm, CGAL::parameters::number_of_iterations(-1)); }, 0,
                                "negative");
  meshfit_test::require_invalid([&] { meshfit::smooth_fitted_mesh(tm, mp::laplacian_iterations(-3)); }, 0, "negative");
  meshfit_test::require_invalid([&] { meshfit::smooth_fitted_mesh(tm, mp::smoothing_tolerance(-0.5)); }, 0,
                                "smoothing_tolerance");
  meshfit_test::require_invalid([&] { meshfit::smooth_fitted_mesh(tm, mp::smoothing_tolerance(std::nan(""))); }, 0,
                                "smoothing_tolerance");
  meshfit_test::require_invalid([&] { meshfit::laplacian_flow(tm, mp::laplacian_alpha(1.5)); }, 0, "laplacian_alpha");
  meshfit_test::require_invalid(
      [&] { meshfit::modified_laplacian_flow(tm, mp::reference_points(std::vector<Point_3>(3))); }, 0, "reference_points");
  Mesh quad;
  const auto v0 = quad.add_vertex(Point_3(0, 0, 0)), v1 = quad.add_vertex(Point_3(1, 0, 0)),
             v2 = quad.add_vertex(Point_3(1, 1, 0)), v3 = quad.add_vertex(Point_3(0, 1, 0));
  quad.add_face(v0, v1, v2, v3);
  meshfit_test::require_invalid([&] { meshfit::smooth_fitted_mesh(quad); }, 0, "not a triangle");
  Mesh bad = input;
  bad.point(Mesh::Vertex_index(4)) = Point_3(std::nan(""), 0, 0);
  meshfit_test::require_invalid([&] { meshfit::smooth_fitted_mesh(bad); }, 0, "vertex 4");
  CHECK(tm.number_of_vertices() == input.number_of_vertices());
  for (auto v : tm.vertices()) CHECK(tm.point(v) == input.point(v));

  Mesh cancelled = noisy(Shape::sphere, input);
  const Mesh before = cancelled;
  std::vector<std::size_t> seen;
  auto stop_at_5 = [&](const meshfit::Progress_step& s) {
    CHECK(s.stage == "smooth");
    CHECK(s.total == 100);
    seen.push_back(s.index);
    return s.index < 5;
  };
  CHECK_THROWS_AS(meshfit::smooth_fitted_mesh(cancelled, mp::progress(stop_at_5)), meshfit::Algorithm_failure);
  CHECK(seen == std::vector<std::size_t>{0, 1, 2, 3, 4, 5});
  for (auto v : cancelled.vertices()) CHECK(cancelled.point(v) == before.point(v));
  // Zero iterations: nothing moves.
  const auto r = meshfit::smooth_fitted_mesh(cancelled, CGAL::parameters::number_of_iterations(0));
  CHECK(r.iterations == 0);
  CHECK(r.max_displacement == 0);
}

#ifdef MESHFIT_CGAL_DATA_DIR
TEST_CASE("smooth: CGAL's elephant keeps its volume and shape under the combined method", "[smooth][real]") {
  Mesh tm;
  meshfit::read_triangle_mesh(MESHFIT_CGAL_DATA_DIR "/elephant.off", tm);
  const Mesh input = tm;
  const auto r = meshfit::smooth_fitted_mesh(tm);
  const double h = mean_edge_length(input);
  const double ratio = CGAL::Polygon_mesh_processing::volume(tm) / CGAL::Polygon_mesh_processing::volume(input);
  INFO("elephant: volume ratio " << ratio << ", mean displacement / h " << r.mean_displacement / h << ", max / h "
                                 << r.max_displacement / h << ", steps reduced " << r.steps_reduced);
  std::size_t degenerate = 0;
  for (auto f : input.faces()) degenerate += CGAL::Polygon_mesh_processing::is_degenerate_triangle_face(f, input);
  INFO("degenerate faces in the input: " << degenerate);
  CHECK(r.iterations > 0);
  CHECK(r.iterations <= 100);
  Mesh mmc = input, mlap = input;
  meshfit::modified_mean_curvature_flow(mmc, CGAL::parameters::number_of_iterations(20));
  meshfit::modified_laplacian_flow(mlap, CGAL::parameters::number_of_iterations(80));
  INFO("modified MC 20 alone: " << CGAL::Polygon_mesh_processing::volume(mmc) / CGAL::Polygon_mesh_processing::volume(input)
       << ", modified Laplacian 80 alone: " << CGAL::Polygon_mesh_processing::volume(mlap) / CGAL::Polygon_mesh_processing::volume(input));
  // The elephant is coarse (2775 vertices) with thin parts (trunk, tail, ears), where sliding on
  // the faces cuts corners: measured 95.2% of the volume (modified mean curvature alone 96.7%,
  // modified Laplacian alone 98.6%), against 80-odd% for 20 Laplacian iterations.
  CHECK(std::abs(1 - ratio) < 0.06);
  CHECK(r.max_displacement < 3 * h);
  CHECK(flipped_faces(input, tm) == 0);
  Mesh lap = input;
  meshfit::laplacian_flow(lap);
  const double lap_ratio = CGAL::Polygon_mesh_processing::volume(lap) / CGAL::Polygon_mesh_processing::volume(input);
  INFO("Laplacian flow, 20 iterations: volume ratio " << lap_ratio);
  CHECK(std::abs(1 - ratio) < 0.5 * std::abs(1 - lap_ratio));
}
#endif

}  // namespace meshfit_smooth_test
