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

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>
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

/// Key of a triangle up to rotation, by result vertex index: its lowest vertex first.
inline std::array<std::size_t, 3> triangle_key(std::array<std::size_t, 3> t) {
  while (t[0] > t[1] || t[0] > t[2]) t = {t[1], t[2], t[0]};
  return t;
}

/// Elements filed under the lowest of their vertex indices (keys a < rows, then b, c), found by
/// scanning that vertex's row: the template's edges and faces, looked up in time of a vertex's
/// degree (hash maps of a million-face template's elements took a second to fill). Of elements with
/// the same key, the first given is found.
template <typename Value>
class Lowest_vertex_rows {
 public:
  struct Keyed {
    std::size_t a, b, c;
    Value value;
  };
  Lowest_vertex_rows(std::size_t rows, const std::vector<Keyed>& keyed) : m_start(rows + 1, 0), m_entries(keyed.size()) {
    for (const Keyed& k : keyed) ++m_start[k.a + 1];
    for (std::size_t i = 0; i < rows; ++i) m_start[i + 1] += m_start[i];
    std::vector<std::size_t> fill(m_start.begin(), m_start.end() - 1);
    for (const Keyed& k : keyed) m_entries[fill[k.a]++] = k;
  }
  const Value* find(std::size_t a, std::size_t b, std::size_t c) const {
    for (std::size_t j = m_start[a]; j < m_start[a + 1]; ++j)
      if (m_entries[j].b == b && m_entries[j].c == c) return &m_entries[j].value;
    return nullptr;
  }

 private:
  std::vector<std::size_t> m_start;
  std::vector<Keyed> m_entries;
};

/// The steps of commit_surface_mesh, in the order it takes them: everything up to
/// take_elements() is computed before `tm` changes.
template <typename WorkPoint, typename Point>
class Surface_mesh_commit {
  using Work = CGAL::Surface_mesh<WorkPoint>;
  using Mesh = CGAL::Surface_mesh<Point>;
  using V = typename Mesh::Vertex_index;
  using H = typename Mesh::Halfedge_index;
  using E = typename Mesh::Edge_index;
  using F = typename Mesh::Face_index;
  static constexpr std::size_t none = SIZE_MAX;

 public:
  /// Numbers the vertices of `tm` and of `work` (template vertex i is result vertex i).
  /// \throws Invalid_input when the result (`number_of_points` points) does not extend the template.
  Surface_mesh_commit(const Work& work, Mesh& tm, std::size_t number_of_points)
      : m_work(work),
        m_tm(tm),
        m_template_vertex(tm.vertices().begin(), tm.vertices().end()),
        m_nt(m_template_vertex.size()),
        m_tindex(tm.num_vertices(), none),
        m_windex(work.num_vertices(), none),
        m_base(work.num_edges(), H()),
        m_edge_kept(tm.num_edges(), 0),
        m_face_kept(tm.num_faces(), 0),
        m_face_of_work(work.num_faces(), F()) {
    for (std::size_t i = 0; i < m_nt; ++i) m_tindex[m_template_vertex[i]] = i;
    for (auto w : work.vertices()) m_windex[w] = m_nw++;
    if (m_nw != number_of_points || m_nw < m_nt) throw Invalid_input("fit: the result does not extend the template");
  }

  /// Template edges by their vertices (lower, higher, 0).
  Lowest_vertex_rows<E> template_edges() const {
    std::vector<typename Lowest_vertex_rows<E>::Keyed> keyed;
    keyed.reserve(m_tm.number_of_edges());
    for (E e : m_tm.edges()) {
      const std::size_t s = m_tindex[m_tm.source(m_tm.halfedge(e))], t = m_tindex[m_tm.target(m_tm.halfedge(e))];
      keyed.push_back({std::min(s, t), std::max(s, t), 0, e});
    }
    return Lowest_vertex_rows<E>(m_nt, keyed);
  }

