#include <meshfit/deform.h>
#include <meshfit/fit.h>
#include <meshfit/io.h>
#include <meshfit/partition.h>
#include <meshfit/surface_walk.h>

#include <CGAL/Polyhedron_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/Face_filtered_graph.h>
#include <CGAL/boost/graph/graph_traits_Polyhedron_3.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/properties_Polyhedron_3.h>
#include <CGAL/Polygon_mesh_processing/repair.h>
#include <CGAL/convex_hull_3.h>

#include "oracle_helpers.h"
#include "test_helpers.h"

#include <array>
#include <cmath>
#include <deque>
#include <map>
#include <random>
#include <set>

namespace meshfit_partition_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;
using meshfit::Point_3;
using meshfit::Vector_3;
using V = Mesh::Vertex_index;

namespace {

Mesh make_mesh(const meshfit::Mesh_data& d) {
  Mesh tm;
  meshfit::build_triangle_mesh(d, tm);
  return tm;
}

// Vertex (i, j) of a grid made by meshfit_test::grid(n) (possibly moved since).
V grid_vertex(std::size_t n, std::size_t i, std::size_t j) { return V(static_cast<Mesh::size_type>(j * (n + 1) + i)); }

V vertex_at(const Mesh& tm, double x, double y, double z = 0) {
  for (auto v : tm.vertices())
    if (tm.point(v) == Point_3(x, y, z)) return v;
  FAIL("no vertex at " << x << " " << y << " " << z);
  return V();
}

// The mesh's faces as sorted corner triples, with each face's unit normal.
struct Normals {
  std::map<V, Vector_3> at_vertex;  // area-weighted, normalised
  std::map<V, Point_3> position;
  std::set<std::array<V, 3>> faces;  // corners, sorted
  std::size_t folded_edges = 0;
  // The face with these corners was there before, and none of them moved.
  bool unchanged(const Mesh& tm, std::vector<V> c) const {
    for (V v : c)
      if (tm.point(v) != position.at(v)) return false;
    std::sort(c.begin(), c.end());
    return faces.count({c[0], c[1], c[2]}) > 0;
  }
};

// Area-weighted normal of `v`: the sum of its faces' cross products.
Vector_3 area_normal(const Mesh& tm, V v) {
  Vector_3 n(0, 0, 0);
  for (auto f : CGAL::faces_around_target(tm.halfedge(v), tm))
    if (f != Mesh::null_face()) n = n + fit_oracle::face_normal(tm, f);
  return n;
}

Normals vertex_normals(const Mesh& tm) {
  Normals n;
  for (auto v : tm.vertices()) {
    const Vector_3 a = area_normal(tm, v);
    const double l = std::sqrt(a.squared_length());
    n.at_vertex[v] = l > 0 ? a / l : a;
    n.position[v] = tm.point(v);
  }
  for (auto f : tm.faces()) {
    std::array<V, 3> c;
    int k = 0;
    for (auto v : CGAL::vertices_around_face(tm.halfedge(f), tm)) c[k++] = v;
    std::sort(c.begin(), c.end());
    n.faces.insert(c);
  }
  n.folded_edges = std::size_t(fit_oracle::folded_edges(tm));
  return n;
}

// The properties every partitioned mesh must have, against the mesh before partitioning: valid
// triangle mesh, same counts, no duplicate edge, no degenerate face, and no new or moved face
// turned away from the surface: its normal makes less than 95 degrees with the vertex normals
// (before) at its corners. (A face standing on edge, at 90 degrees, is a needle along a segment
// where a vertex lies very close to it: not flipped, and left to smoothing.)
void require_valid_and_unflipped(const Mesh& tm, const Normals& before, std::size_t vertices, std::size_t faces) {
  REQUIRE(CGAL::is_valid_polygon_mesh(tm));
  REQUIRE(CGAL::is_triangle_mesh(tm));
  CHECK(tm.number_of_vertices() == vertices);
  CHECK(tm.number_of_faces() == faces);
  std::set<std::pair<V, V>> seen;
  for (auto e : tm.edges()) {
    V a = tm.vertex(e, 0), b = tm.vertex(e, 1);
    if (b < a) std::swap(a, b);
    CHECK(seen.insert({a, b}).second);
  }
  std::size_t degenerate = 0, flipped = 0;
  for (auto f : tm.faces()) {
    std::vector<V> c;
    for (auto v : CGAL::vertices_around_face(tm.halfedge(f), tm)) c.push_back(v);
    if (before.unchanged(tm, c)) continue;
    const Point_3 &p = tm.point(c[0]), &q = tm.point(c[1]), &r = tm.point(c[2]);
    if (CGAL::collinear(p, q, r)) {
      ++degenerate;
      continue;
    }
    const Vector_3 n = CGAL::cross_product(q - p, r - p);
    for (V v : c)
      if (n * before.at_vertex.at(v) / std::sqrt(n.squared_length()) < -std::sin(5 * CGAL_PI / 180)) {
        ++flipped;
        WARN("flipped face " << f << ": " << p << " | " << q << " | " << r << " dot " << n * before.at_vertex.at(v) / std::sqrt(n.squared_length()) << " at " << v);
        break;
      }
  }
  CHECK(degenerate == 0);
  CHECK(flipped == 0);
  // No fold added: adjacent faces more than 90 degrees apart.
  CHECK(std::size_t(fit_oracle::folded_edges(tm)) <= before.folded_edges);
}

meshfit::Curve_network network_of(const std::vector<std::vector<Point_3>>& polylines) {
  return meshfit::Curve_network(polylines);
}

struct Partitioned {
  meshfit::Partition_report report;
  std::size_t chains = 0;   // segments that are chains of mesh edges (the oracle's)
  std::size_t regions = 0;  // faces joined across no chain edge (the oracle's)
};

// Partitions `tm` by `net` and checks every property; returns the report and what the oracle
// (bench/battery/fit_oracle.h) finds: every network vertex a mesh vertex, which segments are
// chains of mesh edges on them, the regions across those chains. The chains' edges must be curve
// edges, and the report must count the oracle's regions when it embedded every segment.
Partitioned partition_and_check(Mesh& tm, const meshfit::Curve_network& net) {
  const Normals before = vertex_normals(tm);
  const std::size_t nv = tm.number_of_vertices(), nf = tm.number_of_faces();
  auto ecm = tm.add_property_map<Mesh::Edge_index, bool>("e:curve", false).first;
  auto fpm = tm.add_property_map<Mesh::Face_index, int>("f:region", -1).first;
  Partitioned out;
  out.report = meshfit::partition_mesh(tm, net, CGAL::parameters::edge_is_constrained_map(ecm).face_patch_map(fpm));
  require_valid_and_unflipped(tm, before, nv, nf);
  const fit_oracle::Network oracle_net = meshfit_test::oracle_network(net);
  const fit_oracle::Embedding embedded = fit_oracle::embedding(tm, oracle_net);
  CHECK(embedded.missing == 0);
  out.chains = oracle_net.segments.size() - std::size_t(embedded.not_chained);
  out.regions = std::size_t(embedded.regions);
  std::size_t chain_edges_not_curve = 0;
  for (auto e : tm.edges()) chain_edges_not_curve += embedded.chain_edge[e.idx()] && !ecm[e];
  CHECK(chain_edges_not_curve == 0);
  if (out.report.not_embedded.empty()) CHECK(out.report.regions == out.regions);
  // Regions: every face labelled, in [0, regions), and no curve-free edge between two regions.
  for (auto f : tm.faces()) {
    REQUIRE(fpm[f] >= 0);
    REQUIRE(static_cast<std::size_t>(fpm[f]) < out.report.regions);
  }
  for (auto e : tm.edges()) {
    if (tm.is_border(e) || ecm[e]) continue;
    CHECK(fpm[tm.face(tm.halfedge(e, 0))] == fpm[tm.face(tm.halfedge(e, 1))]);
  }
  return out;
}

// An n×n grid on [0,n]² whose vertices are perturbed in the plane by up to `jitter` (seeded) and
// lifted by z = f(x, y).
template <typename Height>
Mesh jittered_grid(std::size_t n, double jitter, unsigned seed, Height f) {
  meshfit::Mesh_data d = meshfit_test::grid(n);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  for (auto& p : d.points) {
    const bool border = p.x() == 0 || p.y() == 0 || p.x() == double(n) || p.y() == double(n);
    const double x = border ? p.x() : p.x() + u(rng), y = border ? p.y() : p.y() + u(rng);
    p = Point_3(x, y, f(x, y));
  }
  return make_mesh(d);
}

}  // namespace

