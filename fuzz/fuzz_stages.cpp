// Fuzz targets of the geometric stages. Inputs are decoded into points on a coarse integer grid,
// so repeated, collinear and coplanar configurations are frequent.
#include "fuzz_common.h"

#include <meshfit/deform.h>
#include <meshfit/fit.h>
#include <meshfit/flip.h>
#include <meshfit/rbf.h>

#include <CGAL/Surface_mesh.h>

#include <optional>

namespace {

// Reads bytes as grid coordinates in [-r, r]; missing bytes read as 0.
struct Grid_reader {
  const std::uint8_t* data;
  std::size_t size, pos = 0;
  int byte() { return pos < size ? data[pos++] : 0; }
  double coord(int r) { return static_cast<double>(byte() % (2 * r + 1) - r); }
  meshfit::Point_3 point(int r) {
    const double x = coord(r), y = coord(r), z = coord(r);
    return meshfit::Point_3(x, y, z);
  }
};

}  // namespace

MESHFIT_FUZZ_TARGET(flip) {
  Grid_reader g{data, size};
  meshfit::Triangle_points before, after;
  for (auto& p : before) p = g.point(2);
  for (auto& p : after) p = g.point(2);
  MESHFIT_FUZZ_REQUIRE(meshfit::flip_counter(before, after).state() == meshfit::orientation_flip_test(before, after));
  return 0;
}

MESHFIT_FUZZ_TARGET(rbf) {
  Grid_reader g{data, size};
  const std::size_t n = 4 + static_cast<std::size_t>(g.byte() % 9);
  const meshfit::Rbf_kernel kernel = g.byte() % 2 ? meshfit::Rbf_kernel::cubic : meshfit::Rbf_kernel::linear;
  std::vector<meshfit::Point_3> c(n), v(n);
  for (auto& p : c) p = g.point(2);
  for (auto& p : v) p = g.point(3);
  try {
    meshfit::Rbf_fit_report report;
    const meshfit::Rbf_interpolant E = meshfit::Rbf_interpolant::fit(c, v, kernel, {}, &report);
    std::vector<meshfit::Point_3> out;
    E.evaluate(c, out);
    for (std::size_t i = 0; i < n; ++i) {
      MESHFIT_FUZZ_REQUIRE(meshfit_fuzz::finite(out[i]));
      MESHFIT_FUZZ_REQUIRE(CGAL::squared_distance(out[i], v[i]) < 1e-12);
    }
  } catch (const meshfit::Invalid_input& e) {
    meshfit_fuzz::check_error(e, "RBF");
  } catch (const meshfit::Numerical_error&) {
  }
  return 0;
}

namespace {

// The template of the deform and fit targets: an octahedron of radius 3 with its faces split
// 1-to-4 (18 vertices).
const meshfit::Mesh_data& octahedron_template() {
  static const meshfit::Mesh_data octa = [] {
    meshfit::Mesh_data m;
    m.points = {{3, 0, 0}, {-3, 0, 0}, {0, 3, 0}, {0, -3, 0}, {0, 0, 3}, {0, 0, -3}};
    const std::vector<std::array<std::size_t, 3>> f = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                                       {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    std::map<std::pair<std::size_t, std::size_t>, std::size_t> mid;
    auto midpoint = [&](std::size_t a, std::size_t b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.points.push_back(CGAL::midpoint(m.points[a], m.points[b]));
      return mid[key] = m.points.size() - 1;
    };
    for (const auto& t : f) {
      const std::size_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      m.triangles.push_back({t[0], ab, ca});
      m.triangles.push_back({ab, t[1], bc});
      m.triangles.push_back({ca, bc, t[2]});
      m.triangles.push_back({ab, bc, ca});
    }
    return m;
  }();
  return octa;
}

// The stage inputs a byte string decodes to: 1-3 polylines of 2-5 grid points, 4-6 pairs (no
// template or network vertex twice), a curve density. Throws what Curve_network throws.
struct Stage_inputs {
  meshfit::Curve_network network;
  std::vector<meshfit::Correspondence> pairs;
  meshfit::Curve_density density = meshfit::Curve_density::refine;
};
Stage_inputs decode_stage_inputs(Grid_reader& g) {
  std::vector<meshfit::Curve_network::Polyline> lines(1 + g.byte() % 3);
  for (auto& l : lines) {
    l.resize(2 + g.byte() % 4);
    for (auto& p : l) p = g.point(3);
  }
  Stage_inputs in{meshfit::Curve_network(lines), {}, meshfit::Curve_density::refine};
  const std::size_t wanted = 4 + g.byte() % 3;
  for (std::size_t k = 0; k < wanted; ++k) {
    meshfit::Correspondence c;
    c.template_vertex = static_cast<std::size_t>(g.byte()) % octahedron_template().points.size();
    c.network_vertex = static_cast<std::size_t>(g.byte()) % in.network.number_of_vertices();
    bool repeated = false;
    for (const auto& q : in.pairs) repeated = repeated || q.template_vertex == c.template_vertex || q.network_vertex == c.network_vertex;
    if (!repeated) in.pairs.push_back(c);
  }
  in.density = g.byte() % 2 ? meshfit::Curve_density::drop : meshfit::Curve_density::refine;
  return in;
}

using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;

void require_valid_closed_finite(const Mesh& tm) {
  MESHFIT_FUZZ_REQUIRE(CGAL::is_valid_polygon_mesh(tm));
  MESHFIT_FUZZ_REQUIRE(CGAL::is_closed(tm));
  for (auto v : tm.vertices()) MESHFIT_FUZZ_REQUIRE(meshfit_fuzz::finite(tm.point(v)));
}

}  // namespace

MESHFIT_FUZZ_TARGET(deform) {
  Grid_reader g{data, size};
  try {
    const Stage_inputs in = decode_stage_inputs(g);
    Mesh tm;
    meshfit::build_triangle_mesh(octahedron_template(), tm);
    const auto r = meshfit::deform_template(tm, in.network, in.pairs,
                                            meshfit::parameters::curve_density(in.density).flip_prevention_rounds(4));
    require_valid_closed_finite(tm);
    for (std::size_t v = 0; v < in.network.number_of_vertices(); ++v) {
      const std::size_t t = r.mesh_vertex_of_network_vertex[v];
      if (t == meshfit::Closest_point_assignment::unassigned) continue;
      MESHFIT_FUZZ_REQUIRE(t < tm.number_of_vertices());
      MESHFIT_FUZZ_REQUIRE(tm.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(t))) == in.network.point(v));
    }
  } catch (const meshfit::Invalid_input& e) {
    meshfit_fuzz::check_error(e, "");
  } catch (const meshfit::Numerical_error&) {
  } catch (const meshfit::Algorithm_failure& e) {
    // exit 3 of the command: the algorithm says why it cannot go on
    MESHFIT_FUZZ_REQUIRE(std::string(e.what()).size() > std::string("deform: ").size());
  }
  return 0;
}

