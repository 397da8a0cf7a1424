#include <meshfit/fit.h>
#include <meshfit/internal/angle_flips.h>
#include <meshfit/internal/chain_spacing.h>
#include <meshfit/internal/fit_checks.h>
#include <meshfit/io.h>

#include <CGAL/Surface_mesh.h>

#include "oracle_helpers.h"
#include "test_helpers.h"

#include <algorithm>
#include <map>
#include <random>
#include <set>

namespace meshfit_fit_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;

namespace {

struct Inputs {
  Mesh tm;
  meshfit::Curve_network network;
  std::vector<meshfit::Correspondence> pairs;
};

Inputs example() {
  Inputs in;
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  meshfit::read_triangle_mesh(d + "/template.off", in.tm);
  in.network = meshfit::read_curve_network(d + "/curves.polylines.txt");
  in.pairs = meshfit::read_correspondences(d + "/pairs.txt", in.network);
  return in;
}

}  // namespace

TEST_CASE("fit: the embedded example is fitted, partitioned into 12 regions and verified", "[fit][example]") {
  Inputs in = example();
  const Mesh template_mesh = in.tm;
  const std::size_t template_vertices = in.tm.number_of_vertices();
  auto curve = in.tm.add_property_map<Mesh::Edge_index, bool>("e:curve", false).first;
  auto region = in.tm.add_property_map<Mesh::Face_index, int>("f:region", -1).first;
  std::vector<std::string> stages;
  const meshfit::Fit_report r = meshfit::fit_template_to_curves(
      in.tm, in.network, in.pairs,
      meshfit::parameters::progress([&](const meshfit::Progress_step& s) {
        if (stages.empty() || stages.back() != s.stage) stages.push_back(s.stage);
        return true;
      })
          .edge_is_constrained_map(curve)
          .face_patch_map(region));
  // The oracle judges the result (every network vertex a vertex, every segment a chain of edges,
  // 12 regions, no fold, intersection or zero-area face added); the report must say the same.
  const fit_oracle::Network curves =
      fit_oracle::network_of(fit_oracle::read_polylines(MESHFIT_EXAMPLE_DATA_DIR "/curves.polylines.txt"));
  const fit_oracle::Fit_check check = fit_oracle::check_fit(in.tm, template_mesh, curves, 12);
  INFO(meshfit_test::describe(check));
  CHECK(check.passed());
  CHECK(r.verification.passed());
  CHECK(stages == std::vector<std::string>{"deform", "partition", "smooth", "fit"});
  CHECK(r.partition.regions == 12);
  CHECK(r.verification.expected_regions_known);
  CHECK(r.verification.expected_regions == 12);
  CHECK(r.partition.not_embedded.empty());
  CHECK(r.verification.folded_edges == 0);
  CHECK(r.faces == in.tm.number_of_faces());
  CHECK(in.tm.number_of_vertices() == r.vertices);
  CHECK(in.tm.number_of_vertices() >= template_vertices);
  // The maps were filled on the result: 12 region labels, curve edges along every segment (the
  // oracle's chain edges).
  std::set<int> labels;
  for (auto f : in.tm.faces()) labels.insert(region[f]);
  CHECK(labels.size() == 12);
  CHECK(*labels.begin() == 0);
  std::size_t curve_edges = 0, chain_edges_not_curve = 0;
  for (auto e : in.tm.edges()) {
    curve_edges += curve[e];
    chain_edges_not_curve += check.embedding.chain_edge[e.idx()] && !curve[e];
  }
  CHECK(curve_edges >= in.network.number_of_segments());
  CHECK(chain_edges_not_curve == 0);
  // Vertex i is template vertex i: the user's pairs sit on their network vertices.
  for (const auto& c : in.pairs)
    CHECK(in.tm.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(c.template_vertex))) ==
          in.network.point(c.network_vertex));
  // Every network vertex is a mesh vertex, exactly.
  for (std::size_t v = 0; v < in.network.number_of_vertices(); ++v)
    CHECK(in.tm.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(r.mesh_vertex_of_network_vertex[v]))) ==
          in.network.point(v));
}

TEST_CASE("fit: cancelling through the progress callback leaves the template untouched", "[fit]") {
  for (const char* stop_at : {"deform", "partition", "smooth", "fit"}) {
    INFO("cancelled in " << stop_at);
    Inputs in = example();
    const meshfit::Mesh_data before = meshfit::to_mesh_data(in.tm);
    bool thrown = false;
    try {
      meshfit::fit_template_to_curves(
          in.tm, in.network, in.pairs,
          meshfit::parameters::progress([&](const meshfit::Progress_step& s) { return s.stage != stop_at; }));
    } catch (const meshfit::Algorithm_failure& e) {
      thrown = std::string(e.what()).find("cancelled") != std::string::npos;
    }
    CHECK(thrown);
    const meshfit::Mesh_data after = meshfit::to_mesh_data(in.tm);
    CHECK(after.points == before.points);
    CHECK(after.triangles == before.triangles);
  }
}

TEST_CASE("fit: pairs that mirror the template fail in stage 1 and leave it untouched", "[fit]") {
  Inputs in = example();
  const meshfit::Mesh_data before = meshfit::to_mesh_data(in.tm);
  // Mirror the network's x: the same template vertices now go to mirrored points.
  std::vector<meshfit::Curve_network::Polyline> mirrored;
  for (const auto& pl : in.network.polylines()) {
    meshfit::Curve_network::Polyline m;
    for (std::size_t v : pl) m.emplace_back(-in.network.point(v).x(), in.network.point(v).y(), in.network.point(v).z());
    mirrored.push_back(m);
  }
  const meshfit::Curve_network net(mirrored);
  std::vector<meshfit::Correspondence> pairs = in.pairs;
  for (auto& c : pairs) {
    const meshfit::Point_3& p = in.network.point(c.network_vertex);
    c.network_vertex = *net.find_vertex(meshfit::Point_3(-p.x(), p.y(), p.z()));
  }
  CHECK_THROWS_AS(meshfit::fit_template_to_curves(in.tm, net, pairs), meshfit::Algorithm_failure);
  CHECK(meshfit::to_mesh_data(in.tm).points == before.points);
}