// --- the walk -----------------------------------------------------------------------------------

TEST_CASE("surface walk: across a flat region, crossing edges to the end vertex", "[walk]") {
  Mesh tm = make_mesh(meshfit_test::grid(6));
  const auto path = meshfit::project_segment(tm, vertex_at(tm, 0, 0), vertex_at(tm, 5, 2));
  REQUIRE(path.status == meshfit::Walk_status::reached);
  CHECK(path.waypoints.size() == 2);
  CHECK(path.crossings.size() == 1);
  CHECK(path.crossings[0].size() >= 5);  // the line y = 2x/5 crosses 5 vertical grid lines
  // Every crossed edge has its ends on opposite sides of the line (in the plane z = 0).
  for (auto h : path.crossings[0]) {
    const Point_3 p = tm.point(tm.source(h)), q = tm.point(tm.target(h));
    CHECK(CGAL::orientation(meshfit::Kernel::Point_2(0, 0), meshfit::Kernel::Point_2(5, 2), meshfit::Kernel::Point_2(p.x(), p.y())) ==
          -CGAL::orientation(meshfit::Kernel::Point_2(0, 0), meshfit::Kernel::Point_2(5, 2), meshfit::Kernel::Point_2(q.x(), q.y())));
  }
}

TEST_CASE("surface walk: a segment between adjacent vertices is the edge", "[walk]") {
  Mesh tm = make_mesh(meshfit_test::grid(3));
  const auto path = meshfit::project_segment(tm, vertex_at(tm, 1, 1), vertex_at(tm, 2, 1));
  REQUIRE(path.status == meshfit::Walk_status::reached);
  CHECK(path.waypoints.size() == 2);
  CHECK(path.crossings[0].empty());
}

