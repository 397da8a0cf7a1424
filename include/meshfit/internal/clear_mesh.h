// meshfit internal: emptying a mesh without losing the property maps the caller passed in.
#ifndef MESHFIT_INTERNAL_CLEAR_MESH_H
#define MESHFIT_INTERNAL_CLEAR_MESH_H

#include <CGAL/boost/graph/helpers.h>

#include <type_traits>
#include <utility>

namespace meshfit {
namespace internal {

template <typename Mesh, typename = void>
struct Has_clear_keeping_maps : std::false_type {};
template <typename Mesh>
struct Has_clear_keeping_maps<
    Mesh, std::void_t<decltype(std::declval<Mesh&>().clear_without_removing_property_maps())>>
    : std::true_type {};

/// CGAL::Surface_mesh::clear() also removes the property maps added to the mesh, which would
/// leave a caller's face_patch_map dangling; this keeps them.
template <typename Mesh>
void clear_mesh(Mesh& tm) {
  if constexpr (Has_clear_keeping_maps<Mesh>::value) tm.clear_without_removing_property_maps();
  else CGAL::clear(tm);
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_CLEAR_MESH_H
