// meshfit internal: checks of fit's verification that tests use with their own inputs: folded
// and degenerate faces, self-intersection, and the number of regions a network bounds on a
// genus-0 mesh.
#ifndef MESHFIT_INTERNAL_FIT_CHECKS_H
#define MESHFIT_INTERNAL_FIT_CHECKS_H

#include <meshfit/curve_network.h>
#include <meshfit/predicates.h>
#include <meshfit/internal/border_cycles.h>
#include <meshfit/internal/stage_support.h>
#include <meshfit/kernel.h>

#include <CGAL/Surface_mesh.h>

#include <cstddef>
#include <optional>
#include <utility>

namespace meshfit {
namespace internal {

/// Interior edges of `tm` whose two faces turn more than 90 degrees apart, and zero-area faces.
template <typename TriangleMesh, typename VPM>
std::pair<std::size_t, std::size_t> folded_and_degenerate(const TriangleMesh& tm, const VPM& vpm) {
  auto corners = [&](auto h) {
    return Triangle_points{point_of<TriangleMesh>(vpm, source(h, tm)), point_of<TriangleMesh>(vpm, target(h, tm)),
                           point_of<TriangleMesh>(vpm, target(next(h, tm), tm))};
  };
  std::size_t folded = 0, degenerate = 0;
  for (auto f : faces(tm)) {
    const Triangle_points t = corners(halfedge(f, tm));
    degenerate += CGAL::collinear(t[0], t[1], t[2]) ? 1 : 0;
  }
  for (auto e : edges(tm)) {
    const auto h = halfedge(e, tm);
    if (is_border(h, tm) || is_border(opposite(h, tm), tm)) continue;
    folded += edge_folds(tm, h, [&](auto v) { return point_of<TriangleMesh>(vpm, v); }) ? 1 : 0;
  }
  return {folded, degenerate};
}

/// Whether `tm` intersects itself, as CGAL::Polygon_mesh_processing::does_self_intersect says of
/// the whole mesh (a face of no area counts as an intersection), tested in `slabs` slabs across
/// the longest side of its bounding box, one thread per slab (compiled once, src/fit.cpp). Slab i
/// holds every face whose extent along that side meets [q_i, q_i+1] (q the quantiles of the
/// faces' centres, q_0 = -inf, q_slabs = +inf): two faces that intersect overlap along that side at
/// some value, which lies in some slab, so both are in that slab's test. Faces across a slab's
/// ends are tested twice. On the 1 310 720-face scale output, 2 slabs on 2 cores: 1.55-1.73 s ->
/// 0.93-0.97 s (CGAL's own Parallel_tag with TBB: 3.1-3.2 s, as it shuffles the boxes and splits
/// them many times).
bool does_self_intersect_in_slabs(const CGAL::Surface_mesh<Point_3>& tm, std::size_t slabs);

/// The number of regions `network` bounds on `tm` once every segment is a chain of the edges
/// `curve`, when the topology of `tm` determines it (connected, genus 0, each border cycle either
/// all curve edges or none; see Fit_verification::expected_regions); empty otherwise.
template <typename TriangleMesh, typename ECM>
std::optional<std::size_t> expected_regions(const TriangleMesh& tm, const Curve_network& network, const ECM& curve) {
  if (!genus_zero_border_cycles(tm)) return {};
  // A border cycle with no curve edge is a hole inside one region; one made of curve edges only
  // bounds a face of the network that is not on the mesh. A cycle partly on curves is neither.
  std::size_t curve_cycles = 0;
  for (const auto& cycle : border_cycles(tm)) {
    std::size_t on_curve = 0;
    for (auto g : cycle) on_curve += get(curve, edge(g, tm)) ? 1 : 0;
    if (on_curve != 0 && on_curve != cycle.size()) return {};
    curve_cycles += on_curve == cycle.size() ? 1 : 0;
  }
  const std::size_t planar_faces =
      network.number_of_segments() + 1 + network.number_of_components() - network.number_of_vertices();
  if (curve_cycles > planar_faces) return {};
  return planar_faces - curve_cycles;
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_FIT_CHECKS_H