TEST_CASE("surface walk: along existing edges through a vertex", "[walk]") {
  // The grid's diagonals run from (i, j) to (i+1, j+1): the segment (0,0)-(3,3) is three edges.
  Mesh tm = make_mesh(meshfit_test::grid(4));
  const auto path = meshfit::project_segment(tm, vertex_at(tm, 0, 0), vertex_at(tm, 3, 3));
  REQUIRE(path.status == meshfit::Walk_status::reached);
  REQUIRE(path.waypoints.size() == 4);
  CHECK(tm.point(path.waypoints[1]) == Point_3(1, 1, 0));
  CHECK(tm.point(path.waypoints[2]) == Point_3(2, 2, 0));
  for (const auto& c : path.crossings) CHECK(c.empty());
}

TEST_CASE("surface walk: exactly through a vertex between crossed edges", "[walk]") {
  Mesh tm = make_mesh(meshfit_test::grid(5));
  const auto path = meshfit::project_segment(tm, vertex_at(tm, 0, 0), vertex_at(tm, 4, 2));
  REQUIRE(path.status == meshfit::Walk_status::reached);
  REQUIRE(path.waypoints.size() == 3);
  CHECK(tm.point(path.waypoints[1]) == Point_3(2, 1, 0));
  CHECK(!path.crossings[0].empty());
  CHECK(!path.crossings[1].empty());
}

TEST_CASE("surface walk: across a fold", "[walk]") {
  // A jittered grid bent down by 20 degrees along x = 3 (a ridge).
  const double slope = std::tan(CGAL_PI / 9);
  Mesh tm = jittered_grid(6, 0.2, 5, [slope](double x, double) { return -slope * std::max(0.0, x - 3); });
  const V a = grid_vertex(6, 0, 1), b = grid_vertex(6, 6, 4);
  const auto path = meshfit::project_segment(tm, a, b);
  REQUIRE(path.status == meshfit::Walk_status::reached);
  std::size_t crossed = 0;
  for (const auto& c : path.crossings) crossed += c.size();
  CHECK(crossed >= 6);
  // Every crossing is on the cutting plane's two sides, on both flanks of the ridge.
  bool on_slope = false, on_flat = false;
  for (const auto& c : path.crossings)
    for (auto h : c) {
      CHECK(path.plane.side(tm.point(tm.source(h))) == -path.plane.side(tm.point(tm.target(h))));
      (tm.point(tm.source(h)).x() > 3.2 ? on_slope : on_flat) = true;
    }
  CHECK(on_slope);
  CHECK(on_flat);
  // And it is inserted as a chain of edges across the ridge.
  const auto net = network_of({{tm.point(a), tm.point(b)}});
  const Partitioned p = partition_and_check(tm, net);
  CHECK(p.report.not_embedded.empty());
  CHECK(p.chains == 1);
}

