// meshfit: stage 2, partitioning the mesh by the curves (thesis chapter 3 and appendix A).
// Every network vertex is a mesh vertex (after stage 1); each curve segment is made a chain of
// mesh edges (kept when it is one already, else by a walk across the faces and re-triangulation
// by edge flips, else by a shortest edge path moved onto it), and the faces are labelled by
// region. The method, step by step: internal/partition_impl.h.
#ifndef MESHFIT_PARTITION_H
#define MESHFIT_PARTITION_H

#include <meshfit/curve_network.h>
#include <meshfit/exceptions.h>
#include <meshfit/internal/commit_result.h>
#include <meshfit/internal/stage_support.h>
#include <meshfit/parameters.h>

#include <CGAL/Dynamic_property_map.h>
#include <CGAL/Named_function_parameters.h>
#include <CGAL/boost/graph/helpers.h>

#include <vector>

namespace meshfit {

/// How a curve segment became a chain of mesh edges.
enum class Segment_embedding {
  existing_edge,  ///< it was an edge, or a chain of edges lying on it, of the mesh already
  walk,           ///< projected path and re-triangulation of the clear-out region
  fallback,       ///< shortest edge path moved onto the segment
  not_embedded    ///< neither worked without folding the mesh
};

/// What partitioning did.
struct Partition_report {
  std::size_t segments = 0;        ///< segments of the network
  std::size_t existing_edges = 0;  ///< of those, Segment_embedding::existing_edge
  std::size_t by_walk = 0;         ///< Segment_embedding::walk
  std::size_t by_fallback = 0;     ///< Segment_embedding::fallback
  std::vector<std::size_t> not_embedded;          ///< indices into network.segments()
  std::vector<Segment_embedding> how;             ///< per segment
  std::size_t walks_failed = 0;                   ///< walks that did not reach their end (or could not be inserted)
  std::size_t faces_crossed = 0;                  ///< by the walks that were inserted
  std::size_t edge_flips = 0;                     ///< flips kept (flips undone are not counted)
  std::size_t vertices_moved = 0;                 ///< path vertices moved onto their segments
  std::size_t curve_edges = 0;                    ///< edges on the curves at the end
  std::size_t regions = 0;                        ///< regions labelled
  std::size_t vertices = 0;                       ///< unchanged by partitioning
  std::size_t faces = 0;                          ///< unchanged by partitioning
  double seconds = 0;                             ///< in all; by phase:
  double matching_seconds = 0;  ///< network vertices matched to mesh vertices, existing edges taken
  double walk_seconds = 0;      ///< insertions along the projected paths
  double fallback_seconds = 0;  ///< shortest paths
  double region_seconds = 0;    ///< labelling
  /// For each network vertex, the index (in the order of vertices(tm)) of its mesh vertex.
  std::vector<std::size_t> mesh_vertex_of_network_vertex;
};

template <typename TriangleMesh, typename VPM, typename ECM>
std::vector<typename boost::graph_traits<TriangleMesh>::vertex_descriptor> segment_edge_chain(
    const TriangleMesh& tm, const VPM& vpm, const ECM& ecm,
    typename boost::graph_traits<TriangleMesh>::vertex_descriptor a,
    typename boost::graph_traits<TriangleMesh>::vertex_descriptor b, double tolerance);

namespace internal {
/// partition_mesh on meshfit's own mesh, compiled once (src/partition.cpp): the mesh changes as
/// the work goes (a cancel leaves it partly partitioned). `fixed` may be null; `region`, when not
/// null, receives the regions.
Partition_report partition_work(Work_mesh& tm, const Curve_network& network, const Progress_callback& progress,
                                Work_edge_flags curve, const Work_vertex_flags* fixed, Work_face_labels* region);
}  // namespace internal

/// Makes every segment of `network` a chain of edges of `tm` (see the top of this file) and labels
/// the regions between them. Every network vertex must be a vertex of `tm` (within the network's
/// merge tolerance). The numbers of vertices and faces do not change; vertex positions change
/// only where a path vertex is moved onto its segment.
/// A segment that cannot be embedded without folding the mesh is listed in
/// `report.not_embedded`; the mesh is then left as it was around it.
/// The work is done on a copy of `tm` (internal/commit_result.h): an exception (a cancel from the
/// `progress` callback, …) leaves `tm`, its property maps and their values as they were; on
/// success the result is written into `tm` in place, as fit_template_to_curves does (a
/// CGAL::Surface_mesh keeps its property maps, with their values on every vertex and on the edges
/// and faces no flip replaced; a CGAL::Polyhedron_3 keeps its vertex handles, its faces and
/// halfedges are made anew), and the output maps are written after that.
/// \tparam TriangleMesh a model of `MutableFaceGraph` (tested: CGAL::Surface_mesh, CGAL::Polyhedron_3) whose
///         points have double Cartesian coordinates (any Cartesian kernel over double, e.g. Epick,
///         Simple_cartesian<double>; an exact kernel is refused at compile time)
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param tm the mesh, whose vertices include the network's (as deform_template leaves it)
/// \param network the curve network
/// \param np an optional sequence of named parameters among the ones listed below
/// \return how each segment was embedded, the counts and the time of each phase
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `ReadWritePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///       meshfit::Point_3 as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for `CGAL::vertex_point_t` must be
///       available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{edge_is_constrained_map}
///     \cgalParamDescription{output: set to `true` exactly on the curve edges (every edge is written)}
///     \cgalParamType{a class model of `ReadWritePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%edge_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{an internal map: the curve edges are not returned}
///   \cgalParamNEnd
///   \cgalParamNBegin{face_patch_map}
///     \cgalParamDescription{output: the region of each face, numbered from 0}
///     \cgalParamType{a class model of `WritablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%face_descriptor` as key type and an integer type
///       (`std::size_t` fits every value) as value type}
///     \cgalParamDefault{none: the regions are counted (`report.regions`) but not written}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_is_constrained_map}
///     \cgalParamDescription{input: vertices that must not move, besides the network's}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: only the network's vertices (and the inner vertices of segments that are already edge
///       chains) are held}
///   \cgalParamNEnd
///   \cgalParamNBegin{progress}
///     \cgalParamDescription{a callback called at each step with a meshfit::Progress_step (stage `"partition"`)}
///     \cgalParamType{a callable taking `const meshfit::Progress_step&` and returning `bool` (`false` cancels) or
///       `void` (never cancels)}
///     \cgalParamDefault{none: no calls, no cancelling}
///     \cgalParamExtra{When it returns `false`, partition_mesh throws meshfit::Algorithm_failure.}
///   \cgalParamNEnd
///   \cgalParamNBegin{geom_traits}
///     \cgalParamDescription{the geometric traits of `tm`'s points: checked at compile time to be a Cartesian kernel over `double`; the computation does not call it}
///     \cgalParamType{a Cartesian kernel over `double` (`FT` = `double`): `CGAL::Epick`, `CGAL::Simple_cartesian<double>`;
///       anything else (an exact kernel such as Epeck) is refused at compile time by a static assertion}
///     \cgalParamDefault{the kernel of the point type of the `vertex_point_map` (meshfit::Kernel, Epick, for meshfit::Point_3)}
///     \cgalParamExtra{The stage computes on a copy of the coordinates in meshfit::Kernel (exact predicates on the same
///       doubles), so the results do not depend on this parameter.}
///   \cgalParamNEnd
///   \cgalParamNBegin{number_of_threads}
///     \cgalParamDescription{the most threads (OpenMP's and OpenBLAS's, threads.h) the call uses; the counts are put back
///       as they were when it returns or throws (meshfit::Scoped_number_of_threads)}
///     \cgalParamType{an integer type, at least 1}
///     \cgalParamDefault{unchanged: every core, or what `OMP_NUM_THREADS`, `OPENBLAS_NUM_THREADS` or
///       meshfit::set_number_of_threads() set}
///     \cgalParamExtra{A value below 1 throws meshfit::Invalid_input before any work.}
///   \cgalParamNEnd
/// \cgalNamedParamsEnd
///
/// \throws Invalid_input when `tm` is not a triangle mesh, the network has no segment, or a
///         network vertex is not a mesh vertex (or two network vertices have the same one).
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Partition_report partition_mesh(TriangleMesh& tm, const Curve_network& network,
                                const NamedParameters& np = CGAL::parameters::default_values()) {
  using CGAL::parameters::get_parameter;
  if (!CGAL::is_triangle_mesh(tm)) throw Invalid_input("partition: the mesh is not a triangle mesh");
  if (network.number_of_segments() == 0) throw Invalid_input("partition: the curve network has no segment");
  const Scoped_number_of_threads threads(internal::threads_of(np, "partition"));
  // The work is done on a copy (internal/commit_result.h): `tm` changes only once it is complete.
  const auto vpm = internal::vertex_point_map_of(tm, np);
  internal::Stage_copy<TriangleMesh, std::decay_t<decltype(vpm)>> copy(tm, vpm);
  const auto fixed = copy.template vertex_map_from<bool>(get_parameter(np, CGAL::internal_np::vertex_is_constrained), false);
  auto curve = get(CGAL::dynamic_edge_property_t<bool>(), copy.work);
  auto region = get(CGAL::dynamic_face_property_t<std::size_t>(), copy.work);
  Partition_report report = internal::partition_work(
      copy.work, network, internal::progress_callback(get_parameter(np, internal_np::progress)), curve, &fixed, &region);
  const Mesh_data result =
      to_mesh_data(copy.work, CGAL::parameters::edge_is_constrained_map(curve).face_patch_map(region));
  const internal::Committed_elements<TriangleMesh> committed = copy.commit(result);
  internal::put_patches_and_curves(result, tm, committed.vertex_of, committed.face_of, np);
  return report;
}

/// The chain of curve edges that embeds the segment from vertex `a` to vertex `b`: consecutive
/// vertices from `a` to `b` joined by edges where `ecm` is true, whose inner vertices lie within
/// `tolerance` of the segment and advance along it. Empty when there is none. (A check for tests
/// and for the pipeline's final verification.)
template <typename TriangleMesh, typename VPM, typename ECM>
std::vector<typename boost::graph_traits<TriangleMesh>::vertex_descriptor> segment_edge_chain(
    const TriangleMesh& tm, const VPM& vpm, const ECM& ecm,
    typename boost::graph_traits<TriangleMesh>::vertex_descriptor a,
    typename boost::graph_traits<TriangleMesh>::vertex_descriptor b, double tolerance) {
  using vertex_descriptor = typename boost::graph_traits<TriangleMesh>::vertex_descriptor;
  const Point_3 pa = internal::point_of<TriangleMesh>(vpm, a), pb = internal::point_of<TriangleMesh>(vpm, b);
  const Vector_3 d = pb - pa;
  const double dd = d.squared_length();
  std::vector<vertex_descriptor> chain{a};
  double t = 0;
  for (std::size_t guard = 0; guard <= num_vertices(tm); ++guard) {
    const vertex_descriptor c = chain.back();
    vertex_descriptor best = c;
    double best_t = 2;
    for (auto h : CGAL::halfedges_around_target(halfedge(c, tm), tm)) {
      if (!get(ecm, edge(h, tm))) continue;
      const vertex_descriptor u = source(h, tm);
      if (u == b) {
        chain.push_back(b);
        return chain;
      }
      const Point_3 pu = internal::point_of<TriangleMesh>(vpm, u);
      const double tu = ((pu - pa) * d) / dd;
      if (tu <= t || tu >= 1) continue;
      if (CGAL::squared_distance(pu, pa + tu * d) > tolerance * tolerance) continue;
      if (tu < best_t) best = u, best_t = tu;
    }
    if (best == c) return {};
    chain.push_back(best);
    t = best_t;
  }
  return {};
}

}  // namespace meshfit

#endif  // MESHFIT_PARTITION_H
