// fit_template_to_curves and the caller's data: property maps kept on Surface_mesh, vertex
// handles kept on Polyhedron_3, vertex attributes carried to the added vertices, and nothing
// changed when a stage is cancelled or fails. The oracles are the test's own (the maps' values
// recorded before the call, the result's connectivity read back from the mesh) and the
// independent fit oracle (bench/battery/fit_oracle.h), not fit's verification.
#include <meshfit/fit.h>
#include <meshfit/internal/partition_impl.h>
#include <meshfit/internal/vertex_attributes.h>
#include <meshfit/io.h>

#include <CGAL/Polyhedron_3.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/graph_traits_Polyhedron_3.h>
#include <CGAL/boost/graph/properties_Polyhedron_3.h>

#include <boost/property_map/function_property_map.hpp>
#include <boost/property_map/property_map.hpp>

#include "oracle_helpers.h"
#include "test_helpers.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <type_traits>

namespace meshfit_fit_caller_data_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;
using Poly = CGAL::Polyhedron_3<meshfit::Kernel>;
using V = Mesh::Vertex_index;
using Point_2 = meshfit::Kernel::Point_2;

namespace {

struct Network_and_pairs {
  meshfit::Curve_network network;
  std::vector<meshfit::Correspondence> pairs;
};

template <typename TriangleMesh>
Network_and_pairs example(TriangleMesh& tm) {
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  meshfit::read_triangle_mesh(d + "/template.off", tm);
  Network_and_pairs in;
  in.network = meshfit::read_curve_network(d + "/curves.polylines.txt");
  in.pairs = meshfit::read_correspondences(d + "/pairs.txt", in.network);
  return in;
}

/// The pairs of `in` mirrored in x, with the network: they mirror the template (Algorithm_failure).
Network_and_pairs mirrored(const Network_and_pairs& in) {
  std::vector<meshfit::Curve_network::Polyline> lines;
  for (const auto& pl : in.network.polylines()) {
    meshfit::Curve_network::Polyline m;
    for (std::size_t v : pl) m.emplace_back(-in.network.point(v).x(), in.network.point(v).y(), in.network.point(v).z());
    lines.push_back(m);
  }
  Network_and_pairs out{meshfit::Curve_network(lines), in.pairs};
  for (auto& c : out.pairs) {
    const meshfit::Point_3& p = in.network.point(c.network_vertex);
    c.network_vertex = *out.network.find_vertex(meshfit::Point_3(-p.x(), p.y(), p.z()));
  }
  return out;
}

std::pair<std::size_t, std::size_t> ordered(std::size_t a, std::size_t b) { return {std::min(a, b), std::max(a, b)}; }

std::array<std::size_t, 3> rotated(std::array<std::size_t, 3> t) {
  while (t[0] > t[1] || t[0] > t[2]) t = {t[1], t[2], t[0]};
  return t;
}

/// The value at each vertex that is not `fixed` minus the mean of its neighbours' (the harmonic
/// extension makes it zero), largest over the mesh; neighbours read from the mesh itself.
template <typename TriangleMesh, typename Get>
double largest_harmonic_residual(const TriangleMesh& tm, const std::vector<bool>& fixed, const Get& value) {
  double worst = 0;
  std::size_t k = 0;
  for (auto v : vertices(tm)) {
    if (fixed[k++]) continue;
    std::array<double, 2> mean{0, 0};
    std::size_t n = 0;
    for (auto w : CGAL::vertices_around_target(v, tm)) {
      const auto a = value(w);
      mean[0] += a[0];
      mean[1] += a[1];
      ++n;
    }
    const auto a = value(v);
    worst = std::max({worst, std::abs(a[0] - mean[0] / n), std::abs(a[1] - mean[1] / n)});
  }
  return worst;
}

// Fits with a progress callback that cancels when `stop_at` starts (none when empty) and the UV
// map as vertex_texture_map; true when the fit threw Algorithm_failure as it should: for the
// cancel, or (with `mirror`) for the mirrored pairs.
template <typename TriangleMesh, typename UvMap>
bool fit_is_refused(TriangleMesh& tm, const Network_and_pairs& in, const std::string& stop_at, bool mirror,
                    const UvMap& uv) {
  try {
    meshfit::fit_template_to_curves(
        tm, in.network, in.pairs,
        meshfit::parameters::progress([&](const meshfit::Progress_step& s) { return s.stage != stop_at; })
            .vertex_texture_map(uv));
  } catch (const meshfit::Algorithm_failure& e) {
    return mirror || std::string(e.what()).find("cancelled") != std::string::npos;
  }
  return false;
}

}  // namespace

