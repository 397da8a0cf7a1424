// meshfit internal: the border cycles of a mesh, and whether it is connected and of genus 0.
#ifndef MESHFIT_INTERNAL_BORDER_CYCLES_H
#define MESHFIT_INTERNAL_BORDER_CYCLES_H

#include <CGAL/Dynamic_property_map.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/boost/graph/iterator.h>
#include <boost/graph/graph_traits.hpp>

#include <cstddef>
#include <optional>
#include <vector>

namespace meshfit {
namespace internal {

/// The border cycles of `tm`, each as its border halfedges in order.
template <typename TriangleMesh>
std::vector<std::vector<typename boost::graph_traits<TriangleMesh>::halfedge_descriptor>> border_cycles(
    const TriangleMesh& tm) {
  std::vector<std::vector<typename boost::graph_traits<TriangleMesh>::halfedge_descriptor>> cycles;
  auto seen = get(CGAL::dynamic_halfedge_property_t<bool>(), tm);
  for (auto h : halfedges(tm)) put(seen, h, false);
  for (auto h : halfedges(tm)) {
    if (!is_border(h, tm) || get(seen, h)) continue;
    cycles.emplace_back();
    for (auto g : CGAL::halfedges_around_face(h, tm)) {
      put(seen, g, true);
      cycles.back().push_back(g);
    }
  }
  return cycles;
}

/// Connected, and of genus 0 (a sphere, a disc, a sphere with holes): χ + (border cycles) = 2.
/// Then the number of border cycles, else nothing.
template <typename TriangleMesh>
std::optional<std::size_t> genus_zero_border_cycles(const TriangleMesh& tm) {
  auto component = get(CGAL::dynamic_face_property_t<std::size_t>(), tm);
  if (num_faces(tm) == 0 || CGAL::Polygon_mesh_processing::connected_components(tm, component) != 1) return {};
  const std::size_t cycles = border_cycles(tm).size();
  const long chi = static_cast<long>(num_vertices(tm)) - static_cast<long>(num_edges(tm)) + static_cast<long>(num_faces(tm));
  if (chi + static_cast<long>(cycles) != 2) return {};
  return cycles;
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_BORDER_CYCLES_H
