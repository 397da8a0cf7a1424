// meshfit internal: replacing a template by the result of the pipeline in place, so that the
// caller's mesh keeps its identity: its property maps (CGAL::Surface_mesh) and the descriptors
// of the template's vertices (every mesh type).
//
// The result (`work`, built from the template with vertex i = template vertex i and the added
// vertices after them) becomes the content of `tm`:
//   - CGAL::Surface_mesh: the connectivity of `work` is written into the existing elements of
//     `tm`. Template vertex i keeps its index and its property values; an edge (face) of the
//     result joining the same template vertices as an edge (face, same orientation) of the
//     template keeps that element's index and property values (its halfedges keep their
//     directions); the other elements of the result reuse the template's unmatched and removed
//     elements or are appended, and get every property map's default value. Removed template
//     vertices stay removed (the added vertices are appended after every index).
//   - other meshes (CGAL::Polyhedron_3, …): every face and edge of `tm` is removed through the
//     BGL (CGAL::remove_face, remove_edge), the template's vertices are kept, the added vertices
//     are appended (add_vertex) and the faces added with CGAL::Euler::add_face: vertex
//     descriptors of the template stay valid, face, edge and halfedge descriptors do not.
#ifndef MESHFIT_INTERNAL_COMMIT_RESULT_H
#define MESHFIT_INTERNAL_COMMIT_RESULT_H

#include <meshfit/exceptions.h>
#include <meshfit/internal/stage_support.h>
#include <meshfit/io.h>
#include <meshfit/kernel.h>
#include <meshfit/parameters.h>

#include <CGAL/Dynamic_property_map.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <unordered_map>
#include <vector>