namespace {

// Fits and returns the report. The result must pass the independent oracle (bench/battery/
// fit_oracle.h: the curves file read on its own, every network vertex a mesh vertex, every segment
// a chain of mesh edges, `regions` regions across them, no fold, intersecting pair or zero-area
// face added to the template's); the report must agree.
meshfit::Fit_report fit_and_verify(const std::string& template_path, const std::string& curves,
                                   const std::string& pairs_path, long regions) {
  Mesh tm;
  meshfit::read_triangle_mesh(template_path, tm);
  const Mesh template_mesh = tm;
  const auto network = meshfit::read_curve_network(curves);
  const auto pairs = meshfit::read_correspondences(pairs_path, network);
  const meshfit::Fit_report r = meshfit::fit_template_to_curves(tm, network, pairs);
  const fit_oracle::Fit_check check =
      fit_oracle::check_fit(tm, template_mesh, fit_oracle::network_of(fit_oracle::read_polylines(curves)), regions);
  INFO(meshfit_test::describe(check));
  CHECK(check.passed());
  // The report agrees.
  CHECK(r.verification.passed());
  CHECK(r.partition.not_embedded.empty());
  CHECK(r.partition.regions == std::size_t(check.embedding.regions));
  CHECK(r.faces == tm.number_of_faces());
  return r;
}

}  // namespace

TEST_CASE("fit: the same sphere template fitted to a second network (peanut)", "[fit][example]") {
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  const auto r = fit_and_verify(d + "/template.off", d + "/curves-2.polylines.txt", d + "/pairs-2.txt", 16);
  CHECK(r.partition.regions == 16);
}

TEST_CASE("fit: an open template fitted to a network that includes its boundary", "[fit][example][open]") {
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  const auto r =
      fit_and_verify(d + "/sheet/template.off", d + "/sheet/curves.polylines.txt", d + "/sheet/pairs.txt", 4);
  CHECK(r.partition.regions == 4);
}

namespace {
// The unit square as an n x n grid template (vertex (i, j) = j (n + 1) + i).
Mesh unit_square(std::size_t n) {
  Mesh tm;
  meshfit::Mesh_data sheet = meshfit_test::grid(n);
  for (auto& p : sheet.points) p = meshfit::Point_3(p.x() / double(n), p.y() / double(n), 0);
  meshfit::build_triangle_mesh(sheet, tm);
  return tm;
}
}  // namespace

TEST_CASE("fit: an open grid onto a larger saddle: curves leaving the coarse surface stay inside", "[fit][open]") {
  // The template is the unit square; the network is the square [-0.08, 1.08]² lifted onto a saddle,
  // its boundary and two lines each way, all sampled at the same parameters (crossings are the
  // same doubles). The pairs put the template's inner crossings on the network's, so the coarse
  // surface stays the unit square: the outer parts of the lines lie beyond its border, their
  // nearest points on it. Oracles of this test's own: every segment is a path of mesh edges whose
  // vertices lie on it, the faces fall into 9 regions across those edges, and no face turns over
  // (the saddle is a height field, every face must keep facing +z); and the shared oracle's.
  Mesh tm = unit_square(24);
  const Mesh template_mesh = tm;
  auto lift = [](double x, double y) { return meshfit::Point_3(x, y, 0.5 * ((x - 0.5) * (x - 0.5) - (y - 0.5) * (y - 0.5))); };
  const std::vector<double> t = {-0.08, 0.05, 0.15, 0.3, 0.5, 0.7, 0.85, 0.95, 1.08};
  std::vector<meshfit::Curve_network::Polyline> lines;
  for (double k : {-0.08, 0.3, 0.7, 1.08}) {
    meshfit::Curve_network::Polyline a, b;
    for (double u : t) a.push_back(lift(k, u)), b.push_back(lift(u, k));
    lines.push_back(a);
    lines.push_back(b);
  }
  const meshfit::Curve_network network(lines);
  std::vector<meshfit::Correspondence> pairs;
  for (double x : {0.3, 0.7})
    for (double y : {0.3, 0.7}) {
      meshfit::Correspondence c;
      c.network_vertex = *network.find_vertex(lift(x, y));
      c.template_vertex = static_cast<std::size_t>(std::lround(y * 24) * 25 + std::lround(x * 24));
      pairs.push_back(c);
    }
  auto curve = tm.add_property_map<Mesh::Edge_index, bool>("e:curve", false).first;
  meshfit::fit_template_to_curves(tm, network, pairs, CGAL::parameters::edge_is_constrained_map(curve));
  {
    const fit_oracle::Fit_check check = fit_oracle::check_fit(tm, template_mesh, fit_oracle::network_of(lines), 9);
    INFO(meshfit_test::describe(check));
    CHECK(check.passed());
  }
  // Chains: from a's vertex, step to the neighbour on segment ab farthest along it (greedy).
  auto vertex_at = [&](const meshfit::Point_3& p) {
    for (auto v : tm.vertices())
      if (tm.point(v) == p) return v;
    return Mesh::null_vertex();
  };
  std::size_t not_chains = 0;
  std::set<Mesh::Edge_index> chain_edges;
  for (const auto& [a, b] : network.segments()) {
    const meshfit::Point_3 &pa = network.point(a), &pb = network.point(b);
    const meshfit::Segment_3 ab(pa, pb);
    Mesh::Vertex_index u = vertex_at(pa);
    const Mesh::Vertex_index end = vertex_at(pb);
    double along = 0;
    while (u != Mesh::null_vertex() && u != end) {
      Mesh::Vertex_index next = Mesh::null_vertex();
      Mesh::Halfedge_index via;
      double next_along = 2;
      for (auto h : CGAL::halfedges_around_source(u, tm)) {
        const meshfit::Point_3& q = tm.point(tm.target(h));
        const double s = ((q - pa) * (pb - pa)) / (pb - pa).squared_length();
        if (s > along && s <= 1 + 1e-12 && s < next_along && CGAL::squared_distance(ab, q) < 1e-20)
          next = tm.target(h), via = h, next_along = s;
      }
      if (next != Mesh::null_vertex()) chain_edges.insert(tm.edge(via)), along = next_along;
      u = next;
    }
    not_chains += u != end;
  }
  CHECK(not_chains == 0);
  // Regions: faces joined across edges that are no chain edge.
  std::map<Mesh::Face_index, int> label;
  int regions = 0;
  for (auto f0 : tm.faces()) {
    if (label.count(f0)) continue;
    std::vector<Mesh::Face_index> stack{f0};
    label[f0] = regions;
    while (!stack.empty()) {
      const auto f = stack.back();
      stack.pop_back();
      for (auto h : CGAL::halfedges_around_face(tm.halfedge(f), tm)) {
        const auto g = tm.face(tm.opposite(h));
        if (g == Mesh::null_face() || chain_edges.count(tm.edge(h)) || label.count(g)) continue;
        label[g] = regions;
        stack.push_back(g);
      }
    }
    ++regions;
  }
  CHECK(regions == 9);
  std::size_t turned = 0;
  for (auto f : tm.faces()) {
    const auto h = tm.halfedge(f);
    const meshfit::Point_3 &a = tm.point(tm.source(h)), &b = tm.point(tm.target(h)), &c = tm.point(tm.target(tm.next(h)));
    turned += !(CGAL::cross_product(b - a, c - a).z() > 0);
  }
  CHECK(turned == 0);
}