  /// Template faces by their vertices (triangle_key).
  Lowest_vertex_rows<F> template_faces() const {
    std::vector<typename Lowest_vertex_rows<F>::Keyed> keyed;
    keyed.reserve(m_tm.number_of_faces());
    for (F f : m_tm.faces()) {
      const H h = m_tm.halfedge(f);
      if (m_tm.next(m_tm.next(m_tm.next(h))) != h) continue;  // not a triangle: no result face matches it
      const auto k = triangle_key({m_tindex[m_tm.target(m_tm.prev(h))], m_tindex[m_tm.target(h)],
                                   m_tindex[m_tm.target(m_tm.next(h))]});
      keyed.push_back({k[0], k[1], k[2], f});
    }
    return Lowest_vertex_rows<F>(m_nt, keyed);
  }

  /// Each edge of `work` joining two template vertices that an edge of the template joins stands
  /// for that edge, its halfedge(e) for the template's halfedge in the same direction.
  void match_edges(const Lowest_vertex_rows<E>& template_edge) {
    for (auto e : m_work.edges()) {
      const auto h = m_work.halfedge(e);
      const std::size_t s = m_windex[m_work.source(h)], t = m_windex[m_work.target(h)];
      if (s >= m_nt || t >= m_nt) {
        m_unmatched_edges.push_back(e);
        continue;
      }
      const E* found = template_edge.find(std::min(s, t), std::max(s, t), 0);
      if (!found) {
        m_unmatched_edges.push_back(e);
        continue;
      }
      const H th = m_tm.halfedge(*found);
      m_base[e] = m_tindex[m_tm.target(th)] == t ? th : m_tm.opposite(th);
      m_edge_kept[*found] = 1;
    }
  }

  /// Each face of `work` with the same three template vertices as a face of the template, in the
  /// same order, stands for that face.
  void match_faces(const Lowest_vertex_rows<F>& template_face) {
    for (auto f : m_work.faces()) {
      const auto h = m_work.halfedge(f);
      const std::array<std::size_t, 3> c{m_windex[m_work.target(m_work.prev(h))], m_windex[m_work.target(h)],
                                         m_windex[m_work.target(m_work.next(h))]};
      const auto k = triangle_key(c);
      const F* found = c[0] < m_nt && c[1] < m_nt && c[2] < m_nt ? template_face.find(k[0], k[1], k[2]) : nullptr;
      if (!found) {
        m_unmatched_faces.push_back(f);
        continue;
      }
      m_face_of_work[f] = *found;
      m_face_kept[*found] = 1;
    }
  }

  /// The elements of `tm` for the result's unmatched edges and faces and its added vertices.
  void take_elements() {
    // The elements of the template that no result element matches go to the free lists; the
    // result's other edges and faces take them back (add_edge and add_face reset their property
    // values to the defaults) or are appended. Vertices are appended, never recycled: the
    // template's vertices come first in vertices(tm).
    const bool recycle = m_tm.does_recycle_garbage();
    m_had_garbage = m_tm.has_garbage();
    for (E e : std::vector<E>(m_tm.edges().begin(), m_tm.edges().end()))
      if (!m_edge_kept[e]) m_tm.remove_edge(e);
    for (F f : std::vector<F>(m_tm.faces().begin(), m_tm.faces().end()))
      if (!m_face_kept[f]) m_tm.remove_face(f);
    m_tm.set_recycle_garbage(true);
    for (E e : m_unmatched_edges) m_base[e] = m_tm.add_edge();
    for (F f : m_unmatched_faces) m_face_of_work[f] = m_tm.add_face();
    m_tm.set_recycle_garbage(false);
    m_out.vertex_of = m_template_vertex;
    m_out.vertex_of.reserve(m_nw);
    for (std::size_t k = m_nt; k < m_nw; ++k) m_out.vertex_of.push_back(m_tm.add_vertex());
    m_tm.set_recycle_garbage(recycle);
  }

