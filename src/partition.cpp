// Stage 2 (partition.h) compiled once, for meshfit's own mesh.
#include <meshfit/internal/partition_impl.h>

namespace meshfit {
namespace internal {

Partition_report partition_work(Work_mesh& tm, const Curve_network& network, const Progress_callback& progress,
                                Work_edge_flags curve, const Work_vertex_flags* fixed, Work_face_labels* region) {
  // One instantiation: maps of no use to the caller are made here (all false; regions unread).
  Work_vertex_flags none = fixed ? *fixed : get(CGAL::dynamic_vertex_property_t<bool>(), tm);
  if (!fixed)
    for (auto v : vertices(tm)) put(none, v, false);
  const Work_face_labels labels = region ? *region : get(CGAL::dynamic_face_property_t<std::size_t>(), tm);
  return partition_mesh_in_place(
      tm, network,
      parameters::progress(progress).edge_is_constrained_map(curve).vertex_is_constrained_map(none).face_patch_map(labels));
}

}  // namespace internal
}  // namespace meshfit