TEST_CASE("fit: an open grid onto a saddle whose boundary is in the network follows it to its border", "[fit][open]") {
  // The unit square (24 x 24) onto z = 0.7((x - 1/2)^2 - (y - 1/2)^2), the network the lifted
  // square's boundary (sampled at every third template edge) and the lines x, y = 1/3, 2/3 (at
  // every edge), crossings the same doubles; 8 pairs where the lines meet the boundary. The saddle
  // is curved across the border: a thin-plate energy that held the slope across the border at 0
  // ended the battery's open-plane-saddle-boundary 1.04 % of the diagonal from the truth (0.48 %
  // now; here 0.49 %). Oracles: the shared one (9 regions), and every vertex's height against
  // the saddle's there.
  Mesh tm = unit_square(24);
  const Mesh template_mesh = tm;
  auto height = [](double x, double y) { return 0.7 * ((x - 0.5) * (x - 0.5) - (y - 0.5) * (y - 0.5)); };
  auto lift = [&](double x, double y) { return meshfit::Point_3(x, y, height(x, y)); };
  std::vector<meshfit::Curve_network::Polyline> lines;
  for (int k : {0, 8, 16, 24}) {
    meshfit::Curve_network::Polyline a, b;
    const bool side = k == 0 || k == 24;
    for (int j = 0; j <= 24; ++j)
      if (!side || j % 3 == 0 || j % 8 == 0) a.push_back(lift(k / 24.0, j / 24.0)), b.push_back(lift(j / 24.0, k / 24.0));
    lines.push_back(a);
    lines.push_back(b);
  }
  const meshfit::Curve_network network(lines);
  std::vector<meshfit::Correspondence> pairs;
  for (const auto& [i, j] : std::vector<std::pair<int, int>>{{8, 0}, {16, 0}, {24, 8}, {24, 16}, {16, 24}, {8, 24}, {0, 16}, {0, 8}}) {
    meshfit::Correspondence c;
    c.network_vertex = *network.find_vertex(lift(i / 24.0, j / 24.0));
    c.template_vertex = static_cast<std::size_t>(j * 25 + i);
    pairs.push_back(c);
  }
  meshfit::fit_template_to_curves(tm, network, pairs);
  const fit_oracle::Fit_check check = fit_oracle::check_fit(tm, template_mesh, fit_oracle::network_of(lines), 9);
  INFO(meshfit_test::describe(check));
  CHECK(check.passed());
  double worst = 0, diagonal = std::sqrt(2 + 0.35 * 0.35);
  for (auto v : tm.vertices()) {
    const meshfit::Point_3& p = tm.point(v);
    worst = std::max(worst, std::abs(p.z() - height(p.x(), p.y())));
  }
  INFO("largest height error " << worst << ", " << 100 * worst / diagonal << " % of the diagonal");
  CHECK(worst < 0.01 * diagonal);
}

namespace {
// A battery case kept in test/data (its truth left out), read with meshfit's readers; `check`
// scores a fit of it with the shared oracle, which reads the curves again with its own reader.
struct Data_case {
  std::string dir;
  Mesh tm;
  meshfit::Curve_network network;
  std::vector<meshfit::Correspondence> pairs;
  fit_oracle::Fit_check check(const Mesh& fitted, std::size_t regions) const {
    return fit_oracle::check_fit(fitted, tm, fit_oracle::network_of(fit_oracle::read_polylines(dir + "/curves.polylines.txt")),
                                 regions);
  }
};
Data_case load_data_case(const std::string& name) {
  const std::string dir = MESHFIT_TEST_DATA_DIR "/" + name;
  Mesh tm;
  meshfit::read_triangle_mesh(dir + "/template.off", tm);
  Data_case c{dir, tm, meshfit::read_curve_network(dir + "/curves.polylines.txt"), {}};
  c.pairs = meshfit::read_correspondences(dir + "/pairs.txt", c.network);
  return c;
}
}  // namespace

TEST_CASE("fit: an open template onto a wave whose boundary is in the network keeps its border on the curves",
          "[fit][open]") {
  // The battery's open-plane-wave-boundary (test/data/open-plane-wave-boundary/README.md): CGAL's
  // plane onto a wave, the network 4 lines and the square's boundary, 9 regions. When the curves
  // along the border pulled the surface's nearest points rather than the border's, the border
  // flared out past the network's corners: 11 regions, and fit's own verification, which cannot
  // know the count once a border cycle is only partly on curves, let it through. Oracle: the
  // shared one, with the 9 regions the network bounds.
  const Data_case c = load_data_case("open-plane-wave-boundary");
  Mesh tm = c.tm;
  meshfit::fit_template_to_curves(tm, c.network, c.pairs);
  const fit_oracle::Fit_check check = c.check(tm, 9);
  INFO(meshfit_test::describe(check));
  CHECK(check.passed());
}

