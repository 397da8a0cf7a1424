// meshfit: the regions and curve edges of a Mesh_data written into a caller's property maps (the
// face_patch_map and edge_is_constrained_map named parameters), for io.h's read_triangle_mesh and
// the stages that return a partitioned mesh (partition.h, fit.h).
#ifndef MESHFIT_INTERNAL_PATCHES_AND_CURVES_H
#define MESHFIT_INTERNAL_PATCHES_AND_CURVES_H

#include <meshfit/exceptions.h>

#include <CGAL/Named_function_parameters.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/named_params_helper.h>

#include <cstddef>
#include <string>
#include <type_traits>

namespace meshfit {
namespace internal {

/// Writes the regions and curve edges of `mesh` (a Mesh_data, io.h) into the `face_patch_map` and
/// `edge_is_constrained_map` of `np` (when given), on `tm` whose vertex `vertex_of[i]` and face
/// `face_of[f]` are vertex i and triangle f of `mesh`.
template <typename MeshData, typename TriangleMesh, typename VertexRange, typename FaceRange, typename NamedParameters>
void put_patches_and_curves(const MeshData& mesh, TriangleMesh& tm, const VertexRange& vertex_of,
                            const FaceRange& face_of, const NamedParameters& np) {
  using CGAL::parameters::get_parameter;
  auto fpm = get_parameter(np, CGAL::internal_np::face_patch);
  if constexpr (!std::is_same_v<decltype(fpm), CGAL::internal_np::Param_not_found>) {
    for (std::size_t f = 0; f < face_of.size(); ++f)
      put(fpm, face_of[f], mesh.face_patch.empty() ? 0 : mesh.face_patch[f]);
  }
  auto ecm = get_parameter(np, CGAL::internal_np::edge_is_constrained);
  if constexpr (!std::is_same_v<decltype(ecm), CGAL::internal_np::Param_not_found>) {
    for (auto e : edges(tm)) put(ecm, e, false);
    for (const auto& ce : mesh.curve_edges) {
      if (ce[0] >= vertex_of.size() || ce[1] >= vertex_of.size())
        throw Invalid_input("a curve edge refers to a missing vertex");
      const auto h = halfedge(vertex_of[ce[0]], vertex_of[ce[1]], tm);
      if (!h.second)
        throw Invalid_input("curve edge (" + std::to_string(ce[0]) + ", " +
                            std::to_string(ce[1]) + ") is not an edge of the mesh");
      put(ecm, edge(h.first, tm), true);
    }
  }
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_PATCHES_AND_CURVES_H
