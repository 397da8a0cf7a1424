// meshfit: the projected path of a curve segment on the mesh (thesis appendix A).
//
// The thesis walks from the segment's start vertex face by face along dir_p = n × (dir_c × n)
// (eq. A.1–A.2), re-aiming at the end vertex after each crossing. Re-aiming from a constructed
// crossing point makes every later branch a decision on rounded numbers. Here the walk follows
// one cutting plane instead: the plane through the segment's two end vertices a, b that contains
// the mean of their vertex normals N (so, on each face, the path runs in the direction of dir_p
// for the mean normal, and the plane is fixed once per segment). The plane is given by a, b and
// one auxiliary point e rounded once (see Cutting_plane); after that every branch is an exact
// predicate on these three points and the mesh's points:
//   - which side of the plane a vertex lies on (orientation_in_plane, flip.h), hence which edge
//     of a face the path leaves through, and whether it passes exactly through a vertex or runs
//     along an edge (a vertex on the plane);
//   - whether a vertex lies before a, between a and b, or past b along the segment
//     (CGAL::angle, the sign of a dot product of differences of input points).
// The walk ends at b, or fails (a Walk_status says why); it never visits a face twice, so it
// takes at most num_faces steps. Crossings are stored symbolically (the halfedge crossed); the
// crossing point is constructed only on request.
#ifndef MESHFIT_SURFACE_WALK_H
#define MESHFIT_SURFACE_WALK_H

#include <meshfit/predicates.h>
#include <meshfit/internal/stage_support.h>
#include <meshfit/kernel.h>

#include <CGAL/Named_function_parameters.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>
#include <CGAL/boost/graph/named_params_helper.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

namespace meshfit {

/// How a walk ended.
enum class Walk_status {
  reached,             ///< the path reached the segment's end vertex
  boundary,            ///< the path left the mesh through a border edge
  constrained_edge,    ///< the path would cross an edge it must not cross (another curve)
  constrained_vertex,  ///< the path runs through a vertex it must not use (a network vertex, …)
  left_segment,        ///< the path went past the end or behind the start of the segment
  revisited,           ///< the path came back to a face or vertex it had passed (a loop)
  degenerate_plane,    ///< the segment is parallel to the surface normal: no cutting plane
  no_exit              ///< from a vertex on the path, no face continues it
};

/// A short phrase for messages: "reached", "left the mesh through its boundary", ….
inline const char* to_string(Walk_status s) {
  switch (s) {
    case Walk_status::reached: return "reached";
    case Walk_status::boundary: return "left the mesh through its boundary";
    case Walk_status::constrained_edge: return "would cross another curve";
    case Walk_status::constrained_vertex: return "runs through a constrained vertex";
    case Walk_status::left_segment: return "left the segment";
    case Walk_status::revisited: return "looped";
    case Walk_status::degenerate_plane: return "no cutting plane (segment along the normal)";
    case Walk_status::no_exit: return "found no way on";
  }
  return "?";
}

/// The plane a walk follows and the view in which its clear-out region is re-triangulated.
/// `e` is the auxiliary point: the triangle (a, b, e) has the normal N, the surface's mean normal
/// at a and b made orthogonal to the segment. Projected along N, the segment is a line and a
/// point's side of it is orientation_in_plane({a, b, e}, a, b, p): the same exact predicate
/// decides which edges the walk crosses and which edges the re-triangulation must remove, so
/// the two always agree. The cutting plane is the plane through a and b containing N.
struct Cutting_plane {
  Point_3 a;  ///< the segment's start
  Point_3 b;  ///< the segment's end
  Point_3 e;  ///< the auxiliary point (see above)
  Plane_orientation view;  ///< orientation in the view along N: in the plane of (a, b, e)
  /// Exact side of `p` (a and b themselves, which end most walks, without arithmetic).
  CGAL::Sign side(const Point_3& p) const { return p == a || p == b ? CGAL::ZERO : view(a, b, p); }
  /// Exact: p's projection on the line ab lies strictly between a and b.
  bool strictly_between(const Point_3& p) const {
    return CGAL::angle(b, a, p) == CGAL::ACUTE && CGAL::angle(a, b, p) == CGAL::ACUTE;
  }
  /// Exact: p's projection on the line ab lies before a (away from b).
  bool behind_a(const Point_3& p) const { return CGAL::angle(b, a, p) == CGAL::OBTUSE; }
  /// Exact: p's projection on the line ab lies past b.
  bool past_b(const Point_3& p) const { return CGAL::angle(a, b, p) == CGAL::OBTUSE; }
  /// Signed distance-like value of `p` (floating point; only to construct crossing points).
  double height(const Point_3& p) const {
    return CGAL::cross_product(b - a, e - a) * CGAL::cross_product(b - a, p - a);
  }
};

/// The projected path of a segment: the vertices it passes through (waypoints: its two end
/// vertices, plus any vertex lying exactly on the cutting plane between them) and, between
/// consecutive waypoints, the edges it crosses.
template <typename TriangleMesh>
struct Surface_path {
  /// The mesh's vertex type.
  using vertex_descriptor = typename boost::graph_traits<TriangleMesh>::vertex_descriptor;
  /// The mesh's halfedge type.
  using halfedge_descriptor = typename boost::graph_traits<TriangleMesh>::halfedge_descriptor;