TEST_CASE("fit: Fine_shape::automatic falls back to the approach's shape when the template's bending folds",
          "[fit][open][fine_shape]") {
  // The battery's open-patch-01-wave-boundary (test/data/open-patch-01-wave-boundary/README.md):
  // curved patch onto a wave. Asked for explicitly, the template's bending leaves faces flipped
  // after every start (measured: 11); the default shape, which resolves to the bending here (the
  // curves are no denser than the template's edges), must then try the approach's shape, which
  // leaves none. Oracle: the shared one, with the 9 regions the network bounds.
  const Data_case c = load_data_case("open-patch-01-wave-boundary");
  const meshfit::Curve_network& network = c.network;
  const auto& pairs = c.pairs;
  Mesh tm = c.tm, bent = c.tm;
  const auto forced = meshfit::deform_template(bent, network, pairs,
                                               meshfit::parameters::fine_shape(meshfit::Fine_shape::template_bending));
  CHECK(forced.fine_shape == meshfit::Fine_shape::template_bending);
  CHECK(forced.remaining_flips + forced.remaining_folds + forced.segments_not_embedded.size() > 0);
  // Where the defects lie: polylines of the network (measured: the first and the fourth of its 5).
  REQUIRE_FALSE(forced.polylines_near_defects.empty());
  CHECK(forced.polylines_near_defects.size() < network.polylines().size());
  for (std::size_t k : forced.polylines_near_defects) CHECK(k < network.polylines().size());
  CHECK(std::is_sorted(forced.polylines_near_defects.begin(), forced.polylines_near_defects.end()));
  const auto r = meshfit::fit_template_to_curves(tm, network, pairs);
  CHECK(r.deformation.fine_shape == meshfit::Fine_shape::approach);
  // (The fine level leaves one edge folded here, measured; the template has 49 folded edges and
  // the result no more, so the fit passes.)
  CHECK(r.deformation.polylines_near_defects.empty() == (r.deformation.remaining_flips + r.deformation.remaining_folds == 0));
  CHECK(r.deformation.displacement.held_beyond_band == 0);
  const fit_oracle::Fit_check check = c.check(tm, 9);
  INFO(meshfit_test::describe(check));
  CHECK(check.passed());
}

TEST_CASE("fit: a template with few vertices per region the network bounds is subdivided until the regions have a shape",
          "[fit][subdivision]") {
  // The battery's ico162-bumpy-latlong (test/data/ico162-bumpy-latlong/README.md): 162 template
  // vertices, 117 network vertices, 24 regions. Twice the network's vertices would ask for one
  // subdivision (642 vertices, 22 free ones per region); 40 per region ask for a second (2 562).
  // Oracle: the shared one with the 24 regions, and the bumpy sphere itself: every output vertex
  // and face centroid within 1 % of the diagonal of its radius there (measured: 1.50 % of the
  // diagonal from the truth after one subdivision, 0.77 % after two).
  const Data_case c = load_data_case("ico162-bumpy-latlong");
  REQUIRE(c.tm.number_of_vertices() == 162);
  REQUIRE(c.network.number_of_vertices() == 117);
  Mesh tm = c.tm;
  const auto r = meshfit::fit_template_to_curves(tm, c.network, c.pairs);
  CHECK(r.deformation.template_subdivisions == 2);
  const fit_oracle::Fit_check check = c.check(tm, 24);
  INFO(meshfit_test::describe(check));
  CHECK(check.passed());
  auto radius = [](const meshfit::Kernel::Vector_3& p) {
    const auto d = p / std::sqrt(p.squared_length());
    const double x = d.x(), y = d.y(), z = d.z();
    return 1.0 + 0.15 * (3 * x * x * y - y * y * y) + 0.5 * x * y * z + 0.08 * (5 * z * z * z - 3 * z) / 2;
  };
  CGAL::Bbox_3 box;
  for (auto v : tm.vertices()) box += tm.point(v).bbox();
  const double diagonal = std::sqrt(CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                                    CGAL::square(box.zmax() - box.zmin()));
  double worst = 0;
  auto off = [&](const meshfit::Point_3& p) {
    const auto v = p - CGAL::ORIGIN;
    worst = std::max(worst, std::abs(std::sqrt(v.squared_length()) - radius(v)));
  };
  for (auto v : tm.vertices()) off(tm.point(v));
  for (auto f : tm.faces()) {
    const auto h = tm.halfedge(f);
    off(CGAL::centroid(tm.point(tm.source(h)), tm.point(tm.target(h)), tm.point(tm.target(tm.next(h)))));
  }
  CHECK(worst < 0.01 * diagonal);
}

#ifdef MESHFIT_CGAL_DATA_DIR
TEST_CASE("fit: CGAL's elephant fitted to curves from a deformed copy of itself", "[fit][real]") {
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  const auto r = fit_and_verify(MESHFIT_CGAL_DATA_DIR "/elephant.off", d + "/elephant/curves.polylines.txt",
                                d + "/elephant/pairs.txt", 6);
  CHECK(r.partition.regions == 6);
  CHECK(r.deformation.remaining_flips == 0);
}