TEST_CASE("surface walk: stops at the boundary of an open mesh", "[walk]") {
  // An L-shaped domain: the grid without its upper-right quarter. The segment from the top arm
  // to the right arm would cross the missing part (and meets no grid vertex on the way).
  meshfit::Mesh_data d = meshfit_test::grid(6);
  meshfit::Mesh_data l = d;
  l.triangles.clear();
  for (const auto& t : d.triangles) {
    double cx = 0, cy = 0;
    for (std::size_t k : t) cx += d.points[k].x() / 3, cy += d.points[k].y() / 3;
    if (!(cx > 3 && cy > 3)) l.triangles.push_back(t);
  }
  Mesh tm;
  meshfit::build_triangle_mesh(l, tm);
  CGAL::Polygon_mesh_processing::remove_isolated_vertices(tm);
  tm.collect_garbage();
  const auto path = meshfit::project_segment(tm, vertex_at(tm, 1, 6), vertex_at(tm, 6, 2));
  CHECK(path.status == meshfit::Walk_status::boundary);
  // The partition then takes the fallback of the thesis's fig. 3.6: the shortest edge path
  // around the corner, moved onto the segment (the corner's vertices move into the gap).
  const auto net = network_of({{Point_3(1, 6, 0), Point_3(6, 2, 0)}});
  const Partitioned p = partition_and_check(tm, net);
  CHECK(p.report.by_fallback == 1);
  CHECK(p.chains == 1);
}

TEST_CASE("surface walk: will not cross a constrained edge", "[walk]") {
  Mesh tm = make_mesh(meshfit_test::grid(4));
  auto ecm = tm.add_property_map<Mesh::Edge_index, bool>("e:c", false).first;
  // Constrain the vertical grid line x = 2.
  for (auto e : tm.edges())
    if (tm.point(tm.vertex(e, 0)).x() == 2 && tm.point(tm.vertex(e, 1)).x() == 2) ecm[e] = true;
  const auto path = meshfit::project_segment(tm, vertex_at(tm, 0, 1), vertex_at(tm, 4, 2),
                                             CGAL::parameters::edge_is_constrained_map(ecm));
  CHECK(path.status == meshfit::Walk_status::constrained_edge);
}

// --- insertion ----------------------------------------------------------------------------------

TEST_CASE("partition: inserting a segment keeps the face and vertex counts and flips nothing", "[partition]") {
  Mesh tm = jittered_grid(10, 0.25, 7, [](double, double) { return 0.0; });
  const auto net = network_of({{tm.point(grid_vertex(10, 0, 3)), tm.point(grid_vertex(10, 10, 8))}});
  const Partitioned p = partition_and_check(tm, net);
  CHECK(p.report.by_walk == 1);
  CHECK(p.report.not_embedded.empty());
  CHECK(p.report.faces_crossed >= 10);
  CHECK(p.chains == 1);
  CHECK(p.regions == 2);
}

TEST_CASE("partition: a network with a feature point, a closed loop, curves ending on the boundary",
          "[partition]") {
  // A wavy open sheet. A closed loop around the middle; a curve from the left boundary to the
  // right boundary through two loop corners (feature points of degree 4); a segment that is an
  // edge already; two segments sharing an end.
  const std::size_t n = 16;
  Mesh tm = jittered_grid(n, 0.2, 11, [](double x, double y) { return 0.5 * std::sin(x / 3) * std::cos(y / 4); });
  auto P = [&](std::size_t i, std::size_t j) { return tm.point(grid_vertex(n, i, j)); };
  const auto net = network_of({
      {P(4, 5), P(12, 4), P(11, 12), P(5, 11), P(4, 5)},  // closed loop
      {P(0, 7), P(4, 5)},                                  // boundary to the loop
      {P(11, 12), P(16, 9)},                               // the loop to the boundary
      {P(12, 4), P(13, 4), P(15, 1)},                      // an existing edge, then a diagonal run
  });
  REQUIRE(net.feature_points().size() == 3);
  const Partitioned p = partition_and_check(tm, net);
  INFO("walk " << p.report.by_walk << " fallback " << p.report.by_fallback << " existing " << p.report.existing_edges);
  CHECK(p.report.not_embedded.empty());
  CHECK(p.chains == net.number_of_segments());
  CHECK(p.report.existing_edges >= 1);
  // Inside the loop, and outside it split by the boundary-to-boundary curve: 3 regions.
  CHECK(p.regions == 3);
}