// The whole pipeline on the deform target's inputs (same decoding, same corpus format). Promised:
// on return, a valid closed mesh with finite coordinates, a region for every face, and, when the
// verification passed, every network vertex exactly at its mesh vertex and every curve edge
// between two vertices that lie on one segment's line; on an exception, the mesh as it was.
MESHFIT_FUZZ_TARGET(fit) {
  Grid_reader g{data, size};
  std::optional<Stage_inputs> in;
  try {
    in = decode_stage_inputs(g);
  } catch (const meshfit::Invalid_input& e) {
    meshfit_fuzz::check_error(e, "");
    return 0;
  }
  Mesh tm;
  meshfit::build_triangle_mesh(octahedron_template(), tm);
  std::vector<meshfit::Point_3> before;
  for (auto v : tm.vertices()) before.push_back(tm.point(v));
  auto curve = tm.add_property_map<Mesh::Edge_index, bool>("e:curve", false).first;
  auto region = tm.add_property_map<Mesh::Face_index, std::size_t>("f:region", SIZE_MAX).first;
  auto unchanged = [&] {
    if (tm.number_of_vertices() != before.size() || tm.number_of_faces() != octahedron_template().triangles.size()) return false;
    std::size_t i = 0;
    for (auto v : tm.vertices())
      if (tm.point(v) != before[i++]) return false;
    return true;
  };
  try {
    const meshfit::Fit_report r = meshfit::fit_template_to_curves(
        tm, in->network, in->pairs,
        meshfit::parameters::curve_density(in->density)
            .flip_prevention_rounds(4)
            .number_of_iterations(10)
            .edge_is_constrained_map(curve)
            .face_patch_map(region));
    require_valid_closed_finite(tm);
    for (auto f : tm.faces()) MESHFIT_FUZZ_REQUIRE(region[f] < std::max<std::size_t>(r.partition.regions, 1));
    if (r.verification.passed()) {
      for (std::size_t v = 0; v < in->network.number_of_vertices(); ++v) {
        const std::size_t t = r.mesh_vertex_of_network_vertex[v];
        MESHFIT_FUZZ_REQUIRE(t < tm.number_of_vertices());
        MESHFIT_FUZZ_REQUIRE(tm.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(t))) == in->network.point(v));
      }
      // A curve edge joins two points of one segment's line (exact collinearity).
      for (auto e : tm.edges()) {
        if (!curve[e]) continue;
        const meshfit::Point_3 a = tm.point(tm.source(tm.halfedge(e))), b = tm.point(tm.target(tm.halfedge(e)));
        bool on_a_segment = false;
        for (const auto& sg : in->network.segments()) {
          const meshfit::Point_3 &p = in->network.point(sg[0]), &q = in->network.point(sg[1]);
          on_a_segment = on_a_segment || (CGAL::collinear(p, q, a) && CGAL::collinear(p, q, b));
        }
        MESHFIT_FUZZ_REQUIRE(on_a_segment);
      }
    }
  } catch (const meshfit::Invalid_input& e) {
    meshfit_fuzz::check_error(e, "");
    MESHFIT_FUZZ_REQUIRE(unchanged());
  } catch (const meshfit::Numerical_error&) {
    MESHFIT_FUZZ_REQUIRE(unchanged());
  } catch (const meshfit::Algorithm_failure& e) {
    MESHFIT_FUZZ_REQUIRE(std::string(e.what()).size() > std::string("fit: ").size());
    MESHFIT_FUZZ_REQUIRE(unchanged());
  }
  return 0;
}
