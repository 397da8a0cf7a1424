// The surface fine level (deform_fine_on_surface, Fine_level::surface) compiled once, for
// meshfit's own mesh: the curves are embedded in the coarse surface, where nothing is folded yet,
// and the embedded vertices are then moved onto the curves by a thin-plate displacement, with
// the faces that turn over untangled. Surface_fine_level holds the state its steps share; run()
// makes them in order.
#include <meshfit/internal/deform_impl.h>
#include <meshfit/internal/smallest_angle.h>
#include <meshfit/partition.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Dynamic_property_map.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <queue>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace meshfit {
namespace internal {
namespace {

class Surface_fine_level {
 public:
  Surface_fine_level(Work_mesh& tm, const Curve_network& network, const std::vector<Correspondence>& pairs,
                     const Deform_options& options, bool split_for_paths, std::optional<Work_face_tree> tree,
                     const std::vector<double>* template_bending)
      : split_for_paths(split_for_paths),
        template_bending(template_bending),
        tm(tm),
        network(network),
        pairs(pairs),
        options(options),
        vpm(get_property_map(CGAL::vertex_point, tm)),
        s(tm, vpm),
        nv(network.number_of_vertices()),
        fixed(get(CGAL::dynamic_vertex_property_t<bool>(), tm)),
        curve(get(CGAL::dynamic_edge_property_t<bool>(), tm)) {
    report.fine_level = Fine_level::surface;
    report.fine_shape = template_bending ? Fine_shape::template_bending : Fine_shape::approach;
    report.user_pairs = pairs.size();
    coarse_tree = std::move(tree);
  }

  Deformation_report run() {
    check_inputs();
    assign_pairs();
    project_network();
    place_border_vertices();
    place_inner_vertices();
    refuse_crossing_segments();
    find_border_arcs();
    embed_segments();
    collect_chains();
    split_edges_between_curves();
    set_targets();
    move_and_untangle();
    relax();
    flip_held_faces();
    flip_folded_diagonals();
    flip_slivers();
    free_trapped_vertices();
    finish();
    return report;
  }

 private:
  using GT = boost::graph_traits<Work_mesh>;
  using vertex_descriptor = GT::vertex_descriptor;
  using halfedge_descriptor = GT::halfedge_descriptor;
  using edge_descriptor = GT::edge_descriptor;
  using face_descriptor = GT::face_descriptor;
  using VPM = boost::property_map<Work_mesh, CGAL::vertex_point_t>::type;
  using Tree = Work_face_tree;
  static constexpr std::size_t unassigned = Closest_point_assignment::unassigned;

  // The pairs are valid, and a network that is not planar cannot be drawn on a genus-0 template
  // without crossings.
  void check_inputs() const;
  // mesh_of and reserved from the user's pairs.
  void assign_pairs();

  // 1. Network vertices onto the surface. Whatever distance lies between a network vertex's
  // surface point and its mesh vertex is a tangential motion in step 3, which can fold small
  // faces: the margin that keeps new vertices off edges and corners is small.
  static constexpr double placement_margin = 0.05;
  // surface_point and distance of every network vertex; a polyline all of whose points are far
  // from the surface is refused.
  void project_network();

  // Boundary: the vertices of curves that run along the template's border go onto the border (a
  // border edge is split, or a border vertex used), and a segment between two such vertices that
  // runs along the border becomes the border arc between them, rather than a chord cutting border
  // triangles off.
  // The nearest point to p on the border: border[k] at parameter u from its source (the border
  // must not be empty).
  Nearest_on_segments nearest_border_point(const Point_3& p) const;
  void place_border_vertices();
  // The other network vertices, into the faces nearest their surface points.
  void place_inner_vertices();
  // The point nearest q of the surface and the face holding it, found earlier as `hit`, in a mesh
  // only subdivided since (insert_near splits faces and edges and moves no vertex: the surface is
  // the same point set, the point the same, its face one of the faces cut from hit's): the nearest
  // of the faces within three vertex rings of hit's face, each projected onto as the face tree
  // does. Saves place_inner_vertices's later passes a tree of the whole mesh each.
  std::pair<Point_3, face_descriptor> nearest_in_subdivided(const std::pair<Point_3, face_descriptor>& hit,
                                                            const Point_3& q) const;
  // Curves that cross without a shared vertex cannot both be edge chains: two segments of
  // different polylines with no common end whose surface images cross in the view along the
  // surface normal there (exact orientations in that view) while the segments themselves nearly
  // meet in space.
  void refuse_crossing_segments() const;

  // 2. The network as projected, embedded in the surface.
  // Segments along the boundary: the border arc from one end to the other that passes no other
  // network vertex, when it is at most half as long again as the segment (a segment across the
  // surface between two boundary points is not along the boundary).
  void find_border_arcs();
  // The network as projected, but for the boundary segments, embedded by stage 2's insertion.
  // Two network vertices placed at one point (curves denser than the template's faces there)
  // would make a segment of zero length, which no network holds.
  void embed_segments();
  // The refusal of embed_segments when two network vertices were placed at one point or within
  // the network's merge tolerance of each other: it names the two nearest (polyline and point).
  [[noreturn]] void refuse_coincident_placements() const;
  // Each segment's chain: its boundary arc, or the chain stage 2 made of it. Where stage 2 could
  // not make one (its insertion refuses to fold the surface, and its fallback moves vertices onto
  // the chord, which may lie off the surface), the shortest edge path from one end to the other
  // that crosses no chain (through no chain vertex nor curve edge) is taken as it is: only its
  // topology matters here, since step 3 moves its vertices onto the segment anyway. When no such
  // path exists and split_for_paths is set, the edges joining two chain vertices are split and the
  // path sought again.
  void collect_chains();
  // Where two chains run side by side, or a chain turns round a triangle, a face has all its
  // corners on curves: nothing of it can move when the curves take their places, and it folds or
  // collapses onto a segment. An interior edge that joins two held vertices and is no curve edge
  // is split at its midpoint, so that every face keeps a free corner to be moved (step 4). When
  // such faces are a quarter of the mesh and the network has more than twice the template's
  // vertices, the curves leave the template no room between them: say so, rather than grow the
  // mesh and untangle what cannot be. (A template whose vertices all lie on the curves, a
  // tetrahedron onto its own edges say, needs no room.)
  void split_edges_between_curves();
  // The refusal above (also made before collect_chains splits edges to find a path).
  void refuse_crowded_curves() const;
  // Splits at its midpoint every interior edge that joins two chain vertices and is no curve edge;
  // the number split.
  std::size_t split_edges_joining_chains();
  // The shortest edge path between the ends of segment k that passes through no chain vertex nor
  // along a curve edge, kept near the chord; empty when the chains wall the ends off.
  std::vector<vertex_descriptor> shortest_free_path(std::size_t k) const;

  // 3. Targets: network vertices at their points, chain vertices on their segments.
  void set_targets();
  // The vertices step 3's thin-plate field moves. Once the approach has brought the surface to
  // the curves, the held vertices' motions are a fraction of an edge, and the field through them
  // matters only near them: the vertices more than a few rings from every held vertex (more for
  // a larger motion: vertices_within_reach) are held where they are, and the system shrinks to a band
  // along the curves, whose factorisation costs little (strips have small separators). When the
  // band would hold at least half the free vertices, every vertex is in it: the whole field
  // costs about as much then. Scale case bench/scale, 1 310 720 faces: 68 129 vertices solved
  // for, 587 088 held beyond the band, the step 16.3 s -> 1.0 s, Hausdorff distance to the truth 0.522 % ->
  // 0.476 %, smallest angle 7.44 -> 7.59 degrees; band_rings 1 to 8 and band_fade 3 to 20 gave
  // the same distance on the 327 680-face case (0.460 %).
  static constexpr std::size_t band_rings = 4;
  static constexpr double band_fade = 10;
  std::vector<bool> displacement_band() const;
  // template_bending for every vertex of the mesh now (the inserted ones from their neighbours).
  std::vector<double> bending_at_every_vertex() const;