namespace {
// How many segments of `network` are not a chain of edges of `m`: from the vertex at one end's
// point, along edges whose far vertex lies on the segment (within 1e-9 of its length) and nearer
// the other end, to the vertex at the other end's point. The test's own oracle, not the library's.
std::size_t segments_not_edge_chains(const Mesh& m, const meshfit::Curve_network& network) {
  std::map<meshfit::Point_3, Mesh::Vertex_index> at;
  for (auto v : m.vertices()) at.emplace(m.point(v), v);
  std::size_t missing = 0;
  for (const auto& [a, b] : network.segments()) {
    const meshfit::Point_3 &pa = network.point(a), &pb = network.point(b);
    const auto ia = at.find(pa), ib = at.find(pb);
    if (ia == at.end() || ib == at.end()) {
      ++missing;
      continue;
    }
    const meshfit::Segment_3 seg(pa, pb);
    const double tolerance = 1e-9 * std::sqrt(seg.squared_length());
    Mesh::Vertex_index v = ia->second;
    for (std::size_t steps = 0; v != ib->second && steps < m.number_of_vertices(); ++steps) {
      Mesh::Vertex_index next = v;
      for (auto h : CGAL::halfedges_around_source(v, m)) {
        const auto w = m.target(h);
        if (CGAL::squared_distance(m.point(w), seg) <= tolerance * tolerance &&
            CGAL::squared_distance(m.point(w), pb) < CGAL::squared_distance(m.point(v), pb))
          next = w;
      }
      if (next == v) break;
      v = next;
    }
    missing += v != ib->second;
  }
  return missing;
}
}  // namespace

TEST_CASE("deform: CGAL's pig onto plane sections of a bent copy embeds every segment", "[deform][real]") {
  // examples/data/pig: the stress battery's real-pig case (4 sections of a bent, twisted,
  // anisotropically scaled copy, 10 crossings). A crossing's third segment is walled off by the
  // chains around it on every start; the fallback splits the edges in its way.
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  Mesh tm;
  meshfit::read_triangle_mesh(MESHFIT_CGAL_DATA_DIR "/pig.off", tm);
  const meshfit::Curve_network network = meshfit::read_curve_network(d + "/pig/curves.polylines.txt");
  const auto pairs = meshfit::read_correspondences(d + "/pig/pairs.txt", network);
  const meshfit::Deformation_report r = meshfit::deform_template(tm, network, pairs);
  CHECK(r.segments_not_embedded.empty());
  CHECK(segments_not_edge_chains(tm, network) == 0);
  CHECK(r.remaining_flips == 0);
}

TEST_CASE("fit: on CGAL's pig, which intersects itself, intersecting face pairs are counted on both", "[fit][real]") {
  // The pig has intersecting faces of its own; the counts are recounted here on the template and
  // on the result written back (a failed verification still writes it), and compared as the
  // verification must.
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  Mesh tm;
  meshfit::read_triangle_mesh(MESHFIT_CGAL_DATA_DIR "/pig.off", tm);
  auto count_pairs = [](const Mesh& m) { return std::size_t(fit_oracle::self_intersections(m)); };
  const std::size_t template_pairs = count_pairs(tm);
  REQUIRE(template_pairs > 0);
  const meshfit::Curve_network network = meshfit::read_curve_network(d + "/pig/curves.polylines.txt");
  const auto pairs = meshfit::read_correspondences(d + "/pig/pairs.txt", network);
  const meshfit::Fit_report r = meshfit::fit_template_to_curves(tm, network, pairs);
  const meshfit::Fit_verification& v = r.verification;
  REQUIRE(v.self_intersection_checked);
  const std::size_t result_pairs = count_pairs(tm);
  CHECK(v.self_intersects == (result_pairs > 0));
  if (!v.self_intersects) return;
  CHECK(v.template_self_intersects);
  CHECK(v.template_self_intersecting_pairs == template_pairs);
  CHECK(v.self_intersecting_pairs == result_pairs);
  const auto problems = v.problems();
  const bool said = std::any_of(problems.begin(), problems.end(), [](const std::string& p) {
    return p.find("pairs of faces intersect") != std::string::npos;
  });
  CHECK(said == (result_pairs > template_pairs));
}
#endif

namespace {
// A sheared grid whose diagonals all run the long way: every quadrilateral's other diagonal gives
// larger angles. `lift` bends it along x = 2 into a roof (0: flat).
meshfit::Mesh_data sheared_grid(std::size_t n, double lift) {
  meshfit::Mesh_data m = meshfit_test::grid(n);
  for (auto& p : m.points) {
    const double x = p.x() + 0.9 * p.y();
    p = meshfit::Point_3(x, p.y(), lift * std::abs(x - 2.0));
  }
  return m;
}

double smallest_angle_deg(const meshfit::Mesh_data& m) {
  double smallest = 180;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const meshfit::Vector_3 a = m.points[t[(k + 1) % 3]] - m.points[t[k]], b = m.points[t[(k + 2) % 3]] - m.points[t[k]];
      smallest = std::min(smallest, std::acos(a * b / std::sqrt(a.squared_length() * b.squared_length())) * 180 / CGAL_PI);
    }
  return smallest;
}
}  // namespace