TEST_CASE("partition: three great circles on a sphere make 8 regions", "[partition][sphere]") {
  // Sphere vertices: 2000 random points and the circles' samples (every 15 degrees, so the 6
  // crossings are samples); the mesh is their convex hull, so the samples are mesh vertices but
  // the hull's edges do not follow the circles.
  std::mt19937 rng(2007);
  std::normal_distribution<double> g;
  std::vector<Point_3> pts;
  for (int i = 0; i < 2000; ++i) {
    const Vector_3 v(g(rng), g(rng), g(rng));
    pts.push_back(CGAL::ORIGIN + v / std::sqrt(v.squared_length()));
  }
  std::vector<std::vector<Point_3>> circles(3);
  for (int k = 0; k <= 24; ++k) {
    const double t = k * CGAL_PI / 12;
    const double c = k % 6 == 0 ? std::round(std::cos(t)) : std::cos(t);
    const double s = k % 6 == 0 ? std::round(std::sin(t)) : std::sin(t);
    circles[0].emplace_back(c, s, 0);
    circles[1].emplace_back(0, c, s);
    circles[2].emplace_back(s, 0, c);
  }
  for (const auto& circle : circles) pts.insert(pts.end(), circle.begin(), circle.end() - 1);
  Mesh tm;
  CGAL::convex_hull_3(pts.begin(), pts.end(), tm);
  const auto net = network_of(circles);
  REQUIRE(net.number_of_vertices() == 66);
  REQUIRE(net.feature_points().size() == 6);
  std::size_t edges_before = 0;
  for (const auto& s : net.segments()) {
    V a, b;
    for (auto v : tm.vertices()) {
      if (tm.point(v) == net.point(s[0])) a = v;
      if (tm.point(v) == net.point(s[1])) b = v;
    }
    edges_before += tm.halfedge(a, b) != Mesh::null_halfedge();
  }
  const Partitioned p = partition_and_check(tm, net);
  INFO("segments that were edges " << edges_before << ", walk " << p.report.by_walk << ", fallback "
                                   << p.report.by_fallback << ", faces crossed " << p.report.faces_crossed);
  CHECK(edges_before < net.number_of_segments());
  CHECK(p.report.not_embedded.empty());
  CHECK(p.chains == 72);
  CHECK(p.regions == 8);
  CHECK(p.report.by_walk > 0);
}

#ifdef MESHFIT_CGAL_DATA_DIR
TEST_CASE("partition: a loop of the elephant's own vertices splits it in two", "[partition][real]") {
  Mesh tm;
  meshfit::read_triangle_mesh(MESHFIT_CGAL_DATA_DIR "/elephant.off", tm);
  // The faces within 5 edges of a vertex form a disc; every second vertex of its boundary is a
  // point of a closed polyline, so the segments skip a vertex and are not edges.
  const V seed(100);
  std::map<V, int> hops{{seed, 0}};
  std::deque<V> queue{seed};
  while (!queue.empty()) {
    const V v = queue.front();
    queue.pop_front();
    if (hops[v] == 5) continue;
    for (V u : CGAL::vertices_around_target(v, tm))
      if (!hops.count(u)) hops[u] = hops[v] + 1, queue.push_back(u);
  }
  auto inside = tm.add_property_map<Mesh::Face_index, bool>("f:in", false).first;
  for (auto f : tm.faces()) {
    bool all = true;
    for (V v : CGAL::vertices_around_face(tm.halfedge(f), tm)) all = all && hops.count(v);
    inside[f] = all;
  }
  CGAL::Face_filtered_graph<Mesh> disc(tm, true, inside);
  std::vector<Point_3> loop;
  for (auto h : CGAL::halfedges(disc)) {
    if (!CGAL::is_border(h, disc)) continue;
    for (auto b : CGAL::halfedges_around_face(h, disc)) loop.push_back(tm.point(target(b, disc)));
    break;
  }
  REQUIRE(loop.size() >= 20);
  std::vector<Point_3> polyline;
  for (std::size_t i = 0; i < loop.size(); i += 2) polyline.push_back(loop[i]);
  polyline.push_back(polyline.front());
  const auto net = network_of({polyline});
  const Partitioned p = partition_and_check(tm, net);
  INFO("walk " << p.report.by_walk << " fallback " << p.report.by_fallback << " existing " << p.report.existing_edges);
  CHECK(p.report.not_embedded.empty());
  CHECK(p.chains == net.number_of_segments());
  CHECK(p.regions == 2);
}
#endif