  // 4. Untangling: move the free vertices around faces that turned over or fold (4a, 4b below).
  // Bad faces: those turned over against step 2's surface, and those beside an edge that folds
  // now and did not fold there. "Turned over" is judged against the coarse surface's vertex
  // normals (the sign of the face's orientation with the point a + N above its corner a, N the
  // sum of its corners' normals, an exact predicate), not in the face's own plane on step 2's
  // surface, which may stand on edge: a flip test there would call the repair of such a face a
  // flip.
  // Faces standing steeply on the reference (more than about 70 degrees from it) are relaxed as
  // well, though they count as neither flips nor folds: left alone, such a face (a sliver stage 2
  // leaves where a curve runs through a template vertex) ends up on either side of vertical.
  std::vector<face_descriptor> bad_faces();
  // The free vertices of the bad faces and those up to `rings` edges away from them.
  std::vector<bool> rings_around(const std::vector<face_descriptor>& bad, std::size_t rings) const;
  // The segments whose chains are nearest (in edges of the mesh) to any corner of `bad`.
  std::vector<std::size_t> segments_nearest(const std::vector<face_descriptor>& bad) const;
  // 4a. A foldover-free energy (untangle_faces) on the free vertices within a few rings of the bad
  // faces, the rings growing while faces stay bad; each face judged in the plane of the reference
  // normal it is judged against here, each vertex moving in the plane of its own. The border
  // stays where it is. A result is kept only when it leaves fewer bad faces.
  void untangle_around_bad();
  // When the whole motion leaves bad faces, it is made again in four equal parts, untangling
  // after each: a tangle is repaired while it is small, before the rest of the motion makes it
  // large (on the battery's ico2562-superellipsoid-latlong-dense10: exit 3 with one face turned
  // over in one step, clean in four).
  void move_and_untangle();
  // 4b. Relaxation pulls vertices towards their neighbours' mean, which also shrinks what it
  // relaxes: rings grow only a little, and the best state seen is kept.
  void relax();
  // Whether the face a b c is turned the way of its corners' reference normals.
  bool good(std::size_t a, std::size_t b, std::size_t c) const;
  // Whether the face of h folds with a neighbour across one of its edges.
  bool folds_with_neighbours(halfedge_descriptor h) const;
  // Flips the edge of h (u-v, faces u v x and v u y) to x-y when it is no curve edge nor on the
  // border, x-y is not an edge yet, both new faces are good and turn the same way and, with
  // `unfolded`, neither folds with a neighbour (else it is flipped back). True if flipped.
  bool flip_if_good(halfedge_descriptor h, bool unfolded);
  // A bad face all of whose corners are held (chain vertices of two curves and the network
  // vertex between them, say) cannot be relaxed; flipping one of its edges that is not a curve
  // edge can repair it when both new faces are good (the face and vertex counts are kept).
  // Each flip repairs a bad face, and each is followed by a scan of the whole mesh: at most four
  // flips per bad face, and 256 in all, keep this from running quadratically long (what is left
  // is reported in remaining_flips).
  void flip_held_faces();
  // A fold left between two good faces is often the diagonal of their quadrilateral taken the
  // wrong way (across a row of nearly collinear chain vertices): flip that edge when it is not a
  // curve edge and both new faces are good and fold with none of their neighbours.
  void flip_folded_diagonals();
  // Slivers: a face with an angle under 5 degrees (a curve vertex placed next to an edge) is
  // mended by flipping the edge that gives the pair of faces beside it a larger smallest angle, as
  // long as the flip is good (flip_if_good) and leaves no face with three held corners —
  // smoothing moves no held vertex and cannot. At most one flip per edge and pass, 3 passes.
  void flip_slivers();
  // A free corner of a face still turned over may have no place left that untangling finds: on
  // real-pig, a vertex of degree 4 between two chains that meet at a corner, all four neighbours
  // held, a degree from the chain before the motion. Each free corner of a face turned over is put
  // where its faces are all good (place_in_ring); failing that, edges out of it are flipped, each
  // leaving a good face of its old neighbours behind (the face and vertex counts are kept), until
  // what remains of its ring has such a place, down to a triangle. Kept when the faces of its disc
  // turn over or fold less (trouble) than before; else undone. Three passes.
  void free_trapped_vertices();
  // Puts v where the fewest of its faces are turned over, then where their smallest angle is
  // largest: its place, the mean of its neighbours (taken when it turns none over), or a point
  // between the mean and a neighbour or an edge of the ring. The number of its faces turned over.
  std::size_t place_in_ring(vertex_descriptor v);
  // The faces of `region` turned over, and those folding with a neighbour.
  std::size_t trouble(const std::vector<face_descriptor>& region) const;
  // The mesh takes the positions; every network vertex must be at its point.
  void finish();

  const bool split_for_paths;  // see fine_on_surface
  const std::vector<double>* template_bending;  // see fine_on_surface
  Work_mesh& tm;
  const Curve_network& network;
  const std::vector<Correspondence>& pairs;
  const Deform_options& options;
  const std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  VPM vpm;
  Deform_state<Work_mesh, VPM> s;
  Deformation_report report;
  const std::size_t nv;  // network vertices
  std::size_t template_vertices = 0;

  // Steps 1 and 2: where the network's vertices are on the mesh and how its segments run there.
  std::vector<std::size_t> mesh_of;  // network vertex -> mesh vertex
  std::vector<bool> reserved;        // mesh vertices taken by a network vertex
  std::vector<double> distance;      // network vertex -> its distance from the coarse surface
  std::vector<Point_3> surface_point;
  std::optional<Tree> coarse_tree;  // the caller's or built by project_network, rebuilt by place_inner_vertices after border splits
  std::vector<bool> on_border;  // network vertices placed on the template's border
  std::vector<halfedge_descriptor> border;
  std::vector<bool> is_network_vertex, on_chain;  // by mesh vertex
  Work_vertex_flags fixed;  // inner vertices of border arcs: stage 2 leaves them
  Work_edge_flags curve;    // chain edges
  std::vector<std::vector<vertex_descriptor>> arc, chain_of;  // by segment
  std::vector<Vector_3> reference_normal;  // by mesh vertex