  /// The connectivity of `work` written into those elements.
  void write_halfedges() {
    for (H h : m_work.halfedges()) {
      const H th = halfedge_of(h);
      m_tm.set_target(th, vertex_of(m_work.target(h)));
      m_tm.set_face(th, m_work.face(h) == m_work.null_face() ? m_tm.null_face() : m_face_of_work[m_work.face(h)]);
      m_tm.set_next(th, halfedge_of(m_work.next(h)));
    }
  }

  /// The vertices' halfedges, and `points[k]`, the position of the result's vertex k, written
  /// through `vpm`.
  template <typename VPM>
  void write_vertices(const std::vector<Point_3>& points, const VPM& vpm) {
    using P = typename boost::property_traits<VPM>::value_type;
    for (V w : m_work.vertices()) {
      const H h = m_work.halfedge(w);
      m_tm.set_halfedge(vertex_of(w), h == m_work.null_halfedge() ? m_tm.null_halfedge() : halfedge_of(h));
      put(vpm, vertex_of(w), point_as<P>(points[m_windex[w]]));
    }
  }

  /// The faces' halfedges.
  void write_faces() {
    for (F f : m_work.faces()) {
      m_tm.set_halfedge(m_face_of_work[f], halfedge_of(m_work.halfedge(f)));
      m_out.face_of.push_back(m_face_of_work[f]);
    }
  }

  /// The elements of `tm` holding the result.
  Committed_elements<Mesh> finish() {
    // Every element removed above was taken back: the mesh has no garbage, as before (with none
    // removed, collect_garbage moves nothing; it only clears the flag).
    if (!m_had_garbage && m_tm.number_of_removed_vertices() == 0 && m_tm.number_of_removed_edges() == 0 &&
        m_tm.number_of_removed_faces() == 0)
      m_tm.collect_garbage();
    return std::move(m_out);
  }

 private:
  V vertex_of(V w) const { return m_out.vertex_of[m_windex[w]]; }
  // m_base[e] stands for halfedge(e) of `work`, the even one of edge e's pair (an Edge_index made
  // from a halfedge keeps that halfedge: work.halfedge(work.edge(h)) is h itself).
  H halfedge_of(H h) const {
    const std::size_t e = std::size_t(h) / 2;
    return std::size_t(h) % 2 == 0 ? m_base[e] : m_tm.opposite(m_base[e]);
  }

  const Work& m_work;
  Mesh& m_tm;
  std::vector<V> m_template_vertex;
  std::size_t m_nt;
  std::vector<std::size_t> m_tindex, m_windex;
  std::size_t m_nw = 0;
  // The halfedge of `tm` standing for halfedge(e) of each edge e of `work` (null: not matched yet).
  std::vector<H> m_base;
  std::vector<char> m_edge_kept, m_face_kept;
  std::vector<F> m_face_of_work;
  std::vector<E> m_unmatched_edges;
  std::vector<F> m_unmatched_faces;
  bool m_had_garbage = false;
  Committed_elements<Mesh> m_out;
};

/// CGAL::Surface_mesh: see the top of this file. `points[k]` is the position of the result's
/// vertex k, written through `vpm`.
template <typename WorkPoint, typename Point, typename VPM>
Committed_elements<CGAL::Surface_mesh<Point>> commit_surface_mesh(const CGAL::Surface_mesh<WorkPoint>& work,
                                                                   const std::vector<Point_3>& points,
                                                                   CGAL::Surface_mesh<Point>& tm, const VPM& vpm) {
  if (std::max(tm.num_vertices(), work.num_vertices()) >= (std::size_t(1) << 32))
    throw Invalid_input("fit: too many vertices");
  Surface_mesh_commit<WorkPoint, Point> commit(work, tm, points.size());
  const auto template_edge = commit.template_edges();
  const auto template_face = commit.template_faces();
  commit.match_edges(template_edge);
  commit.match_faces(template_face);
  commit.take_elements();
  commit.write_halfedges();
  commit.write_vertices(points, vpm);
  commit.write_faces();
  return commit.finish();
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