TEST_CASE("partition: random networks on random meshes keep the mesh valid", "[partition][random]") {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    INFO("seed " << seed);
    const std::size_t n = 12;
    Mesh tm = jittered_grid(n, 0.3, seed, [seed](double x, double y) {
      return 0.7 * std::sin(0.3 * x * (1 + seed % 3)) * std::sin(0.4 * y);
    });
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::size_t> u(0, n);
    std::vector<std::vector<Point_3>> polylines;
    for (int c = 0; c < 3; ++c) {
      std::vector<Point_3> pl;
      for (int k = 0; k < 4; ++k) {
        const Point_3 q = tm.point(grid_vertex(n, u(rng), u(rng)));
        if (pl.empty() || pl.back() != q) pl.push_back(q);
      }
      if (pl.size() >= 2) polylines.push_back(pl);
    }
    const auto net = network_of(polylines);
    const Partitioned p = partition_and_check(tm, net);
    CHECK(p.chains + p.report.not_embedded.size() == net.number_of_segments());
    CHECK(p.report.by_walk + p.report.by_fallback + p.report.existing_edges + p.report.not_embedded.size() ==
          net.number_of_segments());
  }
}

TEST_CASE("partition: the embedded example after deformation", "[partition][example]") {
  Mesh tm;
  meshfit::read_triangle_mesh(MESHFIT_EXAMPLE_DATA_DIR "/template.off", tm);
  const auto net = meshfit::read_curve_network(MESHFIT_EXAMPLE_DATA_DIR "/curves.polylines.txt");
  const auto pairs = meshfit::read_correspondences(MESHFIT_EXAMPLE_DATA_DIR "/pairs.txt", net);
  const auto d = meshfit::deform_template(tm, net, pairs);
  REQUIRE(d.remaining_flips == 0);
  const Partitioned p = partition_and_check(tm, net);
  INFO("walk " << p.report.by_walk << " fallback " << p.report.by_fallback << " existing " << p.report.existing_edges);
  CHECK(p.report.not_embedded.empty());
  CHECK(p.chains == net.number_of_segments());
  // 4 plane sections meeting at 10 feature points: V - E + F = 2 on the sphere gives
  // F = 2 - 210 + 220 = 12 regions.
  CHECK(p.regions == 12);
}

TEST_CASE("partition: works on Polyhedron_3", "[partition][generic]") {
  using Poly = CGAL::Polyhedron_3<meshfit::Kernel>;
  Poly poly;
  meshfit::build_triangle_mesh(meshfit_test::grid(6), poly);
  const auto net = network_of({{Point_3(0, 1, 0), Point_3(6, 4, 0)}, {Point_3(6, 4, 0), Point_3(2, 6, 0)}});
  std::map<boost::graph_traits<Poly>::edge_descriptor, bool> curve;
  std::map<boost::graph_traits<Poly>::face_descriptor, int> region;
  const auto r = meshfit::partition_mesh(poly, net,
                                         CGAL::parameters::edge_is_constrained_map(boost::make_assoc_property_map(curve))
                                             .face_patch_map(boost::make_assoc_property_map(region)));
  CHECK(r.not_embedded.empty());
  CHECK(r.by_walk == 2);
  CHECK(r.regions == 3);  // boundary to boundary, twice
  CHECK(poly.size_of_facets() == 72);
  CHECK(CGAL::is_valid_polygon_mesh(poly));
  // The oracle on a copy: both segments chains of edges, 3 regions across them.
  const fit_oracle::Embedding embedded =
      fit_oracle::embedding(fit_oracle::copy_of(poly), meshfit_test::oracle_network(net));
  CHECK(embedded.missing == 0);
  CHECK(embedded.not_chained == 0);
  CHECK(embedded.regions == 3);
}

TEST_CASE("partition: a network vertex that is not a mesh vertex is an error naming it", "[partition]") {
  Mesh tm = make_mesh(meshfit_test::grid(3));
  const auto net = network_of({{Point_3(0, 0, 0), Point_3(1.5, 2, 0)}});
  meshfit_test::require_invalid([&] { meshfit::partition_mesh(tm, net); }, 0, "network vertex 1 (1.5");
}

}  // namespace meshfit_partition_test