  // Steps 3 and 4: the motion, by mesh vertex.
  std::size_t n = 0;
  std::vector<Point_3> before, goal, after;
  std::vector<bool> constrained;
  std::vector<Vector_3> given, displacement;
  Vertex_adjacency adjacency;
  std::vector<bool> folded_before;  // by edge
  std::size_t serious = 0;          // flips + folds of the last call of bad_faces
  // bad_faces' judgements, kept between calls: the positions judged, each face's corners and
  // verdict (0 good, 1 turned over, 2 steep), each edge's fold (by index).
  std::vector<Point_3> judged_at;
  std::vector<std::array<std::size_t, 3>> judged_corners;
  std::vector<unsigned char> face_verdict, edge_folded;
  std::vector<face_descriptor> flipped;
};

void Surface_fine_level::check_inputs() const {
  check_pairs(pairs, s.vertex.size(), num_faces(tm), network);
  // A network that is not planar cannot be drawn on a genus-0 template without crossings.
  if (genus_zero_border_cycles(tm)) {
    const std::vector<std::size_t> kuratowski = network.non_planar_segments();
    if (!kuratowski.empty())
      throw Algorithm_failure(
          "deform", "the curve network is not planar: " + name_polylines(network.polylines_of_segments(kuratowski)) +
                        " (in file order) form a subdivision of K5 or K3,3, which cannot be drawn on this genus-0 "
                        "template without two curves crossing; curves that cross must share a vertex (a point written "
                        "identically in both polylines), or the template needs a handle",
          {{"kuratowski_segments", static_cast<double>(kuratowski.size())}});
  }
}

void Surface_fine_level::assign_pairs() {
  mesh_of.assign(nv, unassigned);
  reserved.assign(s.vertex.size(), false);
  for (const Correspondence& c : pairs) {
    const bool other_vertex = mesh_of[c.network_vertex] != unassigned && mesh_of[c.network_vertex] != c.template_vertex;
    const bool other_point = reserved[c.template_vertex] && mesh_of[c.network_vertex] != c.template_vertex;
    if (other_vertex || other_point)
      throw Invalid_input(c.where, std::string("deform: this pair gives ") +
                                       (other_vertex ? "a network vertex a second template vertex"
                                                     : "a template vertex a second network vertex"));
    mesh_of[c.network_vertex] = c.template_vertex;
    reserved[c.template_vertex] = true;
  }
}

void Surface_fine_level::project_network() {
  report_progress(options.progress, "deform", "fine: placing the network vertices on the surface", 0, 4);
  template_vertices = s.vertex.size();
  distance.assign(nv, 0);
  if (!coarse_tree) {  // else the caller's, at the points now
    coarse_tree.emplace(faces(tm).first, faces(tm).second, tm, vpm);
    coarse_tree->accelerate_distance_queries();
  }
  surface_point = tracked_projections(tm, vpm, *coarse_tree, network, pairs, report.projections_off_nearest);
  // A polyline all of whose points are far from the surface cannot be embedded in it: say so
  // now, rather than after a long run.
  const double diag = bbox_diagonal(tm, vpm);
  for (std::size_t v = 0; v < nv; ++v) {
    distance[v] = std::sqrt(CGAL::squared_distance(coarse_tree->closest_point(network.point(v)), network.point(v)));
    report.largest_projection_distance = std::max(report.largest_projection_distance, distance[v]);
  }
  refuse_far_polylines(network, [&](std::size_t v) { return distance[v]; }, diag);
}

Nearest_on_segments Surface_fine_level::nearest_border_point(const Point_3& p) const {
  return nearest_on_segments(
      border.size(),
      [&](std::size_t k) { return std::pair(s.to_point(source(border[k], tm)), s.to_point(target(border[k], tm))); }, p);
}

void Surface_fine_level::place_border_vertices() {
  on_border.assign(nv, false);
  for (auto h : halfedges(tm))
    if (is_border(h, tm)) border.push_back(h);
  if (!border.empty()) {
    // Near the border: nearer to it than half a border edge more than to the surface. The
    // vertices of curves that run along the border (vertices_along_border) go onto it; a curve
    // that only ends there, or leaves the coarse surface across it, keeps its inner vertices inside.
    std::vector<bool> near(nv, false);
    std::vector<Point_3> shadow(nv);
    for (std::size_t v = 0; v < nv; ++v) {
      if (mesh_of[v] != unassigned) {
        near[v] = static_cast<bool>(is_border(s.vertex[mesh_of[v]], tm));
        shadow[v] = s.to_point(s.vertex[mesh_of[v]]);
        continue;
      }
      const Nearest_on_segments b = nearest_border_point(network.point(v));
      near[v] = std::sqrt(b.d2) <= distance[v] + 0.5 * b.length;
      const Point_3 a = s.to_point(source(border[b.k], tm)), c = s.to_point(target(border[b.k], tm));
      shadow[v] = a + b.u * (c - a);
    }
    on_border = vertices_along_border(network, near, shadow);
    for (std::size_t v = 0; v < nv; ++v)
      if (mesh_of[v] != unassigned) on_border[v] = near[v];
  }
  for (std::size_t v = 0; v < nv && !border.empty(); ++v) {
    if (mesh_of[v] != unassigned || !on_border[v]) continue;
    const Nearest_on_segments bp = nearest_border_point(network.point(v));
    const auto best = border[bp.k];
    const double best_u = bp.u;
    const vertex_descriptor near_end = best_u < 0.5 ? source(best, tm) : target(best, tm);
    const std::size_t e = get(s.index, near_end);
    if ((best_u < placement_margin || best_u > 1 - placement_margin) && !reserved[e]) {
      mesh_of[v] = e;
    } else {
      const double u = std::min(1 - placement_margin, std::max(placement_margin, best_u));
      const Point_3 a = s.to_point(source(best, tm)), b = s.to_point(target(best, tm));
      mesh_of[v] = s.split_edge_at(best, a + u * (b - a));
      reserved.resize(s.vertex.size(), false);
      const auto x = s.vertex[mesh_of[v]];
      for (auto h : CGAL::halfedges_around_target(halfedge(x, tm), tm)) {
        if (is_border(h, tm)) border.push_back(h);
        if (is_border(opposite(h, tm), tm)) border.push_back(opposite(h, tm));
      }
    }
    reserved[mesh_of[v]] = true;
  }
}

void Surface_fine_level::place_inner_vertices() {
  std::vector<std::size_t> waiting;
  for (std::size_t v = 0; v < nv; ++v)
    if (mesh_of[v] == unassigned) waiting.push_back(v);
  // The coarse surface's tree serves the first pass when no border vertex split an edge since
  // (the faces are those it was built on); later passes look near the first pass's hits.
  if (!waiting.empty() && s.vertex.size() != template_vertices) {
    coarse_tree.emplace(faces(tm).first, faces(tm).second, tm, vpm);
    coarse_tree->accelerate_distance_queries();
  }
  std::vector<std::pair<Point_3, face_descriptor>> first_hit(nv);
  for (std::size_t pass = 0; !waiting.empty(); ++pass) {
    // One network vertex per face and pass, in the order of the network vertices (not of the
    // face handles, which on a Polyhedron_3 are addresses): the result does not depend on memory.
    std::set<face_descriptor> taken;
    std::vector<std::pair<std::size_t, std::pair<face_descriptor, Point_3>>> at;
    std::vector<std::size_t> later;
    for (std::size_t v : waiting) {
      if (pass == 0) {
        const auto h = coarse_tree->closest_point_and_primitive(surface_point[v]);
        first_hit[v] = {Point_3(h.first.x(), h.first.y(), h.first.z()), h.second};
      }
      const auto hit = pass == 0 ? first_hit[v] : nearest_in_subdivided(first_hit[v], surface_point[v]);
      if (taken.insert(hit.second).second)
        at.push_back({v, {hit.second, hit.first}});
      else
        later.push_back(v);
    }
    for (const auto& [v, fp] : at) {
      const std::size_t t = s.insert_near(fp.first, fp.second, reserved, placement_margin, false, !on_border[v]);
      reserved.resize(s.vertex.size(), false);
      reserved[t] = true;
      mesh_of[v] = t;
    }
    waiting.swap(later);
  }
  coarse_tree.reset();
  report.vertices_inserted_for_density = s.vertex.size() - template_vertices;
  report.faces_subdivided = s.faces_split;
}

std::pair<Point_3, Surface_fine_level::face_descriptor> Surface_fine_level::nearest_in_subdivided(
    const std::pair<Point_3, face_descriptor>& hit, const Point_3& q) const {
  std::vector<face_descriptor> near{hit.second};
  std::set<face_descriptor> seen{hit.second};
  for (std::size_t ring = 0, from = 0; ring < 3; ++ring) {
    const std::size_t to = near.size();
    for (std::size_t k = from; k < to; ++k)
      for (auto v : CGAL::vertices_around_face(halfedge(near[k], tm), tm))
        for (auto g : CGAL::faces_around_target(halfedge(v, tm), tm))
          if (g != GT::null_face() && seen.insert(g).second) near.push_back(g);
    from = to;
  }
  const Kernel k;
  std::optional<std::pair<Point_3, face_descriptor>> best;
  for (auto g : near) {
    const auto h = halfedge(g, tm);  // the corners in the order of the tree's triangles
    const Kernel::Triangle_3 t(s.to_point(target(h, tm)), s.to_point(target(next(h, tm), tm)), s.to_point(source(h, tm)));
    const Point_3 p = k.construct_projected_point_3_object()(t, q);
    if (!best || k.compare_distance_3_object()(q, p, best->first) == CGAL::SMALLER) best = {p, g};
  }
  return *best;
}

void Surface_fine_level::refuse_crossing_segments() const {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;
  const auto& segs = network.segments();
  std::vector<Box> boxes;
  for (std::size_t k = 0; k < segs.size(); ++k)
    boxes.emplace_back(s.to_point(s.vertex[mesh_of[segs[k][0]]]).bbox() + s.to_point(s.vertex[mesh_of[segs[k][1]]]).bbox(), k);
  // The polyline of each segment: two segments of one polyline are not compared (a plane
  // section of a thin part passes close to itself, and its projection may cross there).
  std::vector<std::size_t> polyline_of(segs.size(), SIZE_MAX);
  {
    std::map<std::pair<std::size_t, std::size_t>, std::size_t> index;
    for (std::size_t k = 0; k < segs.size(); ++k) index[std::minmax(segs[k][0], segs[k][1])] = k;
    for (std::size_t l = 0; l < network.polylines().size(); ++l) {
      const auto& pl = network.polylines()[l];
      for (std::size_t i = 0; i + 1 < pl.size(); ++i) {
        const auto it = index.find(std::minmax(pl[i], pl[i + 1]));
        if (it != index.end() && polyline_of[it->second] == SIZE_MAX) polyline_of[it->second] = l;
      }
    }
  }
  std::vector<std::pair<std::size_t, std::size_t>> crossing;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& x, const Box& y) {
    const auto& p = segs[x.info()];
    const auto& q = segs[y.info()];
    if (p[0] == q[0] || p[0] == q[1] || p[1] == q[0] || p[1] == q[1]) return;
    if (polyline_of[x.info()] == polyline_of[y.info()]) return;
    const Point_3 a = s.to_point(s.vertex[mesh_of[p[0]]]), b = s.to_point(s.vertex[mesh_of[p[1]]]),
                  c = s.to_point(s.vertex[mesh_of[q[0]]]), d = s.to_point(s.vertex[mesh_of[q[1]]]);
    const Segment_3 sp(network.point(p[0]), network.point(p[1])), sq(network.point(q[0]), network.point(q[1]));
    // Near in space (a hundredth of the longer segment): curves that pass each other at a distance
    // are not refused on the strength of their projections alone.
    const double reach = 0.01 * std::sqrt(std::max(sp.squared_length(), sq.squared_length()));
    const double gap = CGAL::squared_distance(sp, sq);
    if (!(gap < reach * reach)) return;
    // Nearest at an end of one of them: a segment that stops just short of the other curve (the
    // one before a crossing vertex inserted next to a sample point) passes it, it does not cross.
    const double end_gap = std::min({CGAL::squared_distance(sp.source(), sq), CGAL::squared_distance(sp.target(), sq),
                                     CGAL::squared_distance(sq.source(), sp), CGAL::squared_distance(sq.target(), sp)});
    if (!(end_gap > 4 * gap)) return;
    const Vector_3 N = s.normal(mesh_of[p[0]]) + s.normal(mesh_of[p[1]]) + s.normal(mesh_of[q[0]]) + s.normal(mesh_of[q[1]]);
    if (N == CGAL::NULL_VECTOR) return;
    const Vector_3 u = CGAL::cross_product(N, std::abs(N.x()) < std::abs(N.y()) ? Vector_3(1, 0, 0) : Vector_3(0, 1, 0));
    const Triangle_points view{a, a + u, a + CGAL::cross_product(N, u)};
    const auto side = [&](const Point_3& e, const Point_3& f, const Point_3& g) { return orientation_in_plane(view, e, f, g); };
    const CGAL::Sign c1 = side(a, b, c), c2 = side(a, b, d), c3 = side(c, d, a), c4 = side(c, d, b);
    if (c1 != CGAL::ZERO && c2 != CGAL::ZERO && c3 != CGAL::ZERO && c4 != CGAL::ZERO && c1 != c2 && c3 != c4)
      crossing.emplace_back(std::min(x.info(), y.info()), std::max(x.info(), y.info()));
  });
  if (!crossing.empty()) {
    std::sort(crossing.begin(), crossing.end());
    const auto [p, q] = crossing.front();
    const Point_3 m = CGAL::midpoint(network.point(segs[p][0]), network.point(segs[p][1]));
    std::ostringstream os;
    os.precision(6);
    os << crossing.size() << " pair" << (crossing.size() == 1 ? "" : "s")
       << " of segments cross without a shared vertex; the first: "
       << name_polylines(network.polylines_of_segments({p, q})) << " (in file order) cross near (" << m
       << "): curves that cross must share a vertex there (the same point written in both polylines)";
    throw Algorithm_failure("deform", os.str(), {{"crossing_segment_pairs", static_cast<double>(crossing.size())}});
  }
}