TEST_CASE("fit: edge flips raise the smallest angle on flat parts, keeping curve edges, vertices and the surface",
          "[fit][flips]") {
  const meshfit::Mesh_data input = sheared_grid(6, 0);
  Mesh tm;
  meshfit::build_triangle_mesh(input, tm);
  auto curve = get(CGAL::dynamic_edge_property_t<bool>(), tm);
  // The diagonals of the first column of squares are curve edges.
  std::vector<std::pair<Mesh::Vertex_index, Mesh::Vertex_index>> held;
  for (auto e : tm.edges()) {
    const auto a = tm.point(tm.source(tm.halfedge(e))), b = tm.point(tm.target(tm.halfedge(e)));
    const bool diagonal = a.y() != b.y() && std::abs(std::abs(b.x() - a.x()) - 1.9) < 1e-12;
    const bool first_column = std::min(a.x() - 0.9 * a.y(), b.x() - 0.9 * b.y()) < 0.5;
    put(curve, e, diagonal && first_column);
    if (diagonal && first_column) held.emplace_back(tm.source(tm.halfedge(e)), tm.target(tm.halfedge(e)));
  }
  REQUIRE(held.size() == 6);
  const std::size_t flips = meshfit::internal::flip_for_angles(tm, get(CGAL::vertex_point, tm), curve, 20 * CGAL_PI / 180);
  const meshfit::Mesh_data out = meshfit::to_mesh_data(tm);
  CHECK(flips == 30);  // every other diagonal of the 6 x 6 squares
  CHECK(out.points == input.points);
  CHECK(out.triangles.size() == input.triangles.size());
  for (const auto& [a, b] : held) CHECK(CGAL::halfedge(a, b, tm).second);
  // Away from the held column the faces are the good diagonals' (smallest angle 47.7 degrees, 20.3
  // before); beside it they are as they were.
  meshfit::Mesh_data away = out;
  away.triangles.clear();
  for (const auto& t : out.triangles) {
    bool beside = false;
    for (const auto& [a, b] : held)
      for (int k = 0; k < 3; ++k) beside = beside || std::minmax<std::size_t>(t[k], t[(k + 1) % 3]) == std::minmax<std::size_t>(a, b);
    if (!beside) away.triangles.push_back(t);
  }
  REQUIRE(away.triangles.size() == out.triangles.size() - 12);
  CHECK(smallest_angle_deg(input) < 20.5);
  CHECK(smallest_angle_deg(away) > 47);
  // Still a tiling of the same parallelogram: every face upwards, the same total area.
  double area_in = 0, area_out = 0;
  for (const auto& t : out.triangles) {
    const double z = CGAL::cross_product(out.points[t[1]] - out.points[t[0]], out.points[t[2]] - out.points[t[0]]).z();
    CHECK(z > 0);
    area_out += z / 2;
  }
  for (const auto& t : input.triangles)
    area_in += CGAL::cross_product(input.points[t[1]] - input.points[t[0]], input.points[t[2]] - input.points[t[0]]).z() / 2;
  CHECK(std::abs(area_out - area_in) < 1e-12 * area_in);
}

TEST_CASE("fit: edge flips leave a bent surface's shape alone", "[fit][flips]") {
  // A roof folded by about 90 degrees along x = 2: a flip across the ridge would cut the roof's
  // corner off; the flat parts may still be flipped. Every face must keep all its corners on
  // one side of the ridge (x <= 2 or x >= 2), as the input's do.
  const meshfit::Mesh_data input = sheared_grid(6, 1.0);
  Mesh tm;
  meshfit::build_triangle_mesh(input, tm);
  auto curve = get(CGAL::dynamic_edge_property_t<bool>(), tm);
  for (auto e : tm.edges()) put(curve, e, false);
  auto one_side = [](const meshfit::Mesh_data& m) {
    std::size_t straddling = 0;
    for (const auto& t : m.triangles) {
      bool left = false, right = false;
      for (std::size_t c : t) left = left || m.points[c].x() < 2 - 1e-12, right = right || m.points[c].x() > 2 + 1e-12;
      straddling += left && right;
    }
    return straddling;
  };
  const std::size_t before = one_side(input);
  meshfit::internal::flip_for_angles(tm, get(CGAL::vertex_point, tm), curve, 20 * CGAL_PI / 180);
  CHECK(one_side(meshfit::to_mesh_data(tm)) <= before);
}

TEST_CASE("fit: edge flips leave squares alone (both diagonals equal up to rounding)", "[fit][flips]") {
  Mesh tm;
  meshfit::build_triangle_mesh(meshfit_test::grid(8), tm);
  auto curve = get(CGAL::dynamic_edge_property_t<bool>(), tm);
  for (auto e : tm.edges()) put(curve, e, false);
  CHECK(meshfit::internal::flip_for_angles(tm, get(CGAL::vertex_point, tm), curve, 20 * CGAL_PI / 180) == 0);
}

TEST_CASE("fit: number_of_iterations counts smoothing iterations, flip_prevention_rounds stage 1's rounds",
          "[fit][parameters]") {
  // number_of_iterations means what it means for smooth_fitted_mesh: 5 smoothing iterations, one
  // fifth modified mean curvature (1), the rest modified Laplacian (4).
  {
    Inputs in = example();
    const Mesh template_mesh = in.tm;
    const meshfit::Fit_report r = meshfit::fit_template_to_curves(
        in.tm, in.network, in.pairs, meshfit::parameters::flip_prevention_rounds(3).number_of_iterations(5));
    const fit_oracle::Fit_check check =
        fit_oracle::check_fit(in.tm, template_mesh, meshfit_test::oracle_network(in.network), 12);
    INFO(meshfit_test::describe(check));
    CHECK(check.passed());
    CHECK(r.smoothing.mean_curvature_iterations == 1);
    CHECK(r.smoothing.laplacian_iterations == 4);
    CHECK(r.smoothing.iterations == 5);
  }
  // Each phase's own count overrides the split.
  {
    Inputs in = example();
    const meshfit::Fit_report r = meshfit::fit_template_to_curves(
        in.tm, in.network, in.pairs,
        meshfit::parameters::default_values().number_of_iterations(5).mean_curvature_iterations(2).laplacian_iterations(0));
    CHECK(r.smoothing.mean_curvature_iterations == 2);
    CHECK(r.smoothing.laplacian_iterations == 0);
  }
  // flip_prevention_rounds reaches stage 1: on the example the thesis level needs 2 rounds; with 1
  // it stops after 1 with faces still flipping, and fit's verification says so.
  {
    Inputs in = example();
    const meshfit::Deformation_report d = meshfit::deform_template(
        in.tm, in.network, in.pairs, meshfit::parameters::fine_level(meshfit::Fine_level::thesis));
    CHECK(d.flip_rounds == 2);
    CHECK(d.remaining_flips == 0);
  }
  {
    Inputs in = example();
    const meshfit::Fit_report r = meshfit::fit_template_to_curves(
        in.tm, in.network, in.pairs,
        meshfit::parameters::fine_level(meshfit::Fine_level::thesis).flip_prevention_rounds(1));
    CHECK(r.deformation.flip_rounds == 1);
    CHECK(r.deformation.remaining_flips > 0);
    CHECK(r.verification.flips_remaining == r.deformation.remaining_flips);
    CHECK(!r.verification.passed());
  }
  // Negative counts are refused before any work, naming the parameter.
  for (int which = 0; which < 3; ++which) {
    Inputs in = example();
    const Mesh before = in.tm;
    try {
      if (which == 0) meshfit::fit_template_to_curves(in.tm, in.network, in.pairs, meshfit::parameters::flip_prevention_rounds(-1));
      if (which == 1) meshfit::deform_template(in.tm, in.network, in.pairs, meshfit::parameters::flip_prevention_rounds(-2));
      if (which == 2) meshfit::fit_template_to_curves(in.tm, in.network, in.pairs, CGAL::parameters::number_of_iterations(-3));
      FAIL("no exception for a negative count");
    } catch (const meshfit::Invalid_input& e) {
      const std::string m = e.what();
      CHECK(m.find(which == 2 ? "number_of_iterations" : "flip_prevention_rounds") != std::string::npos);
      CHECK(m.find(which == 0 ? "-1" : which == 1 ? "-2" : "-3") != std::string::npos);
    }
    CHECK(in.tm.number_of_vertices() == before.number_of_vertices());
  }
}

