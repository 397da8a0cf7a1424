// Checks a polygon soup for what meshfit needs of a template (an oriented 2-manifold, possibly
// with boundary) and triangulates polygons. Every error names the face's line or byte offset.
#include <meshfit/coordinate_range.h>

#include "polygon_soup.h"

#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <boost/pending/disjoint_sets.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace meshfit {
namespace internal {

namespace {

std::string where_text(const Polygon_soup& soup, std::size_t where) {
  return soup.binary ? "byte " + std::to_string(where) : "line " + std::to_string(where);
}

// Triangulates a polygon of k > 3 corners, keeping its orientation. CGAL's hole filling chooses
// the triangulation minimising the worst dihedral angle and then the area, which handles
// non-convex and non-planar polygons where a fan would fold; a fan is the fallback when it finds
// none (a polygon with collinear corners).
void triangulate_polygon(const std::vector<Point_3>& points, const std::size_t* c, std::size_t k,
                         std::vector<std::array<std::size_t, 3>>& out) {
  std::vector<Point_3> ring;
  ring.reserve(k);
  for (std::size_t i = 0; i < k; ++i) ring.push_back(points[c[i]]);
  std::vector<CGAL::Triple<int, int, int>> tris;
  namespace PMP = CGAL::Polygon_mesh_processing;
  if (k <= 32) {
    PMP::triangulate_hole_polyline(ring, std::back_inserter(tris));
  } else {
    // The exhaustive search is cubic in k: large polygons get the planar constrained Delaunay
    // triangulation or the search restricted to Delaunay faces, never the cubic fallback.
    PMP::triangulate_hole_polyline(ring, std::back_inserter(tris),
                                   CGAL::parameters::use_2d_constrained_delaunay_triangulation(true)
                                       .do_not_use_cubic_algorithm(true));
  }

  bool ok = tris.size() == k - 2;
  bool reverse = false;
  for (const auto& t : tris) {
    const int idx[3] = {t.first, t.second, t.third};
    for (int j = 0; j < 3; ++j) {
      if (idx[j] < 0 || static_cast<std::size_t>(idx[j]) >= k) ok = false;
      // The polygon's edge (0, 1) fixes the orientation of the triangle containing it.
      if (ok && idx[j] == 0 && idx[(j + 2) % 3] == 1) reverse = true;
    }
  }
  if (!ok) {
    for (std::size_t i = 1; i + 1 < k; ++i) out.push_back({c[0], c[i], c[i + 1]});
    return;
  }
  for (const auto& t : tris) {
    if (reverse) out.push_back({c[t.first], c[t.third], c[t.second]});
    else out.push_back({c[t.first], c[t.second], c[t.third]});
  }
}

struct Half_edge {
  std::size_t lo, hi;  // sorted vertex pair
  std::size_t face;
  bool forward;        // the face goes lo -> hi
  bool operator<(const Half_edge& o) const {
    return std::tie(lo, hi, face) < std::tie(o.lo, o.hi, o.face);
  }
};

[[noreturn]] void fail_at_polygon(const Polygon_soup& soup, std::size_t p, const std::string& problem) {
  throw Invalid_input(soup.location(soup.polygon_where[p]), problem);
}

// Vertex numbers in messages as the file writes them.
std::string vertex_name(const Polygon_soup& soup, std::size_t v) {
  return std::to_string(soup.one_based ? v + 1 : v);
}

// The supported range (coordinate_range.h), once here for every format.
void check_points(const Polygon_soup& soup) {
  const std::size_t n = soup.points.size();
  const Input_location file{soup.file, 0, Input_location::no_offset};
  Bbox_3 box;
  for (std::size_t v = 0; v < n; ++v) {
    if (!in_coordinate_range(soup.points[v]))
      check_coordinate_range(soup.points[v], file, "vertex " + vertex_name(soup, v));
    box += soup.points[v].bbox();
  }
  if (n > 0)
    check_extent(box, file, "the mesh");
}

// Polygon p has 3 corners or more, each a vertex of the soup, none twice (`sorted`: room to work).
void check_polygon(const Polygon_soup& soup, std::size_t p, std::vector<std::size_t>& sorted) {
  const std::size_t n = soup.points.size();
  const std::size_t* c = soup.corners.data() + soup.start[p];
  const std::size_t k = soup.start[p + 1] - soup.start[p];
  if (k < 3)
    fail_at_polygon(soup, p, "face " + std::to_string(p) + " has " + std::to_string(k) +
                                 (k == 1 ? " vertex" : " vertices") + "; a face needs at least 3");
  for (std::size_t i = 0; i < k; ++i)
    if (c[i] >= n)
      fail_at_polygon(soup, p, "face " + std::to_string(p) + " refers to vertex " + vertex_name(soup, c[i]) +
                                   ", but there are only " + std::to_string(n) + " vertices");
  sorted.assign(c, c + k);
  std::sort(sorted.begin(), sorted.end());
  const auto dup = std::adjacent_find(sorted.begin(), sorted.end());
  if (dup != sorted.end())
    fail_at_polygon(soup, p, "vertex " + vertex_name(soup, *dup) + " appears more than once in face " +
                                 std::to_string(p));
}

// The mesh's triangles (and patches), polygon by polygon after checking each; `source`: the
// polygon of each triangle. Returns how many polygons were triangulated.
std::size_t add_triangles(const Polygon_soup& soup, Mesh_data& mesh, std::vector<std::size_t>& source) {
  std::size_t triangulated = 0;
  std::vector<std::size_t> sorted;
  for (std::size_t p = 0; p < soup.number_of_polygons(); ++p) {
    check_polygon(soup, p, sorted);
    const std::size_t* c = soup.corners.data() + soup.start[p];
    const std::size_t k = soup.start[p + 1] - soup.start[p];
    if (k == 3) {
      mesh.triangles.push_back({c[0], c[1], c[2]});
    } else {
      triangulate_polygon(mesh.points, c, k, mesh.triangles);
      ++triangulated;
    }
    source.resize(mesh.triangles.size(), p);
    if (!soup.polygon_patch.empty()) mesh.face_patch.resize(mesh.triangles.size(), soup.polygon_patch[p]);
  }
  return triangulated;
}

// Each triangle's three half-edges, sorted by their vertex pair (then face): counted into rows by
// the lower vertex, each row then sorted (a handful of half-edges), in linear time overall (one
// comparison sort of a million-face mesh's 3.9 million half-edges took 0.35 s).
std::vector<Half_edge> sorted_half_edges(const std::vector<std::array<std::size_t, 3>>& triangles, std::size_t vertices) {
  const std::size_t nt = triangles.size();
  std::vector<std::size_t> start(vertices + 1, 0);
  for (const auto& t : triangles)
    for (int j = 0; j < 3; ++j) ++start[std::min(t[j], t[(j + 1) % 3]) + 1];
  for (std::size_t v = 0; v < vertices; ++v) start[v + 1] += start[v];
  std::vector<Half_edge> hes(3 * nt);
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (std::size_t t = 0; t < nt; ++t)
    for (int j = 0; j < 3; ++j) {
      const std::size_t a = triangles[t][j], b = triangles[t][(j + 1) % 3];
      hes[fill[std::min(a, b)]++] = {std::min(a, b), std::max(a, b), t, a < b};
    }
  for (std::size_t v = 0; v < vertices; ++v)
    std::sort(hes.begin() + static_cast<std::ptrdiff_t>(start[v]), hes.begin() + static_cast<std::ptrdiff_t>(start[v + 1]));
  return hes;
}

// The half-edges hes[i .. j) of one edge: at most two, and two traverse it in opposite directions.
void check_edge(const Polygon_soup& soup, const std::vector<Half_edge>& hes, std::size_t i, std::size_t j,
                const std::vector<std::size_t>& source) {
  const std::string edge_name = "edge (" + std::to_string(hes[i].lo) + ", " + std::to_string(hes[i].hi) + ")";
  if (j - i > 2) {
    std::string faces;
    for (std::size_t k = i; k < j; ++k)
      faces += (k > i ? ", " : "") + std::string("face ") + std::to_string(source[hes[k].face]) + " (" +
               where_text(soup, soup.polygon_where[source[hes[k].face]]) + ")";
    fail_at_polygon(soup, source[hes[i + 2].face], edge_name + " is shared by " + std::to_string(j - i) +
                                                       " faces: " + faces + "; the mesh is not manifold");
  }
  if (j - i == 2 && hes[i].forward == hes[i + 1].forward) {
    const std::size_t p = source[hes[i].face], q = source[hes[i + 1].face];
    fail_at_polygon(soup, q, "face " + std::to_string(q) + " traverses " + edge_name +
                                 " in the same direction as face " + std::to_string(p) + " (" +
                                 where_text(soup, soup.polygon_where[p]) +
                                 "): the faces are not consistently oriented");
  }
}

// Edges: at most two faces each, and two faces traverse their common edge in opposite
// directions (that is what consistent orientation means).
void check_edges(const Polygon_soup& soup, const std::vector<Half_edge>& hes, const std::vector<std::size_t>& source) {
  for (std::size_t i = 0; i < hes.size();) {
    std::size_t j = i + 1;
    while (j < hes.size() && hes[j].lo == hes[i].lo && hes[j].hi == hes[i].hi) ++j;
    check_edge(soup, hes, i, j, source);
    i = j;
  }
}

// The faces around each vertex, in compressed rows: vertex v's are
// face[first[v] .. first[v + 1]], in increasing order.
struct Vertex_faces {
  std::vector<std::size_t> first, face;
  Vertex_faces(const std::vector<std::array<std::size_t, 3>>& triangles, std::size_t n) : first(n + 1, 0) {
    for (const auto& t : triangles)
      for (std::size_t v : t) ++first[v + 1];
    std::partial_sum(first.begin(), first.end(), first.begin());
    face.resize(3 * triangles.size());
    std::vector<std::size_t> fill(first.begin(), first.end() - 1);
    for (std::size_t t = 0; t < triangles.size(); ++t)
      for (std::size_t v : triangles[t]) face[fill[v]++] = t;
  }
};

// The faces around vertex v (m of them, m > 0) form one fan (else two surfaces touch at a point).
// `nbr`: room to work.
void check_fan(const Polygon_soup& soup, const std::vector<std::array<std::size_t, 3>>& triangles,
               const Vertex_faces& around, std::size_t v, const std::vector<std::size_t>& source,
               std::vector<std::pair<std::size_t, std::size_t>>& nbr) {
  const std::size_t m = around.first[v + 1] - around.first[v];
  nbr.clear();  // (other vertex, local corner)
  for (std::size_t i = 0; i < m; ++i) {
    const auto& t = triangles[around.face[around.first[v] + i]];
    for (std::size_t w : t)
      if (w != v) nbr.emplace_back(w, i);
  }
  std::sort(nbr.begin(), nbr.end());
  boost::disjoint_sets_with_storage<> fans(m);  // the faces around v, joined across shared edges
  std::size_t components = m;
  for (std::size_t i = 1; i < nbr.size(); ++i)
    if (nbr[i].first == nbr[i - 1].first && fans.find_set(nbr[i].second) != fans.find_set(nbr[i - 1].second)) {
      fans.union_set(nbr[i].second, nbr[i - 1].second);
      --components;
    }
  if (components > 1) {
    const std::size_t root0 = fans.find_set(std::size_t(0));
    std::size_t other = 1;
    while (fans.find_set(other) == root0) ++other;
    const std::size_t p = source[around.face[around.first[v]]], q = source[around.face[around.first[v] + other]];
    fail_at_polygon(soup, q, "face " + std::to_string(q) + " and face " + std::to_string(p) + " (" +
                                 where_text(soup, soup.polygon_where[p]) + ") meet only at vertex " +
                                 std::to_string(v) + ", whose faces form " + std::to_string(components) +
                                 " separate fans: the mesh is not manifold");
  }
}

// Vertices: the faces around each vertex form one fan; a vertex of no face is reported.
void check_vertices(const Polygon_soup& soup, const std::vector<std::array<std::size_t, 3>>& triangles,
                    const std::vector<std::size_t>& source, Mesh_read_report* report) {
  const Vertex_faces around(triangles, soup.points.size());
  std::vector<std::pair<std::size_t, std::size_t>> nbr;
  for (std::size_t v = 0; v < soup.points.size(); ++v) {
    if (around.first[v + 1] == around.first[v]) {
      if (report) report->isolated_vertices.push_back(v);
      continue;
    }
    check_fan(soup, triangles, around, v, source, nbr);
  }
}

// Curve edges must be edges of the mesh.
void add_curve_edges(const Polygon_soup& soup, const std::vector<Half_edge>& hes, Mesh_data& mesh) {
  const std::size_t n = soup.points.size();
  for (std::size_t e = 0; e < soup.edges.size(); ++e) {
    const auto& ce = soup.edges[e];
    const Input_location at = soup.location(soup.edge_where[e]);
    for (std::size_t v : ce)
      if (v >= n)
        throw Invalid_input(at, "curve edge refers to vertex " + vertex_name(soup, v) +
                                    ", but there are only " + std::to_string(n) + " vertices");
    if (ce[0] == ce[1]) throw Invalid_input(at, "curve edge joins vertex " + std::to_string(ce[0]) + " to itself");
    const Half_edge key{std::min(ce[0], ce[1]), std::max(ce[0], ce[1]), 0, true};
    const auto it = std::lower_bound(hes.begin(), hes.end(), key);
    if (it == hes.end() || it->lo != key.lo || it->hi != key.hi)
      throw Invalid_input(at, "curve edge (" + std::to_string(ce[0]) + ", " + std::to_string(ce[1]) +
                                  ") is not an edge of the mesh");
    mesh.curve_edges.push_back(ce);
  }
}

void fill_report(const Polygon_soup& soup, const Mesh_data& mesh, std::size_t triangulated, Mesh_read_report& report) {
  report.file = soup.file;
  report.polygons_read = soup.number_of_polygons();
  report.polygons_triangulated = triangulated;
  report.unflagged_edges_ignored = soup.ignored_edges;
  report.dropped_attributes = soup.dropped_attributes;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    if (CGAL::collinear(mesh.points[tri[0]], mesh.points[tri[1]], mesh.points[tri[2]]))
      report.degenerate_faces.push_back(t);
  }
}

}  // namespace

Mesh_data validate_polygon_soup(const Polygon_soup& soup, Mesh_read_report* report) {
  check_points(soup);
  Mesh_data mesh;
  mesh.points = soup.points;
  mesh.vertex_uvs = soup.vertex_uvs;
  mesh.vertex_normals = soup.vertex_normals;
  mesh.vertex_colors = soup.vertex_colors;
  std::vector<std::size_t> source;  // polygon of each triangle
  const std::size_t triangulated = add_triangles(soup, mesh, source);
  const std::vector<Half_edge> hes = sorted_half_edges(mesh.triangles, mesh.points.size());
  check_edges(soup, hes, source);
  check_vertices(soup, mesh.triangles, source, report);
  add_curve_edges(soup, hes, mesh);
  if (report) fill_report(soup, mesh, triangulated, *report);
  return mesh;
}

}  // namespace internal
}  // namespace meshfit