void Surface_fine_level::find_border_arcs() {
  report_progress(options.progress, "deform", "fine: embedding the curves in the coarse surface", 1, 4);
  is_network_vertex.assign(s.vertex.size(), false);
  for (std::size_t t : mesh_of) is_network_vertex[t] = true;
  for (auto v : vertices(tm)) put(fixed, v, false);
  arc.assign(network.segments().size(), {});
  for (std::size_t k = 0; k < network.segments().size(); ++k) {
    const auto [a, b] = network.segments()[k];
    if (!on_border[a] || !on_border[b]) continue;
    const auto A = s.vertex[mesh_of[a]], B = s.vertex[mesh_of[b]];
    const double chord = std::sqrt(CGAL::squared_distance(s.to_point(A), s.to_point(B)));
    for (auto h0 : CGAL::halfedges_around_source(A, tm)) {
      // Border halfedges leaving A, and those entering it walked backwards.
      for (int direction = 0; direction < 2; ++direction) {
        const auto start = direction == 0 ? h0 : opposite(h0, tm);
        if (!is_border(start, tm)) continue;
        std::vector<vertex_descriptor> path{A};
        double length = 0;
        auto h = start;
        for (std::size_t guard = 0; guard < border.size() + 2; ++guard) {
          const auto u = direction == 0 ? target(h, tm) : source(h, tm);
          length += std::sqrt(CGAL::squared_distance(s.to_point(path.back()), s.to_point(u)));
          path.push_back(u);
          if (u == B || is_network_vertex[get(s.index, u)] || length > 1.5 * chord) break;
          h = direction == 0 ? next(h, tm) : prev(h, tm);
        }
        if (path.back() == B && length <= 1.5 * chord && (arc[k].empty() || path.size() < arc[k].size()))
          arc[k] = path;
      }
    }
    for (std::size_t i = 1; i + 1 < arc[k].size(); ++i) put(fixed, arc[k][i], true);
  }
}

void Surface_fine_level::embed_segments() {
  // Normals of the coarse surface (its faces only split so far, no shape changed): what "turned
  // over" is judged against in step 4. Stage 2's insertion may leave faces standing on edge where
  // a curve runs through a template vertex; their own normals would not be a reference.
  // (Each vertex's normal alone, read-only: in parallel; 0.5 s of one core at 1.3M faces.)
  reference_normal.resize(s.vertex.size());
  const std::ptrdiff_t vertices = static_cast<std::ptrdiff_t>(s.vertex.size());
#pragma omp parallel for schedule(static) if (vertices >= 50000)
  for (std::ptrdiff_t i = 0; i < vertices; ++i) reference_normal[std::size_t(i)] = s.normal(std::size_t(i));

  // The network as projected, but for the boundary segments, embedded by stage 2's insertion.
  // Two network vertices placed at one point (curves denser than the template's faces there)
  // would make a segment of zero length, which no network holds.
  std::vector<Curve_network::Polyline> lines;
  for (std::size_t k = 0; k < network.segments().size(); ++k)
    if (arc[k].empty()) {
      lines.push_back({s.to_point(s.vertex[mesh_of[network.segments()[k][0]]]),
                       s.to_point(s.vertex[mesh_of[network.segments()[k][1]]])});
      if (lines.back()[0] == lines.back()[1]) refuse_coincident_placements();
    }
  for (auto e : edges(tm)) put(curve, e, false);
  if (!lines.empty()) {
    // One polyline per segment, numbered by the code, not the user's file: the network's own
    // refusals (two points merged within its tolerance) say that the curves are too dense here.
    const Curve_network projected = [&] {
      try {
        return Curve_network(lines);
      } catch (const Invalid_input&) {
        refuse_coincident_placements();
      }
    }();
    std::vector<bool> used(nv, false);
    for (std::size_t k = 0; k < network.segments().size(); ++k)
      if (arc[k].empty()) used[network.segments()[k][0]] = used[network.segments()[k][1]] = true;
    if (projected.number_of_vertices() != static_cast<std::size_t>(std::count(used.begin(), used.end(), true)))
      refuse_coincident_placements();
    try {
      // Stage 2's progress during the embedding is reported as this stage's.
      const Progress_callback forward = [this](const Progress_step& step) {
        return options.progress(Progress_step{"deform", "fine: embedding the curves: " + step.step, 1, 4});
      };
      report.embedding = partition_work(tm, projected, forward, curve, &fixed, nullptr);
    } catch (const Invalid_input& e) {
      // Stage 2 finds network vertices by position: two of them placed nearer to each other than
      // to any other mesh vertex cannot be told apart.
      throw Algorithm_failure("deform", std::string("the curves are denser than the template can hold (") + e.what() +
                                            "): use a finer template, or sparser curves");
    }
  }
}

void Surface_fine_level::refuse_coincident_placements() const {
  // The nearest two placed network vertices: a sweep over the placements in order along the
  // longest side of their box (a network on the surface spreads along it).
  const auto at = [&](std::size_t v) { return s.to_point(s.vertex[mesh_of[v]]); };
  Bbox_3 box;
  for (std::size_t v = 0; v < nv; ++v) box += at(v).bbox();
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (box.max(k) - box.min(k) > box.max(axis) - box.min(axis)) axis = k;
  std::vector<std::size_t> order(nv);
  for (std::size_t v = 0; v < nv; ++v) order[v] = v;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return at(a)[axis] < at(b)[axis] || (at(a)[axis] == at(b)[axis] && a < b);
  });
  double best = std::numeric_limits<double>::infinity();
  std::size_t a = 0, b = 0;
  for (std::size_t i = 0; i < nv; ++i)
    for (std::size_t j = i + 1; j < nv && at(order[j])[axis] - at(order[i])[axis] < best; ++j) {
      const double d = std::sqrt(CGAL::squared_distance(at(order[i]), at(order[j])));
      if (d < best) best = d, a = std::min(order[i], order[j]), b = std::max(order[i], order[j]);
    }
  // Where each of the two is in the user's file: its first polyline and point there.
  const auto where = [&](std::size_t v) {
    for (std::size_t k = 0; k < network.polylines().size(); ++k) {
      const auto& pl = network.polylines()[k];
      const auto it = std::find(pl.begin(), pl.end(), v);
      if (it != pl.end()) return std::pair<std::size_t, std::size_t>(k, std::size_t(it - pl.begin()) + 1);
    }
    return std::pair<std::size_t, std::size_t>(0, 0);  // (every network vertex is on a polyline)
  };
  const auto [ka, ia] = where(a);
  const auto [kb, ib] = where(b);
  const std::string named =
      ka == kb ? name_polylines({ka}) + " (in file order), points " + std::to_string(std::min(ia, ib)) + " and " +
                     std::to_string(std::max(ia, ib))
               : name_polylines({ka}) + ", point " + std::to_string(ia) + ", and " + name_polylines({kb}) +
                     ", point " + std::to_string(ib) + " (in file order),";
  const double size = bbox_diagonal(tm, vpm);
  throw Algorithm_failure(
      "deform",
      "network vertices land on the surface where others do: " + named + " are placed " +
          (best > 0 ? format_number(best / size) + " times the template's size apart" : std::string("at one point")) +
          " on it (their nearest points on the surface after the coarse level coincide): the curves there are "
          "denser than the template can hold, or run across the surface rather than along it; refine the "
          "template there, or move or remove one of those points",
      {{"network_vertex_a", static_cast<double>(a + 1)},
       {"network_vertex_b", static_cast<double>(b + 1)},
       {"distance_over_template_size", best / size}});
}

