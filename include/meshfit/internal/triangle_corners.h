// meshfit internal: the three vertex indices of a triangle face, for any FaceGraph.
#ifndef MESHFIT_INTERNAL_TRIANGLE_CORNERS_H
#define MESHFIT_INTERNAL_TRIANGLE_CORNERS_H

#include <meshfit/exceptions.h>

#include <CGAL/boost/graph/iterator.h>

#include <array>
#include <cstddef>

namespace meshfit {
namespace internal {

/// The indices (through `index`, a vertex property map to std::size_t) of the corners of `f`,
/// in the face's order. \throws Invalid_input when `f` is not a triangle.
template <typename TriangleMesh, typename IndexMap>
std::array<std::size_t, 3> triangle_corners(typename boost::graph_traits<TriangleMesh>::face_descriptor f,
                                            const TriangleMesh& tm, const IndexMap& index) {
  std::array<std::size_t, 3> c{};
  std::size_t k = 0;
  for (auto v : CGAL::vertices_around_face(halfedge(f, tm), tm)) {
    if (k == 3) throw Invalid_input("a face has more than three vertices: not a triangle mesh");
    c[k++] = get(index, v);
  }
  if (k != 3) throw Invalid_input("a face has fewer than three vertices");
  return c;
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_TRIANGLE_CORNERS_H
