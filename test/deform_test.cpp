#include <meshfit/deform.h>
#include <meshfit/io.h>

#include <CGAL/Polyhedron_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/graph_traits_Polyhedron_3.h>
#include <CGAL/boost/graph/properties_Polyhedron_3.h>
#include <CGAL/boost/graph/helpers.h>

#include "test_helpers.h"

using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;
using meshfit::Closest_point_assignment;

namespace {

struct Example {
  Mesh tm;
  meshfit::Curve_network network;
  std::vector<meshfit::Correspondence> pairs;
};

Example load_example(const std::string& template_path = MESHFIT_EXAMPLE_DATA_DIR "/template.off") {
  Example e;
  meshfit::read_triangle_mesh(template_path, e.tm);
  e.network = meshfit::read_curve_network(MESHFIT_EXAMPLE_DATA_DIR "/curves.polylines.txt");
  e.pairs = meshfit::read_correspondences(MESHFIT_EXAMPLE_DATA_DIR "/pairs.txt", e.network);
  return e;
}

// Pairs for another sphere template: each feature point with the template vertex farthest in
// the direction the ellipsoid-to-sphere map sends it.
std::vector<meshfit::Correspondence> feature_pairs(const Mesh& tm, const meshfit::Curve_network& net) {
  std::vector<meshfit::Correspondence> pairs;
  for (std::size_t v : net.feature_points()) {
    const meshfit::Point_3& p = net.point(v);
    const meshfit::Vector_3 d(p.x() / 2, p.y() / 0.8, p.z() / 0.7);
    std::size_t best = 0;
    double score = -1e300;
    for (auto u : tm.vertices())
      if ((tm.point(u) - CGAL::ORIGIN) * d > score) {
        score = (tm.point(u) - CGAL::ORIGIN) * d;
        best = u.idx();
      }
    bool taken = false;
    for (const auto& q : pairs) taken = taken || q.template_vertex == best;
    if (taken) continue;
    meshfit::Correspondence c;
    c.template_vertex = best;
    c.network_vertex = v;
    pairs.push_back(c);
  }
  return pairs;
}

// Every network vertex that the report says is embedded is exactly a mesh vertex's position.
std::size_t embedded_exactly(const Mesh& tm, const meshfit::Curve_network& net, const meshfit::Deformation_report& r) {
  std::size_t n = 0;
  for (std::size_t v = 0; v < net.number_of_vertices(); ++v) {
    const std::size_t t = r.mesh_vertex_of_network_vertex.at(v);
    if (t == Closest_point_assignment::unassigned) continue;
    REQUIRE(t < tm.number_of_vertices());
    if (tm.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(t))) == net.point(v)) ++n;
  }
  return n;
}

// Faces whose normal points towards the origin: on a surface star-shaped around the origin
// (the ellipsoid) there must be none.
std::size_t inward_faces(const Mesh& tm) {
  std::size_t n = 0;
  for (auto f : tm.faces()) {
    std::vector<meshfit::Point_3> p;
    for (auto v : CGAL::vertices_around_face(tm.halfedge(f), tm)) p.push_back(tm.point(v));
    n += CGAL::orientation(p[0], p[1], p[2], meshfit::Point_3(0, 0, 0)) != CGAL::NEGATIVE;
  }
  return n;
}

}  // namespace

TEST_CASE("deform: the coarse level puts the paired vertices on their network vertices", "[deform]") {
  Example e = load_example();
  const auto r = meshfit::deform_coarse(e.tm, e.network, e.pairs);
  CHECK(r.user_pairs == 8);
  CHECK(r.coarse_fit.relative_residual < 1e-12);
  for (const auto& c : e.pairs)
    CHECK(e.tm.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(c.template_vertex))) == e.network.point(c.network_vertex));
  CHECK(e.tm.number_of_vertices() == 2562);
  CHECK(inward_faces(e.tm) == 0);
}

TEST_CASE("deform: sphere onto the ellipsoid network embeds every network vertex without flips", "[deform][example]") {
  Example e = load_example();
  const auto r = meshfit::deform_template(e.tm, e.network, e.pairs);
  CHECK(r.remaining_flips == 0);
  CHECK(r.dropped_network_vertices.empty());
  CHECK(embedded_exactly(e.tm, e.network, r) == e.network.number_of_vertices());
  CHECK(inward_faces(e.tm) == 0);
  CHECK(CGAL::is_valid_polygon_mesh(e.tm));
  CHECK(CGAL::is_closed(e.tm));
  // Vertices are only added, after the template's own.
  CHECK(r.vertices >= 2562);
  CHECK(r.faces == 2 * r.vertices - 4);
}

TEST_CASE("deform: the thesis's density mode keeps the mesh size and reports the dropped", "[deform][example]") {
  Example e = load_example();
  const auto r = meshfit::deform_template(e.tm, e.network, e.pairs,
                                          meshfit::parameters::curve_density(meshfit::Curve_density::drop));
  CHECK(r.remaining_flips == 0);
  CHECK(e.tm.number_of_vertices() == 2562);
  CHECK(e.tm.number_of_faces() == 5120);
  CHECK(!r.dropped_network_vertices.empty());
  CHECK(embedded_exactly(e.tm, e.network, r) + r.dropped_network_vertices.size() == e.network.number_of_vertices());
  CHECK(inward_faces(e.tm) == 0);
}

TEST_CASE("deform: the same result on Polyhedron_3", "[deform][generic]") {
  Example e = load_example();
  CGAL::Polyhedron_3<meshfit::Kernel> poly;
  meshfit::build_triangle_mesh(meshfit::to_mesh_data(e.tm), poly);
  const auto a = meshfit::deform_template(e.tm, e.network, e.pairs);
  const auto b = meshfit::deform_template(poly, e.network, e.pairs);
  CHECK(b.remaining_flips == 0);
  CHECK(a.vertices == b.vertices);
  const auto pa = meshfit::to_mesh_data(e.tm).points, pb = meshfit::to_mesh_data(poly).points;
  REQUIRE(pa.size() == pb.size());
  for (std::size_t i = 0; i < pa.size(); ++i) CHECK(pa[i] == pb[i]);
}

#ifdef MESHFIT_CGAL_DATA_DIR
TEST_CASE("deform: CGAL's sample sphere as template onto the ellipsoid network", "[deform][real]") {
  Example e = load_example(MESHFIT_CGAL_DATA_DIR "/larger_sphere.off");
  REQUIRE(e.tm.number_of_vertices() == 812);
  e.pairs = feature_pairs(e.tm, e.network);
  REQUIRE(e.pairs.size() >= 8);
  const auto r = meshfit::deform_template(e.tm, e.network, e.pairs);
  CHECK(r.remaining_flips == 0);
  CHECK(embedded_exactly(e.tm, e.network, r) == e.network.number_of_vertices());
  CHECK(CGAL::is_valid_polygon_mesh(e.tm));
}
#endif

TEST_CASE("deform: bad pairs give clear errors", "[deform]") {
  Example e = load_example();
  auto pairs = e.pairs;
  pairs[3].template_vertex = 99999;
  CHECK_THROWS_AS(meshfit::deform_coarse(e.tm, e.network, pairs), meshfit::Invalid_input);
  pairs.assign(e.pairs.begin(), e.pairs.begin() + 3);
  meshfit_test::require_invalid([&] { meshfit::deform_coarse(e.tm, e.network, pairs); }, 0, "at least 4");
}