TEST_CASE("fit: a Surface_mesh keeps every property map, with its values on the template's vertices, edges and faces",
          "[fit][caller_data]") {
  Mesh tm;
  const Network_and_pairs in = example(tm);
  const std::size_t nt = tm.number_of_vertices();
  // A removed vertex after the template's: it stays removed, the added vertices come after it.
  tm.remove_vertex(tm.add_vertex(meshfit::Point_3(9, 9, 9)));
  REQUIRE(tm.has_garbage());
  auto uv = tm.add_property_map<V, Point_2>("v:uv", Point_2(-7, -7)).first;
  auto name = tm.add_property_map<V, std::string>("v:name", "new").first;
  auto ftag = tm.add_property_map<Mesh::Face_index, int>("f:tag", -1).first;
  auto etag = tm.add_property_map<Mesh::Edge_index, int>("e:tag", -1).first;
  auto htag = tm.add_property_map<Mesh::Halfedge_index, int>("h:tag", -1).first;
  for (V v : tm.vertices()) {
    uv[v] = Point_2(tm.point(v).x(), tm.point(v).y());
    name[v] = "v" + std::to_string(std::size_t(v));
  }
  std::map<std::array<std::size_t, 3>, int> face_tag;
  for (auto f : tm.faces()) {
    ftag[f] = int(f) + 100;
    const auto h = tm.halfedge(f);
    face_tag[rotated({tm.source(h), tm.target(h), tm.target(tm.next(h))})] = ftag[f];
  }
  std::map<std::pair<std::size_t, std::size_t>, int> halfedge_tag, edge_tag;
  for (auto h : tm.halfedges()) {
    htag[h] = int(h) + 1000;
    halfedge_tag[{tm.source(h), tm.target(h)}] = htag[h];
  }
  for (auto e : tm.edges()) {
    etag[e] = int(e) + 7;
    const auto h = tm.halfedge(e);
    edge_tag[ordered(tm.source(h), tm.target(h))] = etag[e];
  }
  std::vector<Point_2> uv_before;
  for (V v : tm.vertices()) uv_before.push_back(uv[v]);

  auto curve = tm.add_property_map<Mesh::Edge_index, bool>("e:curve", false).first;
  auto region = tm.add_property_map<Mesh::Face_index, int>("f:region", -1).first;
  const meshfit::Fit_report r = meshfit::fit_template_to_curves(
      tm, in.network, in.pairs, meshfit::parameters::default_values().edge_is_constrained_map(curve).face_patch_map(region));
  CHECK(meshfit_test::oracle_passes(meshfit_test::check_example_fit(tm)));
  REQUIRE(tm.is_valid(false));
  CHECK(tm.number_of_vertices() == r.vertices);
  CHECK(tm.number_of_faces() == r.faces);
  REQUIRE(r.vertices > nt);

  // The maps are the same objects, still in the mesh.
  CHECK(tm.property_map<V, Point_2>("v:uv").second);
  CHECK(tm.property_map<Mesh::Face_index, int>("f:tag").second);
  // Template vertex i is vertex i, with its values; the removed vertex stays removed; the added
  // vertices come after it, with the defaults.
  for (std::size_t i = 0; i < nt; ++i) {
    CHECK(uv[V(Mesh::size_type(i))] == uv_before[i]);
    CHECK(name[V(Mesh::size_type(i))] == "v" + std::to_string(i));
  }
  CHECK(tm.is_removed(V(Mesh::size_type(nt))));
  std::size_t k = 0, added = 0;
  for (V v : tm.vertices()) {
    if (k++ < nt) {
      CHECK(std::size_t(v) == k - 1);
      continue;
    }
    CHECK(std::size_t(v) > nt);
    CHECK(uv[v] == Point_2(-7, -7));
    CHECK(name[v] == "new");
    ++added;
  }
  CHECK(added == r.vertices - nt);
  for (const auto& c : in.pairs)
    CHECK(tm.point(V(Mesh::size_type(c.template_vertex))) == in.network.point(c.network_vertex));

  // A face (edge, halfedge) of the result on the same template vertices keeps its value; the others
  // have the default. Both kinds occur.
  std::size_t kept_faces = 0, new_faces = 0, kept_edges = 0, new_edges = 0, kept_halfedges = 0;
  for (auto f : tm.faces()) {
    const auto h = tm.halfedge(f);
    const auto it = face_tag.find(rotated({tm.source(h), tm.target(h), tm.target(tm.next(h))}));
    if (it != face_tag.end() && std::size_t(tm.source(h)) < nt && std::size_t(tm.target(h)) < nt &&
        std::size_t(tm.target(tm.next(h))) < nt) {
      CHECK(ftag[f] == it->second);
      ++kept_faces;
    } else {
      CHECK(ftag[f] == -1);
      ++new_faces;
    }
  }
  for (auto e : tm.edges()) {
    const auto h = tm.halfedge(e);
    const auto it = edge_tag.find(ordered(tm.source(h), tm.target(h)));
    if (it != edge_tag.end() && std::size_t(tm.source(h)) < nt && std::size_t(tm.target(h)) < nt) {
      CHECK(etag[e] == it->second);
      ++kept_edges;
      for (auto g : {h, tm.opposite(h)}) {
        CHECK(htag[g] == halfedge_tag.at({tm.source(g), tm.target(g)}));
        ++kept_halfedges;
      }
    } else {
      CHECK(etag[e] == -1);
      CHECK(htag[h] == -1);
      CHECK(htag[tm.opposite(h)] == -1);
      ++new_edges;
    }
  }
  INFO("faces kept " << kept_faces << ", new " << new_faces << "; edges kept " << kept_edges << ", new " << new_edges);
  CHECK(kept_faces > 1000);
  CHECK(new_faces > 0);
  CHECK(kept_edges > 1000);
  CHECK(new_edges > 0);
  // The output maps were filled on the result.
  std::set<int> labels;
  for (auto f : tm.faces()) labels.insert(region[f]);
  CHECK(labels.size() == r.partition.regions);
}