  Walk_status status = Walk_status::no_exit;  ///< how the walk ended
  Cutting_plane plane;                        ///< the plane the walk followed
  std::vector<vertex_descriptor> waypoints;   ///< from the segment's start to its end (when reached)
  /// crossings[i]: the edges crossed between waypoints[i] and waypoints[i+1], in order, each as
  /// the halfedge of the face the path leaves.
  std::vector<std::vector<halfedge_descriptor>> crossings;

  /// The number of faces the path runs through (0 unless the end was reached).
  std::size_t faces_crossed() const {
    std::size_t n = 0;
    for (const auto& c : crossings) n += c.size() + 1;
    return status == Walk_status::reached ? n : 0;
  }
};

}  // namespace meshfit

#include <meshfit/internal/surface_walk_impl.h>

namespace meshfit {

/// The projected path of the segment from vertex `source` to vertex `target` of `tm` (thesis
/// appendix A, with one cutting plane per segment as described at the top of this file).
/// The result's `status` says whether `target` was reached; the waypoints and crossings are
/// filled only then.
/// \tparam TriangleMesh a model of `FaceGraph` whose faces are triangles
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param tm the mesh
/// \param source the segment's start, a vertex of `tm`
/// \param target the segment's end, another vertex of `tm`
/// \param np an optional sequence of named parameters among the ones listed below
/// \return the path (Surface_path), or why the walk stopped (`status`)
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///       meshfit::Point_3 as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for `CGAL::vertex_point_t` must be
///       available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{edge_is_constrained_map}
///     \cgalParamDescription{input: the edges the path must not cross}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%edge_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: every edge may be crossed}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_is_constrained_map}
///     \cgalParamDescription{input: the vertices the path must not pass through (its two ends excepted)}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: every vertex may be passed through}
///   \cgalParamNEnd
/// \cgalNamedParamsEnd
///
/// \throws Invalid_input when `source` and `target` are the same vertex.
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Surface_path<TriangleMesh> project_segment(const TriangleMesh& tm,
                                           typename boost::graph_traits<TriangleMesh>::vertex_descriptor source,
                                           typename boost::graph_traits<TriangleMesh>::vertex_descriptor target,
                                           const NamedParameters& np = CGAL::parameters::default_values()) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  using GT = boost::graph_traits<TriangleMesh>;
  const auto vpm = choose_parameter(get_parameter(np, CGAL::internal_np::vertex_point),
                                    get_const_property_map(CGAL::vertex_point, tm));
  const auto ecm = choose_parameter(get_parameter(np, CGAL::internal_np::edge_is_constrained),
                                    CGAL::Static_boolean_property_map<typename GT::edge_descriptor, false>());
  const auto vcm = choose_parameter(get_parameter(np, CGAL::internal_np::vertex_is_constrained),
                                    CGAL::Static_boolean_property_map<typename GT::vertex_descriptor, false>());
  if (source == target) throw Invalid_input("project_segment: the segment's two ends are one vertex");
  bool ok = false;
  const Cutting_plane plane = internal::cutting_plane(tm, vpm, source, target, ok);
  if (!ok) {
    Surface_path<TriangleMesh> path;
    path.plane = plane;
    path.status = Walk_status::degenerate_plane;
    return path;
  }
  auto edge_blocked = [&](typename GT::edge_descriptor e) { return bool(get(ecm, e)); };
  auto vertex_blocked = [&](typename GT::vertex_descriptor v) { return bool(get(vcm, v)); };
  internal::Segment_walker<TriangleMesh, decltype(vpm), decltype(edge_blocked), decltype(vertex_blocked)> walker(
      tm, vpm, edge_blocked, vertex_blocked);
  return walker.walk(source, target, plane);
}

}  // namespace meshfit

#endif  // MESHFIT_SURFACE_WALK_H