TEST_CASE("fit: bunched chain vertices are spaced out along their segment, on it, without turning a face over",
          "[fit][chains]") {
  // A segment from (0,0,0) to (1,0,0) whose chain has three inner vertices bunched at its start
  // (x = 0.01, 0.02, 0.03), between two fans: a vertex above (0.5, 1) and one below (0.5, -1).
  meshfit::Mesh_data input;
  const std::vector<double> xs{0, 0.01, 0.02, 0.03, 1};
  for (double x : xs) input.points.emplace_back(x, 0, 0);
  input.points.emplace_back(0.5, 1, 0);   // 5: above
  input.points.emplace_back(0.5, -1, 0);  // 6: below
  for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
    input.triangles.push_back({i, i + 1, 5});
    input.triangles.push_back({i + 1, i, 6});
  }
  Mesh tm;
  meshfit::build_triangle_mesh(input, tm);
  auto curve = get(CGAL::dynamic_edge_property_t<bool>(), tm);
  for (auto e : tm.edges()) {
    const auto a = tm.point(tm.source(tm.halfedge(e))), b = tm.point(tm.target(tm.halfedge(e)));
    put(curve, e, a.y() == 0 && b.y() == 0);
  }
  const meshfit::Curve_network network({{meshfit::Point_3(0, 0, 0), meshfit::Point_3(1, 0, 0)}});
  const std::vector<std::size_t> mesh_of{0, 4};
  const std::size_t moves = meshfit::internal::space_chain_vertices(tm, get(CGAL::vertex_point, tm), curve, network,
                                                                    mesh_of, network.tolerance());
  const meshfit::Mesh_data out = meshfit::to_mesh_data(tm);
  CHECK(moves > 0);
  // The ends and the fans' apexes stay; the inner vertices stay on the segment, in their order,
  // and no longer bunched.
  CHECK(out.points[0] == input.points[0]);
  CHECK(out.points[4] == input.points[4]);
  CHECK(out.points[5] == input.points[5]);
  CHECK(out.points[6] == input.points[6]);
  for (std::size_t i = 1; i < 4; ++i) {
    CHECK(out.points[i].y() == 0);
    CHECK(out.points[i].z() == 0);
    CHECK(out.points[i].x() > out.points[i - 1].x());
  }
  double smallest_gap = 1;
  for (std::size_t i = 0; i < 4; ++i) smallest_gap = std::min(smallest_gap, out.points[i + 1].x() - out.points[i].x());
  CHECK(smallest_gap > 0.1);
  CHECK(smallest_angle_deg(input) < 1);
  CHECK(smallest_angle_deg(out) > 10);
  // Every face still turns upwards (its normal's z is positive), and the faces still tile the
  // rhombus of area 1.
  double area = 0;
  for (const auto& t : out.triangles) {
    const double z = CGAL::cross_product(out.points[t[1]] - out.points[t[0]], out.points[t[2]] - out.points[t[0]]).z();
    CHECK(z > 0);
    area += z / 2;
  }
  CHECK(std::abs(area - 1) < 1e-12);
}

namespace {

// Regions counted on their own: faces joined across edges that are not curve edges.
std::size_t flood_fill_regions(const Mesh& tm, const Mesh::Property_map<Mesh::Edge_index, bool>& curve) {
  std::map<Mesh::Face_index, bool> seen;
  std::size_t regions = 0;
  for (auto f0 : tm.faces()) {
    if (seen[f0]) continue;
    ++regions;
    std::vector<Mesh::Face_index> stack{f0};
    seen[f0] = true;
    while (!stack.empty()) {
      const auto f = stack.back();
      stack.pop_back();
      for (auto h : CGAL::halfedges_around_face(tm.halfedge(f), tm)) {
        const auto g = tm.face(tm.opposite(h));
        if (g == Mesh::null_face() || curve[tm.edge(h)] || seen[g]) continue;
        seen[g] = true;
        stack.push_back(g);
      }
    }
  }
  return regions;
}

// The closed polyline of the border of the square [i0, i1] × [j0, j1] of an n-grid's points,
// and its edges marked in `curve`.
meshfit::Curve_network::Polyline square_loop(const Mesh& tm, Mesh::Property_map<Mesh::Edge_index, bool>& curve,
                                             std::size_t n, std::size_t i0, std::size_t i1, std::size_t j0,
                                             std::size_t j1) {
  std::vector<Mesh::Vertex_index> loop;
  auto at = [n](std::size_t i, std::size_t j) { return Mesh::Vertex_index(static_cast<std::uint32_t>(j * (n + 1) + i)); };
  for (std::size_t i = i0; i < i1; ++i) loop.push_back(at(i, j0));
  for (std::size_t j = j0; j < j1; ++j) loop.push_back(at(i1, j));
  for (std::size_t i = i1; i > i0; --i) loop.push_back(at(i, j1));
  for (std::size_t j = j1; j > j0; --j) loop.push_back(at(i0, j));
  meshfit::Curve_network::Polyline line;
  for (std::size_t k = 0; k < loop.size(); ++k) {
    const auto [h, found] = CGAL::halfedge(loop[k], loop[(k + 1) % loop.size()], tm);
    REQUIRE(found);
    curve[tm.edge(h)] = true;
    line.push_back(tm.point(loop[k]));
  }
  line.push_back(line.front());
  return line;
}

}  // namespace