TEST_CASE("fit: texture coordinates, colours and normals are carried to the added vertices (Surface_mesh)",
          "[fit][caller_data]") {
  Mesh tm;
  const Network_and_pairs in = example(tm);
  const std::size_t nt = tm.number_of_vertices();
  // UVs and colours affine in the template's position, normals the sphere's.
  auto uv = tm.add_property_map<V, Point_2>("v:uv").first;
  auto colour = tm.add_property_map<V, CGAL::IO::Color>("v:colour").first;
  auto normal = tm.add_property_map<V, meshfit::Vector_3>("v:normal").first;
  auto byte = [](double c) { return static_cast<unsigned char>(std::lround(127.5 + 127 * c)); };
  for (V v : tm.vertices()) {
    const meshfit::Point_3& p = tm.point(v);
    uv[v] = Point_2(p.x(), p.y());
    colour[v] = CGAL::IO::Color(byte(p.x()), byte(p.y()), byte(p.z()), 200);
    const meshfit::Vector_3 n = p - CGAL::ORIGIN;
    normal[v] = n / std::sqrt(n.squared_length());
  }
  std::vector<Point_2> uv_before;
  std::vector<CGAL::IO::Color> colour_before;
  std::vector<meshfit::Vector_3> normal_before;
  for (V v : tm.vertices()) {
    uv_before.push_back(uv[v]);
    colour_before.push_back(colour[v]);
    normal_before.push_back(normal[v]);
  }
  const meshfit::Fit_report r = meshfit::fit_template_to_curves(
      tm, in.network, in.pairs,
      meshfit::parameters::default_values().vertex_texture_map(uv).vertex_color_map(colour).vertex_normal_map(normal));
  CHECK(meshfit_test::oracle_passes(meshfit_test::check_example_fit(tm)));
  REQUIRE(tm.number_of_vertices() > nt);
  CHECK(tm.is_valid(false));
  CHECK(!tm.has_garbage());

  // Template vertices keep their values exactly.
  std::vector<bool> fixed(tm.number_of_vertices(), false);
  for (std::size_t i = 0; i < nt; ++i) {
    const V v(static_cast<Mesh::size_type>(i));
    fixed[i] = true;
    CHECK(uv[v] == uv_before[i]);
    CHECK(colour[v] == colour_before[i]);
    CHECK(normal[v] == normal_before[i]);
  }
  // Added vertices: each UV is the mean of its neighbours' on the result (so inside their convex
  // hull) and inside the template's UV range; colours inside their neighbours' range (up to the
  // rounding); normals of unit length, on the side of their neighbours' normals.
  const double residual =
      largest_harmonic_residual(tm, fixed, [&](V v) { return std::array<double, 2>{uv[v].x(), uv[v].y()}; });
  CHECK(residual < 1e-9);
  for (V v : tm.vertices()) {
    if (std::size_t(v) < nt) continue;
    INFO("added vertex " << std::size_t(v));
    CHECK(std::isfinite(uv[v].x()));
    CHECK(std::isfinite(uv[v].y()));
    CHECK(uv[v].x() * uv[v].x() + uv[v].y() * uv[v].y() <= 1 + 1e-9);  // the template is the unit sphere
    std::array<int, 4> lo{255, 255, 255, 255}, hi{0, 0, 0, 0};
    meshfit::Vector_3 mean(0, 0, 0);
    for (V w : CGAL::vertices_around_target(v, tm)) {
      for (int c = 0; c < 4; ++c) {
        lo[c] = std::min(lo[c], int(colour[w][std::size_t(c)]));
        hi[c] = std::max(hi[c], int(colour[w][std::size_t(c)]));
      }
      mean = mean + normal[w];
    }
    for (int c = 0; c < 4; ++c) {
      CHECK(int(colour[v][std::size_t(c)]) >= lo[c] - 1);
      CHECK(int(colour[v][std::size_t(c)]) <= hi[c] + 1);
    }
    CHECK(int(colour[v].a()) == 200);
    CHECK(std::abs(normal[v].squared_length() - 1) < 1e-12);
    CHECK(normal[v] * mean > 0);
  }
}