namespace meshfit {
namespace internal {

/// The mesh the stages work on, whatever the caller's: points of meshfit's kernel (Epick), so that
/// the caller's mesh may have any Cartesian kernel over double (its points are read and written
/// as doubles, exactly).
using Work_mesh = CGAL::Surface_mesh<Point_3>;
/// Flags on its edges and vertices, labels on its faces (dynamic property maps).
using Work_edge_flags = boost::property_map<Work_mesh, CGAL::dynamic_edge_property_t<bool>>::type;
using Work_vertex_flags = boost::property_map<Work_mesh, CGAL::dynamic_vertex_property_t<bool>>::type;
using Work_face_labels = boost::property_map<Work_mesh, CGAL::dynamic_face_property_t<std::size_t>>::type;

template <typename Mesh>
struct Is_surface_mesh : std::false_type {};
template <typename P>
struct Is_surface_mesh<CGAL::Surface_mesh<P>> : std::true_type {};

/// The elements of `tm` that hold the result's vertices and faces, in the order to_mesh_data
/// numbers them on `work` (vertices(work), faces(work)).
template <typename TriangleMesh>
struct Committed_elements {
  std::vector<typename boost::graph_traits<TriangleMesh>::vertex_descriptor> vertex_of;
  std::vector<typename boost::graph_traits<TriangleMesh>::face_descriptor> face_of;
};

/// Key of an undirected edge or of a triangle up to rotation, by result vertex index.
inline std::uint64_t edge_key(std::size_t a, std::size_t b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t(a) << 32) | std::uint64_t(b);
}
struct Triangle_key_hash {
  std::size_t operator()(const std::array<std::size_t, 3>& t) const {
    return std::hash<std::size_t>()(t[0]) ^ (std::hash<std::size_t>()(t[1]) * 0x9e3779b97f4a7c15ULL) ^
           (std::hash<std::size_t>()(t[2]) * 0xc2b2ae3d27d4eb4fULL);
  }
};
inline std::array<std::size_t, 3> triangle_key(std::array<std::size_t, 3> t) {
  while (t[0] > t[1] || t[0] > t[2]) t = {t[1], t[2], t[0]};
  return t;
}

/// CGAL::Surface_mesh: see the top of this file. `points[k]` is the position of the result's
/// vertex k, written through `vpm`.
template <typename WorkPoint, typename Point, typename VPM>
Committed_elements<CGAL::Surface_mesh<Point>> commit_surface_mesh(const CGAL::Surface_mesh<WorkPoint>& work,
                                                                   const std::vector<Point_3>& points,
                                                                   CGAL::Surface_mesh<Point>& tm, const VPM& vpm) {
  using Mesh = CGAL::Surface_mesh<Point>;
  using P = typename boost::property_traits<VPM>::value_type;
  using V = typename Mesh::Vertex_index;
  using H = typename Mesh::Halfedge_index;
  using E = typename Mesh::Edge_index;
  using F = typename Mesh::Face_index;
  constexpr std::size_t none = SIZE_MAX;
  if (std::max(tm.num_vertices(), work.num_vertices()) >= (std::size_t(1) << 32))
    throw Invalid_input("fit: too many vertices");

  // Everything is computed before `tm` changes.
  std::vector<V> template_vertex(tm.vertices().begin(), tm.vertices().end());
  const std::size_t nt = template_vertex.size();
  std::vector<std::size_t> tindex(tm.num_vertices(), none), windex(work.num_vertices(), none);
  for (std::size_t i = 0; i < nt; ++i) tindex[template_vertex[i]] = i;
  std::size_t nw = 0;
  for (auto w : work.vertices()) windex[w] = nw++;
  if (nw != points.size() || nw < nt) throw Invalid_input("fit: the result does not extend the template");

  // Template edges and faces by their vertices.
  std::unordered_map<std::uint64_t, E> template_edge;
  template_edge.reserve(tm.number_of_edges());
  for (E e : tm.edges())
    template_edge.emplace(edge_key(tindex[tm.source(tm.halfedge(e))], tindex[tm.target(tm.halfedge(e))]), e);
  std::unordered_map<std::array<std::size_t, 3>, F, Triangle_key_hash> template_face;
  template_face.reserve(tm.number_of_faces());
  for (F f : tm.faces()) {
    const H h = tm.halfedge(f);
    if (tm.next(tm.next(tm.next(h))) != h) continue;  // not a triangle: no result face matches it
    template_face.emplace(triangle_key({tindex[tm.target(tm.prev(h))], tindex[tm.target(h)],
                                        tindex[tm.target(tm.next(h))]}),
                          f);
  }

  // The halfedge of `tm` standing for halfedge(e) of each edge e of `work` (null: not matched yet).
  std::vector<H> base(work.num_edges(), H());
  std::vector<char> edge_kept(tm.num_edges(), 0), face_kept(tm.num_faces(), 0);
  std::vector<F> face_of_work(work.num_faces(), F());
  std::vector<E> unmatched_edges;
  std::vector<F> unmatched_faces;
  for (auto e : work.edges()) {
    const auto h = work.halfedge(e);
    const std::size_t s = windex[work.source(h)], t = windex[work.target(h)];
    if (s >= nt || t >= nt) {
      unmatched_edges.push_back(e);
      continue;
    }
    const auto it = template_edge.find(edge_key(s, t));
    if (it == template_edge.end()) {
      unmatched_edges.push_back(e);
      continue;
    }
    const H th = tm.halfedge(it->second);
    base[e] = tindex[tm.target(th)] == t ? th : tm.opposite(th);
    edge_kept[it->second] = 1;
  }
  for (auto f : work.faces()) {
    const auto h = work.halfedge(f);
    const std::array<std::size_t, 3> c{windex[work.target(work.prev(h))], windex[work.target(h)],
                                       windex[work.target(work.next(h))]};
    const auto it = c[0] < nt && c[1] < nt && c[2] < nt ? template_face.find(triangle_key(c)) : template_face.end();
    if (it == template_face.end()) {
      unmatched_faces.push_back(f);
      continue;
    }
    face_of_work[f] = it->second;
    face_kept[it->second] = 1;
  }

  // The elements of the template that no result element matches go to the free lists; the
  // result's other edges and faces take them back (add_edge and add_face reset their property
  // values to the defaults) or are appended. Vertices are appended, never recycled: the
  // template's vertices come first in vertices(tm).
  const bool recycle = tm.does_recycle_garbage(), had_garbage = tm.has_garbage();
  for (E e : std::vector<E>(tm.edges().begin(), tm.edges().end()))
    if (!edge_kept[e]) tm.remove_edge(e);
  for (F f : std::vector<F>(tm.faces().begin(), tm.faces().end()))
    if (!face_kept[f]) tm.remove_face(f);
  tm.set_recycle_garbage(true);
  for (E e : unmatched_edges) base[e] = tm.add_edge();
  for (F f : unmatched_faces) face_of_work[f] = tm.add_face();
  tm.set_recycle_garbage(false);
  Committed_elements<Mesh> out;
  out.vertex_of = template_vertex;
  out.vertex_of.reserve(nw);
  for (std::size_t k = nt; k < nw; ++k) out.vertex_of.push_back(tm.add_vertex());
  tm.set_recycle_garbage(recycle);

  auto vertex_of = [&](V w) { return out.vertex_of[windex[w]]; };
  // base[e] stands for halfedge(e) of `work`, the even one of edge e's pair (an Edge_index made
  // from a halfedge keeps that halfedge: work.halfedge(work.edge(h)) is h itself).
  auto halfedge_of = [&](H h) {
    const std::size_t e = std::size_t(h) / 2;
    return std::size_t(h) % 2 == 0 ? base[e] : tm.opposite(base[e]);
  };
  for (H h : work.halfedges()) {
    const H th = halfedge_of(h);
    tm.set_target(th, vertex_of(work.target(h)));
    tm.set_face(th, work.face(h) == work.null_face() ? tm.null_face() : face_of_work[work.face(h)]);
    tm.set_next(th, halfedge_of(work.next(h)));
  }
  for (V w : work.vertices()) {
    const H h = work.halfedge(w);
    tm.set_halfedge(vertex_of(w), h == work.null_halfedge() ? tm.null_halfedge() : halfedge_of(h));
    put(vpm, vertex_of(w), point_as<P>(points[windex[w]]));
  }
  for (F f : work.faces()) {
    tm.set_halfedge(face_of_work[f], halfedge_of(work.halfedge(f)));
    out.face_of.push_back(face_of_work[f]);
  }
  // Every element removed above was taken back: the mesh has no garbage, as before (with none
  // removed, collect_garbage moves nothing; it only clears the flag).
  if (!had_garbage && tm.number_of_removed_vertices() == 0 && tm.number_of_removed_edges() == 0 &&
      tm.number_of_removed_faces() == 0)
    tm.collect_garbage();
  return out;
}

/// Any other mutable face graph: see the top of this file. `triangles` are the result's faces by
/// vertex index (to_mesh_data's order).
template <typename TriangleMesh, typename VPM>
Committed_elements<TriangleMesh> commit_face_graph(const std::vector<Point_3>& points,
                                                   const std::vector<std::array<std::size_t, 3>>& triangles,
                                                   TriangleMesh& tm, const VPM& vpm) {
  using GT = boost::graph_traits<TriangleMesh>;
  Committed_elements<TriangleMesh> out;
  out.vertex_of.assign(vertices(tm).begin(), vertices(tm).end());
  if (points.size() < out.vertex_of.size()) throw Invalid_input("fit: the result does not extend the template");
  const std::vector<typename GT::face_descriptor> old_faces(faces(tm).begin(), faces(tm).end());
  const std::vector<typename GT::edge_descriptor> old_edges(edges(tm).begin(), edges(tm).end());
  for (auto f : old_faces) remove_face(f, tm);
  for (auto e : old_edges) remove_edge(e, tm);
  for (auto v : out.vertex_of) set_halfedge(v, GT::null_halfedge(), tm);
  while (out.vertex_of.size() < points.size()) out.vertex_of.push_back(add_vertex(tm));
  using P = typename boost::property_traits<VPM>::value_type;
  for (std::size_t k = 0; k < points.size(); ++k) put(vpm, out.vertex_of[k], point_as<P>(points[k]));
  out.face_of.reserve(triangles.size());
  for (const auto& t : triangles) {
    const std::array<typename GT::vertex_descriptor, 3> corners{out.vertex_of[t[0]], out.vertex_of[t[1]],
                                                                out.vertex_of[t[2]]};
    out.face_of.push_back(CGAL::Euler::add_face(corners, tm));
    // The result was a valid mesh of the same type: this cannot happen, short of a bug.
    if (out.face_of.back() == GT::null_face())
      throw Algorithm_failure("fit", "a face of the result could not be added to the mesh");
  }
  return out;
}

/// Writes the result held by `work` (`result` = to_mesh_data(work, …)) into `tm` in place, the
/// points converted to the point type of `vpm`:
/// commit_surface_mesh for a CGAL::Surface_mesh, commit_face_graph otherwise.
template <typename TriangleMesh, typename VPM>
Committed_elements<TriangleMesh> commit_work(const Work_mesh& work, const Mesh_data& result, TriangleMesh& tm,
                                             const VPM& vpm) {
  if constexpr (Is_surface_mesh<TriangleMesh>::value)
    return commit_surface_mesh(work, result.points, tm, vpm);
  else
    return commit_face_graph(result.points, result.triangles, tm, vpm);
}

/// `np` with `value` added for `Tag` in front: get_parameter finds the first of a tag from the
/// front, so this hides a value `np` already has for it.
template <typename Tag, typename T, typename NamedParameters>
Named_parameters<T, Tag, NamedParameters> with_parameter(const T& value, const NamedParameters& np) {
  return Named_parameters<T, Tag, NamedParameters>(value, np);
}

/// A stage run on a copy of the caller's mesh, so that a stage that throws (a cancel from the
/// `progress` callback, Algorithm_failure, …) leaves the caller's mesh, its property maps and
/// their values exactly as they were: `work` is `tm` rebuilt from its points (read through
/// `vpm`) and triangles, vertex i and face f of `work` being the i-th vertex and f-th face of
/// `tm`; commit() then writes `work` into `tm` in place (commit_work: Surface_mesh property maps
/// and Polyhedron vertex handles kept). `work` is a Work_mesh whatever the type of `tm`.
template <typename TriangleMesh, typename VPM>
struct Stage_copy {
  TriangleMesh& tm;
  VPM vpm;
  Work_mesh work;
  /// The vertices of `tm` and of `work`, in the order of vertices(tm): template_vertex[i] is
  /// work_vertex[i].
  std::vector<typename boost::graph_traits<TriangleMesh>::vertex_descriptor> template_vertex;
  std::vector<Work_mesh::Vertex_index> work_vertex;