void Surface_fine_level::collect_chains() {
  // Chain vertices lie on their (projected) segments within rounding: the default merge
  // tolerance of the mesh's size.
  const double chain_tolerance = default_merge_tolerance * bbox_diagonal(tm, vpm);

  // Each segment's chain: its boundary arc, or the chain stage 2 made of it. Where stage 2 could
  // not make one (its insertion refuses to fold the surface, and its fallback moves vertices onto
  // the chord, which may lie off the surface), the shortest edge path from one end to the other
  // that crosses no chain (through no chain vertex nor curve edge) is taken as it is: only its
  // topology matters here, since step 3 moves its vertices onto the segment anyway.
  const auto& segments = network.segments();
  chain_of.assign(segments.size(), {});
  on_chain = is_network_vertex;
  on_chain.resize(s.vertex.size(), false);
  std::vector<std::size_t> missing;
  for (std::size_t k = 0; k < segments.size(); ++k) {
    chain_of[k] = !arc[k].empty() ? arc[k]
                                  : segment_edge_chain(tm, vpm, curve, s.vertex[mesh_of[segments[k][0]]],
                                                       s.vertex[mesh_of[segments[k][1]]], chain_tolerance);
    // A chain through another network vertex (three of them in a line on the projected surface)
    // would give that vertex two places: such a segment takes the shortest path instead.
    for (std::size_t i = 1; i + 1 < chain_of[k].size(); ++i)
      if (is_network_vertex[get(s.index, chain_of[k][i])]) {
        chain_of[k].clear();
        break;
      }
    if (chain_of[k].size() < 2) missing.push_back(k);
    for (std::size_t i = 0; i + 1 < chain_of[k].size(); ++i) {
      put(curve, edge(halfedge(chain_of[k][i], chain_of[k][i + 1], tm).first, tm), true);
      on_chain[get(s.index, chain_of[k][i])] = true;
    }
  }
  bool refusal_checked = false;
  for (std::size_t k : missing) {
    std::vector<vertex_descriptor> path = shortest_free_path(k);
    // The ends may be walled off by faces with no free corner (two chains, or a chain and a
    // network vertex, joined by an edge): split such edges, as split_edges_between_curves does
    // later, and try again (on real-pig, a crossing whose third segment had no way out).
    if (path.empty() && split_for_paths) {
      if (!refusal_checked) refuse_crowded_curves();  // before a split hides the crowding
      refusal_checked = true;
      const std::size_t split = split_edges_joining_chains();
      report.edges_split_between_curves += split;
      if (split > 0) path = shortest_free_path(k);
    }
    if (path.empty()) continue;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      put(curve, edge(halfedge(path[i], path[i + 1], tm).first, tm), true);
      on_chain[get(s.index, path[i])] = true;
    }
    arc[k] = path;  // placed by arc length below, as boundary arcs are
    chain_of[k] = std::move(path);
    ++report.segments_by_shortest_path;
  }
}

std::vector<Surface_fine_level::vertex_descriptor> Surface_fine_level::shortest_free_path(std::size_t k) const {
  const auto& segments = network.segments();
  const auto A = s.vertex[mesh_of[segments[k][0]]], B = s.vertex[mesh_of[segments[k][1]]];
  const Segment_3 chord(s.to_point(A), s.to_point(B));
  std::vector<double> dist(s.vertex.size(), std::numeric_limits<double>::infinity());
  std::vector<std::size_t> from(s.vertex.size(), unassigned);
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  const std::size_t ia = get(s.index, A), ib = get(s.index, B);
  dist[ia] = 0;
  queue.emplace(0.0, ia);
  while (!queue.empty()) {
    const auto [du, u] = queue.top();
    queue.pop();
    if (du > dist[u]) continue;
    if (u == ib) break;
    if (u != ia && on_chain[u]) continue;
    for (auto h : CGAL::halfedges_around_target(halfedge(s.vertex[u], tm), tm)) {
      if (get(curve, edge(h, tm))) continue;
      const std::size_t w = get(s.index, source(h, tm));
      if (w != ib && on_chain[w]) continue;
      const Point_3 pw = s.to_point(s.vertex[w]);
      const double dw = du + std::sqrt(CGAL::squared_distance(s.to_point(s.vertex[u]), pw)) +
                        2 * std::sqrt(CGAL::squared_distance(chord, pw));
      if (dw < dist[w]) dist[w] = dw, from[w] = u, queue.emplace(dw, w);
    }
  }
  std::vector<vertex_descriptor> path;
  if (from[ib] == unassigned) return path;
  for (std::size_t u = ib; u != unassigned; u = from[u]) path.push_back(s.vertex[u]);
  std::reverse(path.begin(), path.end());
  return path;
}

void Surface_fine_level::split_edges_between_curves() {
  refuse_crowded_curves();
  report.edges_split_between_curves += split_edges_joining_chains();
}

void Surface_fine_level::refuse_crowded_curves() const {
  std::size_t all_held = 0, total = 0;
  for (auto f : faces(tm)) {
    const auto c = s.corners(f);
    ++total;
    if (on_chain[c[0]] && on_chain[c[1]] && on_chain[c[2]]) ++all_held;
  }
  if (4 * all_held > total && nv > 2 * template_vertices)
    throw Algorithm_failure("deform", "the curves are denser than the template can hold: " + std::to_string(all_held) +
                                          " of the " + std::to_string(total) +
                                          " faces of the embedding have all their corners on curves (" +
                                          std::to_string(nv) + " network vertices on a template of " +
                                          std::to_string(template_vertices) +
                                          "): use a finer template (subdivide it), or sparser curves",
                            {{"faces_held_by_curves", static_cast<double>(all_held)},
                             {"faces", static_cast<double>(total)},
                             {"network_vertices", static_cast<double>(nv)},
                             {"template_vertices", static_cast<double>(template_vertices)}});
}

std::size_t Surface_fine_level::split_edges_joining_chains() {
  std::vector<halfedge_descriptor> joining;
  for (auto e : edges(tm)) {
    const auto h = halfedge(e, tm);
    if (get(curve, e) || is_border(h, tm) || is_border(opposite(h, tm), tm)) continue;
    if (on_chain[get(s.index, source(h, tm))] && on_chain[get(s.index, target(h, tm))]) joining.push_back(h);
  }
  for (auto h : joining) {
    const std::size_t a = get(s.index, source(h, tm)), b = get(s.index, target(h, tm));
    s.split_edge_at(h, CGAL::midpoint(s.to_point(source(h, tm)), s.to_point(target(h, tm))));
    reference_normal.push_back(reference_normal[a] + reference_normal[b]);
    on_chain.push_back(false);
    is_network_vertex.push_back(false);
  }
  return joining.size();
}