TEST_CASE("vertex attributes: an added vertex gets its neighbours' mean, and where normals cancel the area-weighted normal",
          "[fit][caller_data]") {
  // Template vertices 0-3, the corners of a unit square in the plane z = 1; the result adds vertex
  // 4 at its centre, in four triangles turning counter-clockwise seen from +z.
  meshfit::Mesh_data tmpl;
  tmpl.points = {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  tmpl.vertex_uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  meshfit::Mesh_data result;
  result.points = tmpl.points;
  result.points.push_back({0.5, 0.5, 1});
  result.triangles = {{4, 0, 1}, {4, 1, 2}, {4, 2, 3}, {4, 3, 0}};
  SECTION("normals whose mean has a length: normalised") {
    tmpl.vertex_normals = {{0, 0, 2}, {0, 1, 1}, {0, 0, 2}, {0, -1, 1}};
    meshfit::internal::extend_vertex_attributes(tmpl, result);
    REQUIRE(result.vertex_normals.size() == 5);
    for (std::size_t i = 0; i < 4; ++i) CHECK(result.vertex_normals[i] == tmpl.vertex_normals[i]);
    CHECK(std::abs(result.vertex_normals[4][0]) < 1e-12);
    CHECK(std::abs(result.vertex_normals[4][1]) < 1e-12);
    CHECK(std::abs(result.vertex_normals[4][2] - 1) < 1e-12);
  }
  SECTION("normals that cancel: the result's geometric normal") {
    tmpl.vertex_normals = {{1, 0, 0}, {-1, 0, 0}, {1, 0, 0}, {-1, 0, 0}};
    meshfit::internal::extend_vertex_attributes(tmpl, result);
    REQUIRE(result.vertex_normals.size() == 5);
    CHECK(result.vertex_normals[4] == std::array<double, 3>{0, 0, 1});
  }
  // The UVs: the centre's is its four neighbours' mean.
  REQUIRE(result.vertex_uvs.size() == 5);
  CHECK(std::abs(result.vertex_uvs[4][0] - 0.5) < 1e-12);
  CHECK(std::abs(result.vertex_uvs[4][1] - 0.5) < 1e-12);
  CHECK(result.vertex_colors.empty());
}

TEST_CASE("fit: a Polyhedron keeps its vertex handles, a map keyed by them gets the added vertices' UVs",
          "[fit][caller_data][generic]") {
  using vertex_descriptor = boost::graph_traits<Poly>::vertex_descriptor;
  Poly tm;
  const Network_and_pairs in = example(tm);
  const std::vector<vertex_descriptor> template_vertices(vertices(tm).begin(), vertices(tm).end());
  const std::size_t nt = template_vertices.size();
  std::map<vertex_descriptor, Point_2> uv_store;
  boost::associative_property_map<std::map<vertex_descriptor, Point_2>> uv(uv_store);
  auto tag = get(CGAL::dynamic_vertex_property_t<int>(), tm);
  for (std::size_t i = 0; i < nt; ++i) {
    const auto& p = template_vertices[i]->point();
    uv_store[template_vertices[i]] = Point_2(p.x(), p.y());
    put(tag, template_vertices[i], int(i));
  }
  const auto uv_before = uv_store;

  const meshfit::Fit_report r = meshfit::fit_template_to_curves(
      tm, in.network, in.pairs, meshfit::parameters::default_values().vertex_texture_map(uv));
  CHECK(meshfit_test::oracle_passes(meshfit_test::check_example_fit(tm)));
  REQUIRE(tm.is_valid());
  CHECK(CGAL::is_triangle_mesh(tm));
  CHECK(num_vertices(tm) == r.vertices);
  CHECK(num_faces(tm) == r.faces);
  REQUIRE(r.vertices > nt);
  const std::vector<vertex_descriptor> after(vertices(tm).begin(), vertices(tm).end());
  // The template's handles are the first vertices, in order, with their values.
  CHECK(std::equal(template_vertices.begin(), template_vertices.end(), after.begin()));
  for (std::size_t i = 0; i < nt; ++i) {
    CHECK(get(tag, after[i]) == int(i));
    CHECK(uv_store.at(after[i]) == uv_before.at(after[i]));
  }
  for (const auto& c : in.pairs) CHECK(after[c.template_vertex]->point() == in.network.point(c.network_vertex));
  // Every added vertex got a UV: the mean of its neighbours'.
  CHECK(uv_store.size() == r.vertices);
  std::vector<bool> fixed(after.size(), false);
  std::fill(fixed.begin(), fixed.begin() + nt, true);
  const double residual = largest_harmonic_residual(tm, fixed, [&](vertex_descriptor v) {
    const Point_2& p = uv_store.at(v);
    return std::array<double, 2>{p.x(), p.y()};
  });
  CHECK(residual < 1e-9);
}

TEST_CASE("fit: a cancelled or failed fit leaves the mesh, its property maps and their values as they were",
          "[fit][caller_data][generic]") {
  // Surface_mesh with a v:uv map (also passed as vertex_texture_map) and a face map.
  auto fit_surface_mesh = [](const std::string& stop_at, bool mirror) {
    INFO("Surface_mesh, " << (mirror ? std::string("mirrored pairs") : "cancelled in " + stop_at));
    Mesh tm;
    const Network_and_pairs in0 = example(tm);
    const Network_and_pairs in = mirror ? mirrored(in0) : in0;
    auto uv = tm.add_property_map<V, Point_2>("v:uv", Point_2(-7, -7)).first;
    auto ftag = tm.add_property_map<Mesh::Face_index, int>("f:tag", -1).first;
    for (V v : tm.vertices()) uv[v] = Point_2(tm.point(v).x(), -tm.point(v).z());
    for (auto f : tm.faces()) ftag[f] = int(f) * 3;
    const Mesh copy = tm;  // all property maps and values
    const auto vmaps = tm.properties<V>(), fmaps = tm.properties<Mesh::Face_index>();
    CHECK(fit_is_refused(tm, in, stop_at, mirror, uv));
    CHECK(tm.properties<V>() == vmaps);
    CHECK(tm.properties<Mesh::Face_index>() == fmaps);
    CHECK(tm.num_vertices() == copy.num_vertices());
    CHECK(tm.num_faces() == copy.num_faces());
    CHECK(tm.num_edges() == copy.num_edges());
    CHECK(!tm.has_garbage());
    const auto uv0 = copy.property_map<V, Point_2>("v:uv").first;
    const auto ftag0 = copy.property_map<Mesh::Face_index, int>("f:tag").first;
    for (V v : tm.vertices()) {
      CHECK(tm.point(v) == copy.point(v));
      CHECK(tm.halfedge(v) == copy.halfedge(v));
      CHECK(uv[v] == uv0[v]);
    }
    for (auto h : tm.halfedges()) {
      CHECK(tm.target(h) == copy.target(h));
      CHECK(tm.next(h) == copy.next(h));
      CHECK(tm.face(h) == copy.face(h));
    }
    for (auto f : tm.faces()) CHECK(ftag[f] == ftag0[f]);
  };
  for (const char* stage : {"deform", "partition", "smooth", "fit"}) fit_surface_mesh(stage, false);
  fit_surface_mesh("", true);

  // Polyhedron with a map keyed by its vertex handles.
  auto fit_polyhedron = [](const std::string& stop_at, bool mirror) {
    INFO("Polyhedron, " << (mirror ? std::string("mirrored pairs") : "cancelled in " + stop_at));
    using vertex_descriptor = boost::graph_traits<Poly>::vertex_descriptor;
    Poly tm;
    const Network_and_pairs in0 = example(tm);
    const Network_and_pairs in = mirror ? mirrored(in0) : in0;
    std::map<vertex_descriptor, Point_2> uv_store;
    boost::associative_property_map<std::map<vertex_descriptor, Point_2>> uv(uv_store);
    for (auto v : vertices(tm)) uv_store[v] = Point_2(v->point().y(), v->point().z());
    const auto uv_before = uv_store;
    const std::vector<vertex_descriptor> vs(vertices(tm).begin(), vertices(tm).end());
    const std::vector<boost::graph_traits<Poly>::halfedge_descriptor> hs(halfedges(tm).begin(), halfedges(tm).end());
    const meshfit::Mesh_data before = meshfit::to_mesh_data(tm);
    CHECK(fit_is_refused(tm, in, stop_at, mirror, uv));
    CHECK(std::equal(vs.begin(), vs.end(), vertices(tm).begin(), vertices(tm).end()));
    CHECK(std::equal(hs.begin(), hs.end(), halfedges(tm).begin(), halfedges(tm).end()));
    const meshfit::Mesh_data after = meshfit::to_mesh_data(tm);
    CHECK(after.points == before.points);
    CHECK(after.triangles == before.triangles);
    CHECK(uv_store == uv_before);
  };
  for (const char* stage : {"deform", "partition", "smooth", "fit"}) fit_polyhedron(stage, false);
  fit_polyhedron("", true);
}

// ---- the stages on their own: a cancel or a failure anywhere leaves the mesh exactly as it was ----

namespace {

/// Everything of a Surface_mesh, read through its API element by element over the whole index
/// range (removed elements included): connectivity, points, removal flags, the property lists
/// and the values of the test's maps. Two meshes compare equal only if they are the same bits
/// as far as any user of the mesh can tell.
struct Surface_mesh_state {
  std::size_t nv = 0, nh = 0, ne = 0, nf = 0, removed_v = 0, removed_e = 0, removed_f = 0;
  bool garbage = false;
  std::vector<std::string> vprops, hprops, eprops, fprops;
  std::vector<std::size_t> v_halfedge, h_target, h_next, h_prev, h_face, f_halfedge;
  std::vector<bool> v_removed, e_removed, f_removed;
  std::vector<meshfit::Point_3> points;
  std::vector<Point_2> uv;
  std::vector<int> etag, htag, ftag;
  std::vector<bool> curve;
  std::vector<std::size_t> region;
  bool operator==(const Surface_mesh_state& o) const {
    return std::tie(nv, nh, ne, nf, removed_v, removed_e, removed_f, garbage, vprops, hprops, eprops, fprops,
                    v_halfedge, h_target, h_next, h_prev, h_face, f_halfedge, v_removed, e_removed, f_removed, points,
                    uv, etag, htag, ftag, curve, region) ==
           std::tie(o.nv, o.nh, o.ne, o.nf, o.removed_v, o.removed_e, o.removed_f, o.garbage, o.vprops, o.hprops,
                    o.eprops, o.fprops, o.v_halfedge, o.h_target, o.h_next, o.h_prev, o.h_face, o.f_halfedge,
                    o.v_removed, o.e_removed, o.f_removed, o.points, o.uv, o.etag, o.htag, o.ftag, o.curve, o.region);
  }
};

Surface_mesh_state state_of(const Mesh& tm) {
  using H = Mesh::Halfedge_index;
  using E = Mesh::Edge_index;
  using F = Mesh::Face_index;
  Surface_mesh_state s;
  s.nv = tm.number_of_vertices() + tm.number_of_removed_vertices();
  s.ne = tm.number_of_edges() + tm.number_of_removed_edges();
  s.nh = 2 * s.ne;
  s.nf = tm.number_of_faces() + tm.number_of_removed_faces();
  s.removed_v = tm.number_of_removed_vertices();
  s.removed_e = tm.number_of_removed_edges();
  s.removed_f = tm.number_of_removed_faces();
  s.garbage = tm.has_garbage();
  s.vprops = tm.properties<V>();
  s.hprops = tm.properties<H>();
  s.eprops = tm.properties<E>();
  s.fprops = tm.properties<F>();
  const auto uv = tm.property_map<V, Point_2>("v:uv").first;
  const auto etag = tm.property_map<E, int>("e:tag").first;
  const auto htag = tm.property_map<H, int>("h:tag").first;
  const auto ftag = tm.property_map<F, int>("f:tag").first;
  const auto curve = tm.property_map<E, bool>("e:curve").first;
  const auto region = tm.property_map<F, std::size_t>("f:region").first;
  for (std::size_t i = 0; i < s.nv; ++i) {
    const V v(static_cast<Mesh::size_type>(i));
    s.v_halfedge.push_back(std::size_t(tm.halfedge(v)));
    s.v_removed.push_back(tm.is_removed(v));
    s.points.push_back(tm.point(v));
    s.uv.push_back(uv[v]);
  }
  for (std::size_t i = 0; i < s.nh; ++i) {
    const H h(static_cast<Mesh::size_type>(i));
    s.h_target.push_back(std::size_t(tm.target(h)));
    s.h_next.push_back(std::size_t(tm.next(h)));
    s.h_prev.push_back(std::size_t(tm.prev(h)));
    s.h_face.push_back(std::size_t(tm.face(h)));
    s.htag.push_back(htag[h]);
  }
  for (std::size_t i = 0; i < s.ne; ++i) {
    const E e(static_cast<Mesh::size_type>(i));
    s.e_removed.push_back(tm.is_removed(e));
    s.etag.push_back(etag[e]);
    s.curve.push_back(curve[e]);
  }
  for (std::size_t i = 0; i < s.nf; ++i) {
    const F f(static_cast<Mesh::size_type>(i));
    s.f_halfedge.push_back(std::size_t(tm.halfedge(f)));
    s.f_removed.push_back(tm.is_removed(f));
    s.ftag.push_back(ftag[f]);
    s.region.push_back(region[f]);
  }
  return s;
}

/// The test's maps on a Surface_mesh, with values that differ from element to element (and from
/// what any stage would write: curve edges every third edge, regions 1000 + f), and one removed
/// vertex, edge and face (garbage must stay garbage).
void add_caller_maps(Mesh& tm) {
  auto uv = tm.add_property_map<V, Point_2>("v:uv", Point_2(-7, -7)).first;
  auto etag = tm.add_property_map<Mesh::Edge_index, int>("e:tag", -1).first;
  auto htag = tm.add_property_map<Mesh::Halfedge_index, int>("h:tag", -1).first;
  auto ftag = tm.add_property_map<Mesh::Face_index, int>("f:tag", -1).first;
  auto curve = tm.add_property_map<Mesh::Edge_index, bool>("e:curve", false).first;
  auto region = tm.add_property_map<Mesh::Face_index, std::size_t>("f:region", 0).first;
  for (V v : tm.vertices()) uv[v] = Point_2(tm.point(v).x(), -tm.point(v).z());
  for (auto e : tm.edges()) etag[e] = 3 * int(e), curve[e] = std::size_t(e) % 3 == 0;
  for (auto h : tm.halfedges()) htag[h] = 5 * int(h);
  for (auto f : tm.faces()) ftag[f] = 7 * int(f), region[f] = 1000 + std::size_t(f);
  tm.remove_vertex(tm.add_vertex(meshfit::Point_3(9, 9, 9)));
  tm.remove_edge(tm.edge(tm.add_edge()));
  tm.remove_face(tm.add_face());
}

/// A Polyhedron's handles, connectivity and points, in the order of its lists.
struct Polyhedron_state {
  std::vector<boost::graph_traits<Poly>::vertex_descriptor> vertices;
  std::vector<boost::graph_traits<Poly>::halfedge_descriptor> halfedges, h_next, h_prev, h_opposite, v_halfedge,
      f_halfedge;
  std::vector<boost::graph_traits<Poly>::face_descriptor> faces, h_face;
  std::vector<boost::graph_traits<Poly>::vertex_descriptor> h_target;
  std::vector<meshfit::Point_3> points;
  bool operator==(const Polyhedron_state& o) const {
    return std::tie(vertices, halfedges, h_next, h_prev, h_opposite, v_halfedge, f_halfedge, faces, h_face, h_target,
                    points) == std::tie(o.vertices, o.halfedges, o.h_next, o.h_prev, o.h_opposite, o.v_halfedge,
                                        o.f_halfedge, o.faces, o.h_face, o.h_target, o.points);
  }
};

Polyhedron_state state_of(Poly& tm) {
  Polyhedron_state s;
  for (auto v : vertices(tm)) {
    s.vertices.push_back(v);
    s.v_halfedge.push_back(halfedge(v, tm));
    s.points.push_back(v->point());
  }
  for (auto h : halfedges(tm)) {
    s.halfedges.push_back(h);
    s.h_next.push_back(next(h, tm));
    s.h_prev.push_back(prev(h, tm));
    s.h_opposite.push_back(opposite(h, tm));
    s.h_face.push_back(face(h, tm));
    s.h_target.push_back(target(h, tm));
  }
  for (auto f : faces(tm)) {
    s.faces.push_back(f);
    s.f_halfedge.push_back(halfedge(f, tm));
  }
  return s;
}

/// A progress callback that cancels at its `stop`-th call (0-based; never when stop is SIZE_MAX)
/// and counts its calls.
struct Cancel_at {
  std::size_t stop = SIZE_MAX;
  std::shared_ptr<std::size_t> calls = std::make_shared<std::size_t>(0);
  bool operator()(const meshfit::Progress_step&) const { return (*calls)++ != stop; }
};

/// Runs `stage(tm, callback)` on a fresh mesh from `make` cancelling at every progress call in
/// turn (at most about `samples` of them, spread over the run, first and last included), and
/// checks each time that the stage threw Algorithm_failure for the cancel and that `state_of(tm)`
/// is as before the call. Returns the number of progress calls of a complete run.
template <typename TriangleMesh, typename Make, typename Stage>
std::size_t check_cancels_leave_mesh(const char* what, const Make& make, const Stage& stage, std::size_t samples = 12) {
  std::size_t total = 0;
  {
    TriangleMesh tm;
    make(tm);
    Cancel_at count;
    stage(tm, count);
    total = *count.calls;
  }
  REQUIRE(total > 0);
  std::vector<std::size_t> stops;
  const std::size_t step = std::max<std::size_t>(1, total / samples);
  for (std::size_t k = 0; k < total; k += step) stops.push_back(k);
  if (stops.back() != total - 1) stops.push_back(total - 1);
  for (std::size_t k : stops) {
    INFO(what << ": cancelled at progress call " << k << " of " << total);
    TriangleMesh tm;
    make(tm);
    const auto before = state_of(tm);
    bool cancelled = false;
    try {
      stage(tm, Cancel_at{k});
    } catch (const meshfit::Algorithm_failure& e) {
      cancelled = std::string(e.what()).find("cancelled") != std::string::npos;
    }
    CHECK(cancelled);
    CHECK(state_of(tm) == before);
  }
  return total;
}

template <typename TriangleMesh>
void with_caller_maps(TriangleMesh& tm) {
  if constexpr (std::is_same_v<TriangleMesh, Mesh>) add_caller_maps(tm);
}

/// The example template, coarse-deformed (as deform_fine and deform_fine_on_surface take it).
template <typename TriangleMesh>
Network_and_pairs coarse_example(TriangleMesh& tm) {
  Network_and_pairs in = example(tm);
  meshfit::deform_coarse(tm, in.network, in.pairs);
  return in;
}

/// The example template, deformed by the thesis level (as partition_mesh takes it: every network
/// vertex a mesh vertex, the segments not yet edges, so that partitioning walks, flips and moves
/// vertices); with `partitioned`, partitioned too and its curve edges returned (as
/// smooth_fitted_mesh takes it).
template <typename TriangleMesh>
std::vector<std::array<std::size_t, 2>> deformed_example(TriangleMesh& tm, bool partitioned) {
  Network_and_pairs in = example(tm);
  meshfit::deform_template(tm, in.network, in.pairs, meshfit::parameters::fine_level(meshfit::Fine_level::thesis));
  if (!partitioned) return {};
  auto curve = get(CGAL::dynamic_edge_property_t<bool>(), tm);
  meshfit::partition_mesh(tm, in.network, CGAL::parameters::edge_is_constrained_map(curve));
  return meshfit::to_mesh_data(tm, CGAL::parameters::edge_is_constrained_map(curve)).curve_edges;
}

}  // namespace

TEMPLATE_TEST_CASE("stages: cancelling deform, partition or smooth at any step leaves the mesh exactly as it was",
                   "[fit][caller_data][cancel][generic]", Mesh, Poly) {
  using TriangleMesh = TestType;
  namespace mp = meshfit::parameters;
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  const meshfit::Curve_network network = meshfit::read_curve_network(d + "/curves.polylines.txt");
  const std::vector<meshfit::Correspondence> pairs = meshfit::read_correspondences(d + "/pairs.txt", network);

  auto template_mesh = [](TriangleMesh& tm) {
    example(tm);
    with_caller_maps(tm);
  };
  CHECK(check_cancels_leave_mesh<TriangleMesh>("deform_template", template_mesh, [&](TriangleMesh& tm, Cancel_at c) {
          meshfit::deform_template(tm, network, pairs, mp::progress(c));
        }) > 4);
  check_cancels_leave_mesh<TriangleMesh>("deform_template, thesis level", template_mesh,
                                         [&](TriangleMesh& tm, Cancel_at c) {
                                           meshfit::deform_template(
                                               tm, network, pairs, mp::progress(c).fine_level(meshfit::Fine_level::thesis));
                                         });
  check_cancels_leave_mesh<TriangleMesh>("deform_coarse", template_mesh, [&](TriangleMesh& tm, Cancel_at c) {
    meshfit::deform_coarse(tm, network, pairs, mp::progress(c));
  });
  auto coarse_mesh = [](TriangleMesh& tm) {
    coarse_example(tm);
    with_caller_maps(tm);
  };
  check_cancels_leave_mesh<TriangleMesh>("deform_fine", coarse_mesh, [&](TriangleMesh& tm, Cancel_at c) {
    meshfit::deform_fine(tm, network, pairs, mp::progress(c));
  });
  check_cancels_leave_mesh<TriangleMesh>("deform_fine_on_surface", coarse_mesh, [&](TriangleMesh& tm, Cancel_at c) {
    meshfit::deform_fine_on_surface(tm, network, pairs, mp::progress(c));
  });

  auto deformed_mesh = [](TriangleMesh& tm) {
    deformed_example(tm, false);
    with_caller_maps(tm);
  };
  // The caller's own maps as partition's outputs and input: on a cancel they keep their values.
  check_cancels_leave_mesh<TriangleMesh>("partition_mesh", deformed_mesh, [&](TriangleMesh& tm, Cancel_at c) {
    if constexpr (std::is_same_v<TriangleMesh, Mesh>) {
      const auto curve = tm.template property_map<Mesh::Edge_index, bool>("e:curve").first;
      const auto region = tm.template property_map<Mesh::Face_index, std::size_t>("f:region").first;
      const auto held = tm.template property_map<V, Point_2>("v:uv").first;  // any vertex map will do
      meshfit::partition_mesh(tm, network,
                              mp::progress(c)
                                  .edge_is_constrained_map(curve)
                                  .face_patch_map(region)
                                  .vertex_is_constrained_map(boost::make_function_property_map<V>(
                                      [held](V v) { return held[v].x() > 0.9; })));
    } else {
      meshfit::partition_mesh(tm, network, mp::progress(c));
    }
  });

  auto partitioned_mesh = [](TriangleMesh& tm) {
    deformed_example(tm, true);
    with_caller_maps(tm);
  };
  check_cancels_leave_mesh<TriangleMesh>("smooth_fitted_mesh", partitioned_mesh, [&](TriangleMesh& tm, Cancel_at c) {
    meshfit::smooth_fitted_mesh(tm, mp::progress(c).number_of_iterations(20));
  });
  check_cancels_leave_mesh<TriangleMesh>("laplacian_flow", partitioned_mesh, [&](TriangleMesh& tm, Cancel_at c) {
    meshfit::laplacian_flow(tm, mp::progress(c).number_of_iterations(10));
  });
}

TEMPLATE_TEST_CASE("stages: deform failing after it began (a polyline far from the template) leaves the mesh as it was",
                   "[fit][caller_data][generic]", Mesh, Poly) {
  using TriangleMesh = TestType;
  TriangleMesh tm;
  Network_and_pairs in = example(tm);
  with_caller_maps(tm);
  // The example's polylines and one more, far away: the coarse level moves the template (the
  // pairs are the example's), then the surface level refuses the far polyline.
  std::vector<meshfit::Curve_network::Polyline> lines;
  for (const auto& pl : in.network.polylines()) {
    meshfit::Curve_network::Polyline l;
    for (std::size_t v : pl) l.push_back(in.network.point(v));
    lines.push_back(l);
  }
  lines.push_back({meshfit::Point_3(50, 50, 50), meshfit::Point_3(51, 50, 50), meshfit::Point_3(52, 51, 50)});
  const meshfit::Curve_network far(lines);
  std::vector<meshfit::Correspondence> pairs = in.pairs;
  for (auto& c : pairs) c.network_vertex = *far.find_vertex(in.network.point(c.network_vertex));
  const auto before = state_of(tm);
  bool refused = false;
  try {
    meshfit::deform_template(tm, far, pairs);
  } catch (const meshfit::Algorithm_failure& e) {
    INFO(e.what());
    refused = std::string(e.what()).find("far") != std::string::npos;
  }
  CHECK(refused);
  CHECK(state_of(tm) == before);
}

TEMPLATE_TEST_CASE("stages: a completed partition is written into the caller's mesh as the stage made it on its own",
                   "[fit][caller_data][generic]", Mesh, Poly) {
  using TriangleMesh = TestType;
  const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
  const meshfit::Curve_network network = meshfit::read_curve_network(d + "/curves.polylines.txt");
  TriangleMesh tm;
  deformed_example(tm, false);
  with_caller_maps(tm);
  // The oracle: the same stage on a copy owned by the test, in place.
  TriangleMesh own;
  meshfit::build_triangle_mesh(meshfit::to_mesh_data(tm), own);
  auto own_curve = get(CGAL::dynamic_edge_property_t<bool>(), own);
  auto own_region = get(CGAL::dynamic_face_property_t<std::size_t>(), own);
  const auto own_report = meshfit::internal::partition_mesh_in_place(
      own, network, CGAL::parameters::edge_is_constrained_map(own_curve).face_patch_map(own_region));
  const meshfit::Mesh_data expected =
      meshfit::to_mesh_data(own, CGAL::parameters::edge_is_constrained_map(own_curve).face_patch_map(own_region));
  REQUIRE(own_report.by_walk + own_report.by_fallback > 0);  // the stage changed the mesh

  const auto vertices_before = std::vector<typename boost::graph_traits<TriangleMesh>::vertex_descriptor>(
      vertices(tm).begin(), vertices(tm).end());
  std::vector<Point_2> uv_before;
  if constexpr (std::is_same_v<TriangleMesh, Mesh>)
    for (V v : tm.vertices()) uv_before.push_back(tm.template property_map<V, Point_2>("v:uv").first[v]);
  auto curve = get(CGAL::dynamic_edge_property_t<bool>(), tm);
  auto region = get(CGAL::dynamic_face_property_t<std::size_t>(), tm);
  const auto report =
      meshfit::partition_mesh(tm, network, CGAL::parameters::edge_is_constrained_map(curve).face_patch_map(region));
  CHECK(report.curve_edges == own_report.curve_edges);
  CHECK(report.regions == own_report.regions);
  // Same vertices (same descriptors, same positions), same triangles, curve edges and regions.
  CHECK(std::equal(vertices_before.begin(), vertices_before.end(), vertices(tm).begin(), vertices(tm).end()));
  const meshfit::Mesh_data got =
      meshfit::to_mesh_data(tm, CGAL::parameters::edge_is_constrained_map(curve).face_patch_map(region));
  CHECK(got.points == expected.points);
  auto triangles_with_regions = [](const meshfit::Mesh_data& m) {
    std::set<std::pair<std::array<std::size_t, 3>, int>> out;
    for (std::size_t f = 0; f < m.triangles.size(); ++f) out.emplace(rotated(m.triangles[f]), m.face_patch[f]);
    return out;
  };
  CHECK(triangles_with_regions(got) == triangles_with_regions(expected));
  auto edge_set = [](const meshfit::Mesh_data& m) {
    std::set<std::pair<std::size_t, std::size_t>> out;
    for (const auto& e : m.curve_edges) out.insert(ordered(e[0], e[1]));
    return out;
  };
  CHECK(edge_set(got) == edge_set(expected));
  // And the independent oracle on the result: every segment a chain of edges, all of them curve
  // edges, 12 regions across them.
  const fit_oracle::Mesh result = fit_oracle::copy_of(tm);
  const fit_oracle::Embedding embedded = fit_oracle::embedding(
      result, fit_oracle::network_of(fit_oracle::read_polylines(d + "/curves.polylines.txt")));
  CHECK(embedded.missing == 0);
  CHECK(embedded.not_chained == 0);
  CHECK(embedded.regions == 12);
  std::set<std::pair<std::size_t, std::size_t>> chain_edges;
  for (auto e : result.edges())
    if (embedded.chain_edge[e.idx()]) chain_edges.insert(ordered(result.vertex(e, 0), result.vertex(e, 1)));
  const auto curve_edges = edge_set(got);
  CHECK(std::includes(curve_edges.begin(), curve_edges.end(), chain_edges.begin(), chain_edges.end()));
  if constexpr (std::is_same_v<TriangleMesh, Mesh>) {
    // The caller's vertex map keeps its values on every vertex (none added by partitioning).
    const auto uv = tm.template property_map<V, Point_2>("v:uv").first;
    std::vector<Point_2> uv_after;
    for (V v : tm.vertices()) uv_after.push_back(uv[v]);
    CHECK(uv_after == uv_before);
  }
}

// ---- kernels: any Cartesian kernel over double --------------------------------------------------

TEST_CASE("kernels: a Simple_cartesian<double> Surface_mesh goes through every stage with Epick's coordinates",
          "[fit][caller_data][kernel]") {
  using SC = CGAL::Simple_cartesian<double>;
  using SC_mesh = CGAL::Surface_mesh<SC::Point_3>;
  Mesh epick;
  const Network_and_pairs in = example(epick);
  SC_mesh sc;
  meshfit::build_triangle_mesh(meshfit::to_mesh_data(epick), sc);
  // The oracle: the same calls on the Epick mesh; meshfit reads and writes the coordinates as
  // doubles, so the results are the same numbers.
  auto same = [](const Mesh& a, const SC_mesh& b) {
    const meshfit::Mesh_data da = meshfit::to_mesh_data(a), db = meshfit::to_mesh_data(b);
    return da.points == db.points && da.triangles == db.triangles;
  };
  const Mesh epick_template = epick;
  const SC_mesh sc_template = sc;
  namespace mp = meshfit::parameters;
  meshfit::deform_template(epick, in.network, in.pairs, mp::fine_level(meshfit::Fine_level::thesis));
  meshfit::deform_template(sc, in.network, in.pairs,
                           mp::fine_level(meshfit::Fine_level::thesis).geom_traits(SC()));
  CHECK(same(epick, sc));
  auto epick_curve = get(CGAL::dynamic_edge_property_t<bool>(), epick);
  auto sc_curve = get(CGAL::dynamic_edge_property_t<bool>(), sc);
  const auto pe = meshfit::partition_mesh(epick, in.network, CGAL::parameters::edge_is_constrained_map(epick_curve));
  const auto ps = meshfit::partition_mesh(sc, in.network, CGAL::parameters::edge_is_constrained_map(sc_curve));
  CHECK(pe.by_walk + pe.by_fallback > 0);
  CHECK(ps.curve_edges == pe.curve_edges);
  CHECK(same(epick, sc));
  meshfit::smooth_fitted_mesh(epick, mp::default_values().number_of_iterations(10).edge_is_constrained_map(epick_curve));
  meshfit::smooth_fitted_mesh(sc, mp::default_values().number_of_iterations(10).edge_is_constrained_map(sc_curve));
  CHECK(same(epick, sc));

  Mesh epick_fit = epick_template;
  SC_mesh sc_fit = sc_template;
  auto sc_uv = sc_fit.add_property_map<SC_mesh::Vertex_index, SC::Point_2>("v:uv").first;
  for (auto v : sc_fit.vertices()) sc_uv[v] = SC::Point_2(sc_fit.point(v).x(), sc_fit.point(v).y());
  const auto re = meshfit::fit_template_to_curves(epick_fit, in.network, in.pairs, mp::default_values().number_of_iterations(10));
  const auto rs = meshfit::fit_template_to_curves(sc_fit, in.network, in.pairs,
                                                  mp::default_values().number_of_iterations(10).geom_traits(SC()).vertex_texture_map(sc_uv));
  CHECK(meshfit_test::oracle_passes(meshfit_test::check_example_fit(sc_fit)));
  CHECK(rs.vertices == re.vertices);
  CHECK(same(epick_fit, sc_fit));
  // The template's vertices keep their UVs; the added ones get finite values.
  std::size_t i = 0;
  for (auto v : sc_fit.vertices()) {
    if (i < sc_template.number_of_vertices())
      CHECK(sc_uv[v] == SC::Point_2(sc_template.point(v).x(), sc_template.point(v).y()));
    else
      CHECK((std::isfinite(sc_uv[v].x()) && std::isfinite(sc_uv[v].y())));
    ++i;
  }
}

}  // namespace meshfit_fit_caller_data_test
