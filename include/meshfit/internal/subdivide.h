// meshfit internal: one step of midpoint (1-to-4) subdivision that keeps the mesh's vertices.
#ifndef MESHFIT_INTERNAL_SUBDIVIDE_H
#define MESHFIT_INTERNAL_SUBDIVIDE_H

#include <meshfit/kernel.h>

#include <CGAL/Dynamic_property_map.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/helpers.h>

#include <array>
#include <vector>

namespace meshfit {
namespace internal {

/// Splits every edge of the triangle mesh `tm` at its midpoint and every face into four (the
/// corner triangles and the middle one): the surface is unchanged, the faces are four times as
/// many and the edges half as long. The existing vertices keep their descriptors and their
/// order in vertices(tm); the new ones come after them (Euler operations only: the caller's
/// property maps stay valid). Border edges are split too.
template <typename TriangleMesh, typename VPM>
void subdivide_at_midpoints(TriangleMesh& tm, const VPM& vpm) {
  using GT = boost::graph_traits<TriangleMesh>;
  using P = typename boost::property_traits<VPM>::value_type;
  const std::vector<typename GT::edge_descriptor> old_edges(edges(tm).first, edges(tm).second);
  const std::vector<typename GT::face_descriptor> old_faces(faces(tm).first, faces(tm).second);
  auto is_new = get(CGAL::dynamic_vertex_property_t<bool>(), tm);
  for (auto v : vertices(tm)) put(is_new, v, false);
  for (auto e : old_edges) {
    const auto h = halfedge(e, tm);
    const auto a = get(vpm, source(h, tm)), b = get(vpm, target(h, tm));
    const P m((a.x() + b.x()) / 2, (a.y() + b.y()) / 2, (a.z() + b.z()) / 2);
    const auto g = CGAL::Euler::split_edge(h, tm);  // target(g) is the new vertex
    put(vpm, target(g, tm), m);
    put(is_new, target(g, tm), true);
  }
  for (auto f : old_faces) {
    // The face is now a hexagon o0 m0 o1 m1 o2 m2; hk is the halfedge that ends at mk.
    std::array<typename GT::halfedge_descriptor, 3> into{};
    std::size_t k = 0;
    for (auto h : CGAL::halfedges_around_face(halfedge(f, tm), tm))
      if (get(is_new, target(h, tm)) && k < 3) into[k++] = h;
    CGAL::Euler::split_face(into[0], into[1], tm);  // cuts off the corner at o1
    CGAL::Euler::split_face(into[2], into[0], tm);  // cuts off the corner at o0
    // Left: the quadrilateral m0 m1 o2 m2, of which into[2] (o2 -> m2) is a side.
    CGAL::Euler::split_face(prev(prev(into[2], tm), tm), into[2], tm);
  }
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_SUBDIVIDE_H