  Stage_copy(TriangleMesh& m, const VPM& p) : tm(m), vpm(p) {
    work_vertex = build_triangle_mesh(to_mesh_data(tm, CGAL::parameters::vertex_point_map(vpm)), work);
    template_vertex.assign(vertices(tm).begin(), vertices(tm).end());
  }

  /// The map of `work` (a dynamic vertex property) holding the values of the caller's vertex map
  /// `map` (all `fallback` when it is not given).
  template <typename Value, typename Map>
  auto vertex_map_from(const Map& map, const Value& fallback) {
    auto out = get(CGAL::dynamic_vertex_property_t<Value>(), work);
    for (std::size_t i = 0; i < work_vertex.size(); ++i) {
      if constexpr (std::is_same_v<Map, CGAL::internal_np::Param_not_found>)
        put(out, work_vertex[i], fallback);
      else
        put(out, work_vertex[i], Value(get(map, template_vertex[i])));
    }
    return out;
  }

  /// Writes `work` into `tm`; `result` is to_mesh_data(work, …).
  Committed_elements<TriangleMesh> commit(const Mesh_data& result) { return commit_work(work, result, tm, vpm); }
};

/// Runs `stage(work, work_np)` on a Stage_copy of `tm` and commits the result when it returns:
/// `work_np` is `np` with the copy's own vertex_point_map in front. For stages whose only
/// parameter keyed by the mesh's elements is the vertex_point_map (deform's).
template <typename TriangleMesh, typename NamedParameters, typename Stage>
auto run_on_copy(TriangleMesh& tm, const NamedParameters& np, const Stage& stage) {
  const auto vpm = vertex_point_map_of(tm, np);
  Stage_copy<TriangleMesh, std::decay_t<decltype(vpm)>> copy(tm, vpm);
  auto report = stage(copy.work, with_parameter<CGAL::internal_np::vertex_point_t>(
                                     get_property_map(CGAL::vertex_point, copy.work), np));
  copy.commit(to_mesh_data(copy.work));
  return report;
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_COMMIT_RESULT_H