void Surface_fine_level::set_targets() {
  report_progress(options.progress, "deform", "fine: moving the curves into place (thin-plate displacement)", 2, 4);
  before = s.positions();
  n = before.size();
  constrained.assign(n, false);
  goal.resize(n);
  const auto& segments = network.segments();
  for (std::size_t v = 0; v < nv; ++v) {
    constrained[mesh_of[v]] = true;
    goal[mesh_of[v]] = network.point(v);
  }
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const auto [a, b] = segments[k];
    const auto A = s.vertex[mesh_of[a]], B = s.vertex[mesh_of[b]];
    const auto& chain = chain_of[k];
    if (chain.size() < 2) {
      report.segments_not_embedded.push_back(k);
      continue;
    }
    ++report.segments_embedded;
    // Where each inner vertex goes along the segment: its parameter along the projected segment,
    // or by arc length along a boundary arc or a shortest path.
    const Point_3 pa = s.to_point(A);
    const Vector_3 d = s.to_point(B) - pa;
    // (A path's projections onto the segment are used when they advance strictly inside it.)
    std::vector<double> along{0}, arc_length{0};
    for (std::size_t i = 1; i < chain.size(); ++i) {
      along.push_back(i + 1 < chain.size() ? ((s.to_point(chain[i]) - pa) * d) / d.squared_length() : 1.0);
      arc_length.push_back(arc_length.back() + std::sqrt(CGAL::squared_distance(s.to_point(chain[i - 1]), s.to_point(chain[i]))));
    }
    for (double& t : arc_length) t /= arc_length.back();
    const bool advancing = std::is_sorted(along.begin(), along.end(), std::less_equal<double>());
    // A fifth of each parameter is even spacing: two inner vertices that project onto nearly the
    // same point of the segment would make a needle that no held vertex lets smoothing undo.
    const double m = static_cast<double>(chain.size() - 1);
    for (std::size_t i = 1; i + 1 < chain.size(); ++i) {
      const std::size_t c = get(s.index, chain[i]);
      const double t = 0.8 * (arc[k].empty() || advancing ? along[i] : arc_length[i]) + 0.2 * (static_cast<double>(i) / m);
      constrained[c] = true;
      goal[c] = network.point(a) + t * (network.point(b) - network.point(a));
    }
  }
  adjacency = s.adjacency();
  given.assign(n, Vector_3(0, 0, 0));
  for (std::size_t i = 0; i < n; ++i)
    if (constrained[i]) given[i] = goal[i] - before[i];
  const std::vector<bool> band = displacement_band();
  std::vector<bool> held = constrained;
  for (std::size_t i = 0; i < n; ++i)
    if (!band[i]) held[i] = true;
  const auto beyond_band = static_cast<std::size_t>(std::count(band.begin(), band.end(), false));
  if (template_bending && beyond_band == 0) {
    // Between the curves the surface takes the template's bending, measured in the metric of the
    // surface now (Laplacian editing: the cotangent Laplacian at `before`, the target Laplacian
    // bent_laplacian of template_bending), rather than keeping the shape the approach left there,
    // whose thin-plate fields ran on the template's parametrisation and bent a plane template
    // where the plane is not. bench/battery, Hausdorff distance to the truth in % of the diagonal,
    // before -> after: open-plane-wave-boundary 1.39 -> 1.21, ico10242-peanut-latlong 1.02 ->
    // 0.69, ico2562-bumpy-latlong 0.50 -> 0.31, ico2562-bumpy-great 3.80 -> 3.16. (The coarse
    // surface's own bending instead: the peanut 1.67, the plane template 1.22.) When the band
    // holds vertices, the field keeps the shape beyond it and is the plain one.
    std::vector<std::array<std::size_t, 3>> triangles;
    triangles.reserve(tm.num_faces());
    for (auto f : faces(tm)) triangles.push_back(s.corners(f));
    Vertex_adjacency weighted = adjacency;
    set_cotangent_weights(weighted, before, triangles);
    const std::vector<double> bending = bending_at_every_vertex();
    const std::vector<Vector_3> delta = bent_laplacian(bending, before, triangles), now = laplacian_of(weighted, before);
    std::vector<Vector_3> target(n);
    for (std::size_t i = 0; i < n; ++i) target[i] = delta[i] - now[i];
    displacement = interpolate_displacements(weighted, held, given, 2, &report.displacement, &target);
  } else {
    displacement = interpolate_displacements(adjacency, held, given, 2, &report.displacement);
    report.fine_shape = Fine_shape::approach;  // the template's bending was not used (none, or a band)
  }
  report.displacement.held_beyond_band = beyond_band;
  report.displacement.constrained_vertices -= report.displacement.held_beyond_band;
  after = before;
  report.fine_pairs = static_cast<std::size_t>(std::count(constrained.begin(), constrained.end(), true));
}

std::vector<double> Surface_fine_level::bending_at_every_vertex() const {
  // The template's vertices keep their indices; a vertex inserted since takes the mean of
  // its neighbours that have a value, ring after ring.
  std::vector<double> bending(n, 0.0);
  std::vector<bool> known(n, false);
  for (std::size_t i = 0; i < std::min(n, template_bending->size()); ++i) bending[i] = (*template_bending)[i], known[i] = true;
  for (bool progress = true; progress;) {
    progress = false;
    std::vector<std::size_t> now;
    for (std::size_t i = 0; i < n; ++i) {
      if (known[i]) continue;
      double sum = 0;
      std::size_t count = 0;
      for (std::size_t k = adjacency.offsets[i]; k < adjacency.offsets[i + 1]; ++k)
        if (known[adjacency.neighbours[k]]) sum += bending[adjacency.neighbours[k]], ++count;
      if (count > 0) bending[i] = sum / static_cast<double>(count), now.push_back(i);
    }
    for (std::size_t i : now) known[i] = true;
    progress = !now.empty();
  }
  return bending;
}

std::vector<bool> Surface_fine_level::displacement_band() const {
  const double edge = mean_edge_length(tm, vpm);
  if (!(edge > 0 && std::isfinite(edge))) return std::vector<bool>(n, true);
  std::vector<bool> band = vertices_within_reach(adjacency, constrained, given, edge, band_rings, band_fade);
  std::size_t free_in_band = 0, free_all = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (!constrained[i]) ++free_all, free_in_band += band[i];
  if (2 * free_in_band >= free_all) band.assign(n, true);
  return band;
}

std::vector<Surface_fine_level::face_descriptor> Surface_fine_level::bad_faces() {
  // Only what changed since the last call is judged again: the faces with a corner moved or
  // replaced (by an edge flip), and the edges beside them (an edge whose faces changed is beside
  // a face whose corners did).
  const bool fresh = judged_at.size() != n || face_verdict.size() != tm.num_faces() || edge_folded.size() != tm.num_edges();
  std::vector<unsigned char> moved(n, fresh ? 1 : 0);
  if (fresh) {
    judged_at = after;
    judged_corners.assign(tm.num_faces(), {0, 0, 0});
    face_verdict.assign(tm.num_faces(), 0);
    edge_folded.assign(tm.num_edges(), 0);
  } else {
    for (std::size_t i = 0; i < n; ++i)
      if (after[i] != judged_at[i]) moved[i] = 1, judged_at[i] = after[i];
  }
  std::vector<unsigned char> changed(tm.num_faces(), 0);
  std::vector<face_descriptor> bad, steep;
  for (auto f : faces(tm)) {
    const std::size_t k = f.idx();
    const auto c = s.corners(f);
    if (fresh || c != judged_corners[k] || moved[c[0]] || moved[c[1]] || moved[c[2]]) {
      changed[k] = 1;
      judged_corners[k] = c;
      const Vector_3 N = reference_normal[c[0]] + reference_normal[c[1]] + reference_normal[c[2]];
      if (CGAL::orientation(after[c[0]], after[c[1]], after[c[2]], after[c[0]] + N) != CGAL::POSITIVE) {
        face_verdict[k] = 1;
      } else {
        const Vector_3 nf = CGAL::cross_product(after[c[1]] - after[c[0]], after[c[2]] - after[c[0]]);
        face_verdict[k] = nf * N < 0.34 * std::sqrt(nf.squared_length() * N.squared_length()) ? 2 : 0;
      }
    }
    if (face_verdict[k] == 1) bad.push_back(f);
    if (face_verdict[k] == 2) steep.push_back(f);
  }
  report.remaining_flips = bad.size();
  // Deform_state::folded_faces(after, nullptr, &folded_before), on the edges beside changed faces.
  std::vector<face_descriptor> folded;
  std::size_t ek = 0;
  for (auto e : edges(tm)) {
    const std::size_t k = ek++;
    const auto h = halfedge(e, tm), g = opposite(h, tm);
    if (is_border(h, tm) || is_border(g, tm)) continue;
    if (k < folded_before.size() && folded_before[k]) continue;
    if (fresh || changed[face(h, tm).idx()] || changed[face(g, tm).idx()])
      edge_folded[e.idx()] = edge_folds(tm, h, [&](vertex_descriptor v) { return after[get(s.index, v)]; });
    if (edge_folded[e.idx()]) folded.push_back(face(h, tm)), folded.push_back(face(g, tm));
  }
  report.remaining_folds = folded.size();
  serious = bad.size() + folded.size();
  bad.insert(bad.end(), folded.begin(), folded.end());
  bad.insert(bad.end(), steep.begin(), steep.end());
  return bad;
}

std::vector<bool> Surface_fine_level::rings_around(const std::vector<face_descriptor>& bad, std::size_t rings) const {
  std::vector<bool> in(n, false);
  std::vector<std::size_t> ring;
  for (auto f : bad)
    for (std::size_t c : s.corners(f))
      if (!constrained[c] && !in[c]) in[c] = true, ring.push_back(c);
  for (std::size_t grow = 0; grow < rings; ++grow) {
    std::vector<std::size_t> next_ring;
    for (std::size_t i : ring)
      for (std::size_t k = adjacency.offsets[i]; k < adjacency.offsets[i + 1]; ++k) {
        const std::size_t j = adjacency.neighbours[k];
        if (!constrained[j] && !in[j]) in[j] = true, next_ring.push_back(j);
      }
    ring.swap(next_ring);
  }
  return in;
}