TEST_CASE("fit: the region count a network bounds is known on genus-0 templates with holes", "[fit][regions]") {
  // A 12 × 12 grid (a disc) with the faces of two squares removed: three border cycles.
  constexpr std::size_t n = 12;
  Mesh tm;
  meshfit::build_triangle_mesh(meshfit_test::grid(n), tm);
  for (std::size_t square : {std::size_t(2 * n + 2), std::size_t(8 * n + 8)})  // squares (2, 2) and (8, 8)
    for (std::size_t t : {2 * square, 2 * square + 1}) CGAL::Euler::remove_face(tm.halfedge(Mesh::Face_index(std::uint32_t(t))), tm);
  tm.collect_garbage();
  auto curve = tm.add_property_map<Mesh::Edge_index, bool>("e:curve", false).first;
  auto known = [&](const std::vector<meshfit::Curve_network::Polyline>& lines) {
    return meshfit::internal::expected_regions(tm, meshfit::Curve_network(lines), curve);
  };

  SECTION("a loop around neither hole: the holes lie inside regions") {
    const auto loop = square_loop(tm, curve, n, 4, 7, 4, 7);
    const auto expected = known({loop});
    REQUIRE(expected);
    CHECK(*expected == 2);
    CHECK(flood_fill_regions(tm, curve) == 2);
  }
  SECTION("a loop around a hole: still two regions, one of them a ring") {
    const auto loop = square_loop(tm, curve, n, 1, 4, 1, 4);
    const auto expected = known({loop});
    REQUIRE(expected);
    CHECK(*expected == 2);
    CHECK(flood_fill_regions(tm, curve) == 2);
  }
  SECTION("a hole's border in the network: the face it bounds is not on the mesh") {
    const auto inner = square_loop(tm, curve, n, 4, 7, 4, 7);
    const auto hole = square_loop(tm, curve, n, 8, 9, 8, 9);
    const auto expected = known({inner, hole});
    REQUIRE(expected);
    CHECK(*expected == 2);
    CHECK(flood_fill_regions(tm, curve) == 2);
  }
  SECTION("a border cycle partly on curves: not determined by the topology") {
    const auto loop = square_loop(tm, curve, n, 0, 3, 8, 11);  // two sides on the outer border
    CHECK_FALSE(known({loop}));
  }
}

TEST_CASE("fit: a template that intersects itself does not excuse new intersections", "[fit][verification]") {
  meshfit::Fit_verification v;
  v.self_intersection_checked = v.self_intersects = v.template_self_intersects = true;
  v.self_intersecting_pairs = v.template_self_intersecting_pairs = 12;
  CHECK(v.passed());  // as many pairs as the template had
  v.self_intersecting_pairs = 17;
  REQUIRE(v.problems().size() == 1);
  CHECK(v.problems()[0] == "17 pairs of faces intersect (the template has 12)");
  v.template_self_intersects = false;  // a clean template: any intersection is one too many
  v.template_self_intersecting_pairs = v.self_intersecting_pairs = 0;
  REQUIRE(v.problems().size() == 1);
  CHECK(v.problems()[0] == "the result intersects itself (the template does not)");
}

TEST_CASE("fit: the self-intersection test in slabs says what CGAL says of the whole mesh", "[fit][verification]") {
  // A wavy 40x40 sheet (no intersection: a height field), then one vertex at a time thrown across
  // the sheet by a seeded random offset, which makes its faces cut others in most trials and
  // in some not: every slab count must say what CGAL's test of the whole mesh (the oracle's
  // count) says, wherever the slab ends fall among the faces that intersect.
  meshfit::Mesh_data sheet = meshfit_test::grid(40);
  std::mt19937 random(20261205);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (auto& p : sheet.points) p = meshfit::Point_3(p.x(), p.y(), 0.3 * std::sin(0.5 * p.x()) + 0.02 * unit(random));
  Mesh tm;
  meshfit::build_triangle_mesh(sheet, tm);
  for (std::size_t slabs : {1, 2, 3, 5, 8}) CHECK_FALSE(meshfit::internal::does_self_intersect_in_slabs(tm, slabs));
  std::size_t with = 0, without = 0;
  for (int trial = 0; trial < 60; ++trial) {
    Mesh moved = tm;
    const Mesh::Vertex_index v(static_cast<std::uint32_t>(std::uniform_int_distribution<int>(0, 1680)(random)));
    const meshfit::Point_3 p = moved.point(v);
    moved.point(v) = meshfit::Point_3(p.x() + 4 * unit(random), p.y() + 4 * unit(random), p.z() + 0.5 * unit(random));
    const bool oracle = fit_oracle::self_intersections(moved) > 0;
    (oracle ? with : without) += 1;
    for (std::size_t slabs : {2, 3, 5, 8}) {
      INFO("trial " << trial << ", " << slabs << " slabs");
      CHECK(meshfit::internal::does_self_intersect_in_slabs(moved, slabs) == oracle);
    }
  }
  CHECK(with >= 10);
  CHECK(without >= 5);
  // A face of no area counts as an intersection, as in CGAL's test: a corner moved onto the
  // opposite edge's midpoint.
  Mesh flat = tm;
  const auto h = halfedge(*faces(flat).begin(), flat);
  const meshfit::Point_3 a = flat.point(source(h, flat)), b = flat.point(target(h, flat));
  flat.point(target(next(h, flat), flat)) = CGAL::midpoint(a, b);
  for (std::size_t slabs : {1, 2, 5}) CHECK(meshfit::internal::does_self_intersect_in_slabs(flat, slabs));
}

}  // namespace meshfit_fit_test
