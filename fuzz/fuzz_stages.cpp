// Fuzz targets of the geometric stages. Inputs are decoded into points on a coarse integer grid,
// so repeated, collinear and coplanar configurations are frequent.
#include "fuzz_common.h"

#include <meshfit/deform.h>
#include <meshfit/flip.h>
#include <meshfit/rbf.h>

#include <CGAL/Surface_mesh.h>

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

MESHFIT_FUZZ_TARGET(deform) {
  using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;
  // The template: an octahedron of radius 3 with its faces split 1-to-4 (18 vertices).
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
  Grid_reader g{data, size};
  std::vector<meshfit::Curve_network::Polyline> lines(1 + g.byte() % 3);
  for (auto& l : lines) {
    l.resize(2 + g.byte() % 4);
    for (auto& p : l) p = g.point(3);
  }
  try {
    const meshfit::Curve_network net(lines);
    std::vector<meshfit::Correspondence> pairs;
    const std::size_t wanted = 4 + g.byte() % 3;
    for (std::size_t k = 0; k < wanted; ++k) {
      meshfit::Correspondence c;
      c.template_vertex = static_cast<std::size_t>(g.byte()) % octa.points.size();
      c.network_vertex = static_cast<std::size_t>(g.byte()) % net.number_of_vertices();
      bool repeated = false;
      for (const auto& q : pairs) repeated = repeated || q.template_vertex == c.template_vertex || q.network_vertex == c.network_vertex;
      if (!repeated) pairs.push_back(c);
    }
    Mesh tm;
    meshfit::build_triangle_mesh(octa, tm);
    const auto density = g.byte() % 2 ? meshfit::Curve_density::drop : meshfit::Curve_density::refine;
    const auto r = meshfit::deform_template(tm, net, pairs,
                                            meshfit::parameters::curve_density(density).flip_prevention_rounds(4));
    MESHFIT_FUZZ_REQUIRE(CGAL::is_valid_polygon_mesh(tm));
    MESHFIT_FUZZ_REQUIRE(CGAL::is_closed(tm));
    for (auto v : tm.vertices()) MESHFIT_FUZZ_REQUIRE(meshfit_fuzz::finite(tm.point(v)));
    for (std::size_t v = 0; v < net.number_of_vertices(); ++v) {
      const std::size_t t = r.mesh_vertex_of_network_vertex[v];
      if (t == meshfit::Closest_point_assignment::unassigned) continue;
      MESHFIT_FUZZ_REQUIRE(t < tm.number_of_vertices());
      MESHFIT_FUZZ_REQUIRE(tm.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(t))) == net.point(v));
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