std::vector<std::size_t> Surface_fine_level::segments_nearest(const std::vector<face_descriptor>& bad) const {
  // A breadth-first search over the mesh's edges from every chain at once, each vertex labelled
  // with the segment of the chain that reached it first.
  constexpr std::size_t none = static_cast<std::size_t>(-1);
  std::vector<std::size_t> label(s.vertex.size(), none), queue;
  for (std::size_t k = 0; k < chain_of.size(); ++k)
    for (auto v : chain_of[k]) {
      const std::size_t i = get(s.index, v);
      if (label[i] == none) label[i] = k, queue.push_back(i);
    }
  for (std::size_t q = 0; q < queue.size(); ++q)
    for (auto h : CGAL::halfedges_around_target(halfedge(s.vertex[queue[q]], tm), tm)) {
      const std::size_t j = get(s.index, source(h, tm));
      if (label[j] == none) label[j] = label[queue[q]], queue.push_back(j);
    }
  std::vector<std::size_t> out;
  for (auto f : bad)
    for (std::size_t c : s.corners(f))
      if (label[c] != none) out.push_back(label[c]);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void Surface_fine_level::untangle_around_bad() {
  std::vector<std::array<std::size_t, 3>> corners;
  std::vector<Vector_3> face_normal;
  for (auto f : faces(tm)) {
    const auto c = s.corners(f);
    corners.push_back(c);
    face_normal.push_back(reference_normal[c[0]] + reference_normal[c[1]] + reference_normal[c[2]]);
  }
  for (std::size_t rings : {2, 6}) {
    std::vector<bool> free = rings_around(flipped, rings);
    for (std::size_t i = 0; i < n; ++i)
      if (free[i] && is_border(s.vertex[i], tm)) free[i] = false;
    Untangle_report untangled;
    std::vector<Point_3> trial = untangle_faces(after, corners, face_normal, free, reference_normal, 1.0, &untangled);
    report.untangled_vertices += untangled.free_vertices;
    const std::pair<std::size_t, std::size_t> was{serious, flipped.size()};
    std::swap(after, trial);
    auto now = bad_faces();
    if (std::make_pair(serious, now.size()) < was) {
      flipped = std::move(now);
    } else {
      std::swap(after, trial);
      flipped = bad_faces();
    }
    ++report.untangle_rounds;
    if (flipped.empty()) break;
  }
}

void Surface_fine_level::move_and_untangle() {
  report_progress(options.progress, "deform", "fine: relaxing where faces turned over", 3, 4);
  s.folded_faces(before, &folded_before);
  for (std::size_t i = 0; i < n; ++i) after[i] = constrained[i] ? goal[i] : before[i] + displacement[i];
  flipped = bad_faces();
  report.flips_found = flipped.size();
  if (!flipped.empty()) {
    constexpr std::size_t steps = 4;
    after = before;
    for (std::size_t step = 1; step <= steps; ++step) {
      const double t = static_cast<double>(step) / static_cast<double>(steps);
      for (std::size_t i = 0; i < n; ++i)
        after[i] = constrained[i] ? (step == steps ? goal[i] : before[i] + t * given[i])
                                  : after[i] + displacement[i] / static_cast<double>(steps);
      flipped = bad_faces();
      if (!flipped.empty()) untangle_around_bad();
    }
  }
  report.flip_rounds = 1;
}

void Surface_fine_level::relax() {
  std::vector<Point_3> best = after;
  std::pair<std::size_t, std::size_t> best_bad{serious, flipped.size()};
  constexpr std::size_t max_rings = 3;
  for (std::size_t round = 0; !flipped.empty() && round < options.flip_prevention_rounds; ++round) {
    const std::vector<bool> relax = rings_around(flipped, std::min(round + 1, max_rings));
    std::vector<std::size_t> moving;
    for (std::size_t i = 0; i < n; ++i)
      if (relax[i]) moving.push_back(i);
    report.untangled_vertices += moving.size();
    for (int sweep = 0; sweep < 30; ++sweep)
      for (std::size_t i : moving) {
        double x = 0, y = 0, z = 0;
        const double deg = static_cast<double>(adjacency.offsets[i + 1] - adjacency.offsets[i]);
        for (std::size_t k = adjacency.offsets[i]; k < adjacency.offsets[i + 1]; ++k) {
          const Point_3& q = after[adjacency.neighbours[k]];
          x += q.x(), y += q.y(), z += q.z();
        }
        after[i] = Point_3(x / deg, y / deg, z / deg);
      }
    flipped = bad_faces();
    ++report.untangle_rounds;
    report.flip_rounds = round + 2;
    report.flips_found += flipped.size();
    if (std::make_pair(serious, flipped.size()) < best_bad) best = after, best_bad = {serious, flipped.size()};
  }
  if (std::make_pair(serious, flipped.size()) > best_bad) {
    after = std::move(best);
    flipped = bad_faces();
  }
}

bool Surface_fine_level::good(std::size_t a, std::size_t b, std::size_t c) const {
  const Vector_3 N = reference_normal[a] + reference_normal[b] + reference_normal[c];
  return CGAL::orientation(after[a], after[b], after[c], after[a] + N) == CGAL::POSITIVE;
}

bool Surface_fine_level::folds_with_neighbours(halfedge_descriptor h) const {
  const auto c = s.corners(face(h, tm));
  const Triangle_points t{after[c[0]], after[c[1]], after[c[2]]};
  for (auto g : CGAL::halfedges_around_face(h, tm)) {
    const auto o = opposite(g, tm);
    if (is_border(o, tm)) continue;
    const auto other = s.corners(face(o, tm));
    if (orientation_in_plane(t, after[other[0]], after[other[1]], after[other[2]]) != CGAL::POSITIVE) return true;
  }
  return false;
}

bool Surface_fine_level::flip_if_good(halfedge_descriptor h, bool unfolded) {
  const auto g = opposite(h, tm);
  if (get(curve, edge(h, tm)) || is_border(h, tm) || is_border(g, tm)) return false;
  const auto u = source(h, tm), v = target(h, tm), x = target(next(h, tm), tm), y = target(next(g, tm), tm);
  if (halfedge(x, y, tm).second) return false;
  const std::size_t iu = get(s.index, u), iv = get(s.index, v), ix = get(s.index, x), iy = get(s.index, y);
  if (!good(iu, iy, ix) || !good(iy, iv, ix)) return false;
  const Triangle_points first{after[iu], after[iy], after[ix]};
  if (orientation_in_plane(first, after[iy], after[iv], after[ix]) != CGAL::POSITIVE) return false;
  CGAL::Euler::flip_edge(h, tm);  // now x -> y
  if (unfolded && (folds_with_neighbours(h) || folds_with_neighbours(opposite(h, tm)))) {
    CGAL::Euler::flip_edge(h, tm);  // back to the diagonal u-v (two diagonals only)
    return false;
  }
  ++report.edges_flipped;
  return true;
}

void Surface_fine_level::flip_held_faces() {
  const std::size_t max_edge_flips = std::min<std::size_t>(64 + 4 * flipped.size(), 256);
  for (int pass = 0; pass < 3 && !flipped.empty(); ++pass) {
    bool changed = false;
    for (auto f : flipped) {
      const auto c = s.corners(f);
      if (!(constrained[c[0]] && constrained[c[1]] && constrained[c[2]]) || good(c[0], c[1], c[2])) continue;
      for (auto h : CGAL::halfedges_around_face(halfedge(f, tm), tm))
        if (flip_if_good(h, false)) {
          changed = true;
          break;
        }
      if (changed) break;  // faces changed: find the bad ones again
    }
    if (!changed) break;
    flipped = bad_faces();
    pass = -1;  // keep going while flips repair something
    if (report.edges_flipped >= max_edge_flips) break;
  }
}

void Surface_fine_level::flip_folded_diagonals() {
  for (std::size_t pass = 0; pass < 4 && report.remaining_folds > 0; ++pass) {
    std::vector<bool> folded_now;
    s.folded_faces(after, &folded_now, &folded_before);
    // The folded edge itself, or, for a curve edge, the other edges of a face beside it whose
    // corners are all held (three chain vertices where a chain turns round a triangle).
    std::vector<edge_descriptor> candidates;
    std::size_t k = 0;
    for (auto e : edges(tm)) {
      const std::size_t ek = k++;
      if (ek >= folded_now.size() || !folded_now[ek]) continue;
      if (!get(curve, e)) {
        candidates.push_back(e);
        continue;
      }
      for (auto h : {halfedge(e, tm), opposite(halfedge(e, tm), tm)}) {
        if (is_border(h, tm)) continue;
        const auto c = s.corners(face(h, tm));
        if (!(constrained[c[0]] && constrained[c[1]] && constrained[c[2]])) continue;
        for (auto g : {next(h, tm), prev(h, tm)})
          if (!get(curve, edge(g, tm))) candidates.push_back(edge(g, tm));
      }
    }
    bool changed = false;
    for (auto e : candidates) changed = flip_if_good(halfedge(e, tm), true) || changed;
    flipped = bad_faces();
    if (!changed) break;
  }
}

void Surface_fine_level::flip_slivers() {
  auto smallest_angle = [&](halfedge_descriptor h) {
    const auto c = s.corners(face(h, tm));
    return internal::smallest_angle(after[c[0]], after[c[1]], after[c[2]]);
  };
  const double sliver = 5 * CGAL_PI / 180;
  // Which faces are slivers, kept up to date through the flips (the points do not move here, so
  // only a flip, or a flip undone, changes a face): an edge with no sliver beside it is passed over without
  // measuring its faces again (1.3 million faces: 4 million angle measures a pass, now 1.3).
  auto thin = get(CGAL::dynamic_face_property_t<bool>(), tm);
  auto mark = [&](halfedge_descriptor h) { put(thin, face(h, tm), smallest_angle(h) < sliver); };
  for (int pass = 0; pass < 3; ++pass) {
    bool changed = false;
    for (auto f : faces(tm)) mark(halfedge(f, tm));
    std::vector<edge_descriptor> all(edges(tm).first, edges(tm).second);
    for (auto e : all) {
      const auto h = halfedge(e, tm), g = opposite(h, tm);
      if (is_border(h, tm) || is_border(g, tm) || get(curve, e)) continue;
      if (!get(thin, face(h, tm)) && !get(thin, face(g, tm))) continue;
      const double before_flip = std::min(smallest_angle(h), smallest_angle(g));
      if (!(before_flip < sliver)) continue;
      // A flip that leaves a face with every corner held (two curves' vertices beside a crossing,
      // say) is not made: nothing could move that face again (the dense example: 3 such faces
      // with Fine_shape::template_bending).
      const std::size_t iu = get(s.index, source(h, tm)), iv = get(s.index, target(h, tm)),
                        ix = get(s.index, target(next(h, tm), tm)), iy = get(s.index, target(next(g, tm), tm));
      if (constrained[ix] && constrained[iy] && (constrained[iu] || constrained[iv])) continue;
      if (flip_if_good(h, true)) {
        if (std::min(smallest_angle(h), smallest_angle(opposite(h, tm))) > before_flip) {
          changed = true;
        } else {
          CGAL::Euler::flip_edge(h, tm);  // no better: back
          --report.edges_flipped;
        }
      }
      // A flip, even one undone, may leave the two faces exchanged.
      mark(h), mark(opposite(h, tm));
    }
    if (!changed) break;
  }
}

std::size_t Surface_fine_level::place_in_ring(vertex_descriptor v) {
  const std::size_t i = get(s.index, v);
  std::vector<Point_3> ring;
  for (auto h : CGAL::halfedges_around_target(halfedge(v, tm), tm)) ring.push_back(after[get(s.index, source(h, tm))]);
  Vector_3 sum(0, 0, 0);
  for (const Point_3& p : ring) sum = sum + (p - CGAL::ORIGIN);
  const Point_3 mean = CGAL::ORIGIN + sum / static_cast<double>(ring.size());
  std::vector<Point_3> candidates{after[i], mean};
  for (std::size_t k = 0; k < ring.size(); ++k) {
    candidates.push_back(CGAL::centroid(ring[k], ring[(k + 1) % ring.size()], mean));
    candidates.push_back(CGAL::midpoint(ring[k], mean));
  }
  // Fewest bad faces around v, then the largest smallest angle; the place v has wins ties.
  std::pair<std::size_t, double> best{SIZE_MAX, 0};
  Point_3 best_point = after[i];
  for (const Point_3& q : candidates) {
    after[i] = q;
    std::pair<std::size_t, double> score{0, -CGAL_PI};
    for (auto f : CGAL::faces_around_target(halfedge(v, tm), tm)) {
      const auto c = s.corners(f);
      if (!good(c[0], c[1], c[2])) ++score.first;
      score.second = std::max(score.second, -internal::smallest_angle(after[c[0]], after[c[1]], after[c[2]]));
    }
    if (score < best) best = score, best_point = q;
    if (best.first == 0 && q == mean) break;  // the mean will do
  }
  after[i] = best_point;
  return best.first;
}

std::size_t Surface_fine_level::trouble(const std::vector<face_descriptor>& region) const {
  std::size_t count = 0;
  for (auto f : region) {
    const auto c = s.corners(f);
    if (!good(c[0], c[1], c[2])) ++count;
    if (folds_with_neighbours(halfedge(f, tm))) ++count;
  }
  return count;
}

void Surface_fine_level::free_trapped_vertices() {
  for (int pass = 0; pass < 3; ++pass) {
    std::vector<vertex_descriptor> candidates;
    std::vector<bool> seen(n, false);
    for (auto f : faces(tm)) {
      const auto c = s.corners(f);
      if (good(c[0], c[1], c[2])) continue;
      for (std::size_t k : c)
        if (!constrained[k] && !seen[k] && !is_border(s.vertex[k], tm)) seen[k] = true, candidates.push_back(s.vertex[k]);
    }
    bool changed = false;
    for (auto v : candidates) {
      const std::size_t i = get(s.index, v);
      const Point_3 was = after[i];
      // The disc of v's faces: what is moved and flipped here stays inside it.
      std::vector<face_descriptor> disc;
      for (auto f : CGAL::faces_around_target(halfedge(v, tm), tm)) disc.push_back(f);
      const std::size_t trouble_before = trouble(disc);
      std::vector<halfedge_descriptor> flips;
      bool placed = place_in_ring(v) == 0;
      for (std::size_t degree = disc.size(); !placed && degree > 3; --degree) {
        // An edge v-w (faces v w x and w v y) whose flip to x-y leaves a good face x y w.
        const auto h = [&] {
          for (auto g : CGAL::halfedges_around_source(v, tm)) {
            const auto w = target(g, tm), x = target(next(g, tm), tm), y = target(next(opposite(g, tm), tm), tm);
            if (!get(curve, edge(g, tm)) && !halfedge(x, y, tm).second && good(get(s.index, w), get(s.index, x), get(s.index, y)))
              return g;
          }
          return GT::null_halfedge();
        }();
        if (h == GT::null_halfedge()) break;
        CGAL::Euler::flip_edge(h, tm);
        flips.push_back(h);
        placed = place_in_ring(v) == 0;
      }
      {
        // The same disc, now: v's faces and those the flips took from it.
        std::vector<face_descriptor> now;
        for (auto f : CGAL::faces_around_target(halfedge(v, tm), tm)) now.push_back(f);
        for (auto h : flips) now.push_back(face(h, tm)), now.push_back(face(opposite(h, tm), tm));
        std::sort(now.begin(), now.end());
        now.erase(std::unique(now.begin(), now.end()), now.end());
        if (trouble(now) < trouble_before) {
          changed = true;
          report.edges_flipped += flips.size();
          continue;
        }
      }
      for (auto it = flips.rbegin(); it != flips.rend(); ++it) CGAL::Euler::flip_edge(*it, tm);
      after[i] = was;
    }
    if (!changed) break;
  }
  flipped = bad_faces();
}

void Surface_fine_level::finish() {
  flipped = bad_faces();
  if (serious > 0)  // the faces turned over and those beside a folded edge come first
    report.segments_near_defects = segments_nearest({flipped.begin(), flipped.begin() + static_cast<std::ptrdiff_t>(serious)});
  s.set_positions(after);

  for (std::size_t v = 0; v < nv; ++v)
    if (s.to_point(s.vertex[mesh_of[v]]) != network.point(v))
      throw Numerical_error("deform: network vertex " + std::to_string(v) + " did not end at its point (mesh vertex " +
                            std::to_string(mesh_of[v]) + ", " +
                            std::to_string(std::count(mesh_of.begin(), mesh_of.end(), mesh_of[v])) +
                            " network vertices on it)");
  report.fine_done = true;
  report.mesh_vertex_of_network_vertex = mesh_of;
  report.fine_seconds = seconds_since(t0);
  report.vertices = num_vertices(tm);
  report.faces = num_faces(tm);
}

}  // namespace

Deformation_report fine_on_surface(Work_mesh& tm, const Curve_network& network,
                                   const std::vector<Correspondence>& pairs, const Deform_options& options,
                                   bool split_for_paths, std::optional<Work_face_tree> tree,
                                   const std::vector<double>* template_bending) {
  return Surface_fine_level(tm, network, pairs, options, split_for_paths, std::move(tree), template_bending).run();
}

}  // namespace internal
}  // namespace meshfit
