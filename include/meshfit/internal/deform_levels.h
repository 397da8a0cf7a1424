// meshfit internal: the levels of stage 1 (deform.h) over any mesh with its own point map, as
// templates; the library compiles them once for its own mesh (src/deform.cpp). Their helpers are
// in deform_impl.h.
#ifndef MESHFIT_INTERNAL_DEFORM_LEVELS_H
#define MESHFIT_INTERNAL_DEFORM_LEVELS_H

#include <meshfit/deform.h>
#include <meshfit/predicates.h>
#include <meshfit/registration.h>
#include <meshfit/internal/clear_mesh.h>
#include <meshfit/internal/deform_impl.h>
#include <meshfit/internal/resample_network.h>
#include <meshfit/internal/subdivide.h>
#include <meshfit/internal/triangle_corners.h>
#include <meshfit/internal/unit_scale.h>
#include <meshfit/memory_limit.h>
#include <meshfit/untangle.h>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Dynamic_property_map.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/helpers.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <queue>
#include <set>
#include <string>
#include <vector>

namespace meshfit {
namespace internal {
/// deform_coarse on `tm` itself. For meshes the pipeline owns (a Stage_copy, fit's copy).
template <typename TriangleMesh>
Deformation_report deform_coarse_impl(TriangleMesh& tm, const Curve_network& network,
                                          const std::vector<Correspondence>& pairs, const Deform_options& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const Rbf_kernel kernel = options.rbf_kernel;
  const Progress_callback& progress = options.progress;

  internal::Deform_state<TriangleMesh, decltype(get_property_map(CGAL::vertex_point, tm))> s(
      tm, get_property_map(CGAL::vertex_point, tm));
  internal::check_pairs(pairs, s.vertex.size(), num_faces(tm), network);
  internal::report_progress(progress, "deform", "coarse: fitting the RBF through the user's pairs", 0, 2);
  std::vector<Point_3> centres, values;
  std::vector<Vector_3> normals;
  // An open template that faces one way (its vector area, the sum of its faces' area vectors, at
  // least a tenth of its area: a disc, a patch, not a closed bag with a pin hole) gets its
  // orientation from the pairs' layout along it (Rbf_interpolant::fit), its facing as the normal.
  Vector_3 facing(0, 0, 0);
  double area = 0;
  if (!CGAL::is_closed(tm))
    for (auto f : faces(tm)) {
      const auto h = halfedge(f, tm);
      const Point_3 a = s.to_point(source(h, tm)), b = s.to_point(target(h, tm)),
                    c = s.to_point(target(next(h, tm), tm));
      const Vector_3 n = CGAL::cross_product(b - a, c - a);
      facing = facing + n;
      area += std::sqrt(n.squared_length());
    }
  const bool open_facing = area > 0 && std::sqrt(facing.squared_length()) >= 0.1 * area;
  for (const Correspondence& c : pairs) {
    centres.push_back(s.to_point(s.vertex[c.template_vertex]));
    values.push_back(network.point(c.network_vertex));
    normals.push_back(open_facing ? facing : s.normal(c.template_vertex));
  }
  Deformation_report report;
  report.user_pairs = pairs.size();
  const Rbf_interpolant E =
      Rbf_interpolant::fit(centres, values, kernel, normals, &report.coarse_fit, options.memory_limit, open_facing);
  internal::report_progress(progress, "deform", "coarse: moving the template", 1, 2);
  const std::vector<Point_3> before = s.positions();
  std::vector<Point_3> p;
  E.evaluate(before, p);
  for (const Correspondence& c : pairs) p[c.template_vertex] = network.point(c.network_vertex);
  // Orientation is judged against the affine part of E, not against the template's own
  // placement: a rotation of the template (any angle) has det R > 0 and flips nothing, a mirror
  // has det R < 0. The faces counted as flipped are those that the RBF part turns over relative
  // to the affine image of the template (exact flip counter), so the count, too, is unchanged by
  // a rigid motion or a uniform scaling of either input.
  report.coarse_affine_determinant = E.affine_determinant();
  report.orientation_reversed = !(report.coarse_affine_determinant > 0);
  std::vector<Point_3> affine_image(before.size());
  for (std::size_t i = 0; i < before.size(); ++i) affine_image[i] = E.affine_part(before[i]);
  std::size_t degenerate = 0;
  report.coarse_flipped_faces = s.flipped_faces(affine_image, p, degenerate).size();
  s.set_positions(p);
  report.coarse_seconds = internal::seconds_since(t0);
  report.vertices = num_vertices(tm);
  report.faces = num_faces(tm);
  report.mesh_vertex_of_network_vertex.assign(network.number_of_vertices(), Closest_point_assignment::unassigned);
  for (const Correspondence& c : pairs) report.mesh_vertex_of_network_vertex[c.network_vertex] = c.template_vertex;
  return report;
}

/// \throws Algorithm_failure when the thesis level's fine RBF, which with Curve_density::refine
///         has every network vertex as a centre, would exceed the memory limit.
inline void check_fine_rbf_memory(const Curve_network& network, const Deform_options& options) {
  if (options.curve_density != Curve_density::refine) return;
  const double n = static_cast<double>(network.number_of_vertices() + 4);
  check_memory_estimate(2 * 8 * n * n, options.memory_limit, "deform",
                        "the fine RBF through all " + std::to_string(network.number_of_vertices()) +
                            " network vertices (a dense system of as many unknowns)");
}

/// The thesis's fine level (deform_fine) on a mesh: closest-point pairs for the network vertices,
/// a fine RBF through them, and local subdivision where faces flip (§2.3), round after round.
template <typename TriangleMesh>
class Thesis_fine_level {
 public:
  Thesis_fine_level(TriangleMesh& tm, const Curve_network& network, const std::vector<Correspondence>& pairs,
                    const Deform_options& options)
      : tm(tm), network(network), pairs(pairs), options(options), vpm(get_property_map(CGAL::vertex_point, tm)),
        s(tm, vpm), fixed(pairs) {
    report.fine_level = Fine_level::thesis;
    report.user_pairs = pairs.size();
  }

  Deformation_report run() {
    check_inputs();
    // Vertices of no face (unused) are no candidates for the closest-point pairs and do not move.
    used.resize(s.vertex.size());
    for (std::size_t i = 0; i < s.vertex.size(); ++i) used[i] = halfedge(s.vertex[i], tm) != GT::null_halfedge();
    // Flip prevention adds vertices; beyond this many it is not converging.
    max_vertices = 8 * (s.vertex.size() + network.number_of_vertices());
    std::vector<Point_3> moved;
    for (std::size_t round = 0;; ++round) {
      const std::vector<Point_3> before = s.positions();
      used.resize(s.vertex.size(), true);  // (vertices inserted since are on faces)
      assignment = closest_point_correspondences(before, network, fixed, Loser_rule::drop, used);
      if (refine_density()) {
        --round;  // refinement is not a flip round
        continue;
      }
      report_progress(options.progress, "deform", "fine: RBF through the correspondences and flip detection", round,
                      options.flip_prevention_rounds);
      const std::vector<std::pair<std::size_t, std::size_t>> placed = move_by_rbf(before, moved);
      const auto flipped = s.flipped_faces(before, moved, report.degenerate_faces_skipped);
      report.flip_rounds = round + 1;
      report.flips_found += flipped.size();
      if (flipped.empty() || round + 1 >= options.flip_prevention_rounds) {
        report.remaining_flips = flipped.size();
        break;
      }
      subdivide_flipped(flipped, placed, before, moved, round);
    }
    s.set_positions(moved);
    report.fine_done = true;
    // With Curve_density::refine these are the network vertices refinement could not serve.
    report.dropped_network_vertices = assignment.losers;
    report.mesh_vertex_of_network_vertex = assignment.template_of;
    report.fine_seconds = seconds_since(t0);
    report.vertices = num_vertices(tm);
    report.faces = num_faces(tm);
    return report;
  }

 private:
  using GT = boost::graph_traits<TriangleMesh>;
  using face_descriptor = typename GT::face_descriptor;
  using VPM = typename boost::property_map<TriangleMesh, CGAL::vertex_point_t>::type;

  void check_inputs() const {
    check_pairs(pairs, s.vertex.size(), num_faces(tm), network);
    // From the counts, before the far-polyline check's closest-point queries (39 s on 5.8 M points).
    check_fine_rbf_memory(network, options);
    check_polylines_near(tm, vpm, network);
  }

  // Density refinement: network vertices that lost their nearest template vertex to another get
  // vertices of their own. It repeats while it makes progress (a loser whose nearest point is
  // taken by a nearer network vertex may need several passes), within a bound. True when it ran.
  bool refine_density() {
    constexpr std::size_t max_refine_passes = 32;
    if (assignment.losers.empty() || options.curve_density != Curve_density::refine ||
        refine_passes >= max_refine_passes || assignment.losers.size() >= last_losers)
      return false;
    ++refine_passes;
    last_losers = assignment.losers.size();
    report_progress(options.progress, "deform", "fine: refining where the curves are denser than the template",
                    refine_passes - 1, max_refine_passes);
    report.vertices_inserted_for_density += pin_at_projections(assignment.losers, {});
    return true;
  }

  // The fine RBF through the assigned pairs moves every vertex from `before` to `moved`; the
  // paired ones land exactly on their network vertices, unused ones stay. Returns the pairs
  // (mesh vertex, network vertex).
  std::vector<std::pair<std::size_t, std::size_t>> move_by_rbf(const std::vector<Point_3>& before,
                                                               std::vector<Point_3>& moved) {
    std::vector<Point_3> centres, values;
    std::vector<std::pair<std::size_t, std::size_t>> placed;
    for (std::size_t v = 0; v < assignment.template_of.size(); ++v) {
      const std::size_t t = assignment.template_of[v];
      if (t == Closest_point_assignment::unassigned) continue;
      centres.push_back(before[t]);
      values.push_back(network.point(v));
      placed.emplace_back(t, v);
    }
    const Rbf_interpolant E =
        Rbf_interpolant::fit(centres, values, options.rbf_kernel, {}, &report.fine_fit, options.memory_limit);
    moved.clear();
    E.evaluate(before, moved);
    for (const auto& [t, v] : placed) moved[t] = network.point(v);
    for (std::size_t t = 0; t < used.size(); ++t)
      if (!used[t]) moved[t] = before[t];
    report.fine_pairs = placed.size();
    return placed;
  }

  // Local subdivision (§2.3.2): a face flips because a paired corner is pulled across it
  // towards its network vertex. That network vertex gets a vertex of its own at its nearest
  // point on the surface (pin_at_projections), and the corner is released; the correspondences
  // are then recomputed. Flipped faces with no paired corner are split at their centroid.
  void subdivide_flipped(const std::vector<face_descriptor>& flipped,
                         const std::vector<std::pair<std::size_t, std::size_t>>& placed,
                         const std::vector<Point_3>& before, const std::vector<Point_3>& moved, std::size_t round) {
    std::vector<std::size_t> pulled;
    std::vector<face_descriptor> unpaired;
    std::vector<std::size_t> network_of(s.vertex.size(), Closest_point_assignment::unassigned);
    for (const auto& [t, v] : placed) network_of[t] = v;
    for (auto f : flipped) {
      bool any = false;
      for (std::size_t t : s.corners(f))
        if (network_of[t] != Closest_point_assignment::unassigned && moved[t] != before[t]) {
          pulled.push_back(network_of[t]);
          any = true;
        }
      if (!any) unpaired.push_back(f);
    }
    std::sort(pulled.begin(), pulled.end());
    pulled.erase(std::unique(pulled.begin(), pulled.end()), pulled.end());
    if (s.vertex.size() + pulled.size() + unpaired.size() > max_vertices)
      throw Algorithm_failure("deform", "flip prevention stopped in round " + std::to_string(round + 1) + ": " +
                                            std::to_string(flipped.size()) + " faces flip, and subdividing them would "
                                            "grow the mesh past " + std::to_string(max_vertices) +
                                            " vertices (8 × (template + network vertices)); the coarse level leaves "
                                            "the template too far from the curves (more correspondences help)",
                              {{"round", static_cast<double>(round + 1)},
                               {"flipped_faces", static_cast<double>(flipped.size())},
                               {"vertex_bound", static_cast<double>(max_vertices)}});
    const std::size_t split_before = s.faces_split;
    report.vertices_inserted_for_flips += pin_at_projections(pulled, unpaired);
    report.faces_subdivided += s.faces_split - split_before;
  }

  // Gives each listed network vertex a mesh vertex at its nearest point on the surface (one per
  // face and call) and pins it there; splits `centroid_faces` at their centroids. Moving such a
  // vertex onto its network vertex is a motion along the normal, which flips nothing. Returns
  // the number of new vertices.
  std::size_t pin_at_projections(const std::vector<std::size_t>& network_vertices,
                                 const std::vector<face_descriptor>& centroid_faces) {
    using Primitive = CGAL::AABB_face_graph_triangle_primitive<TriangleMesh, VPM>;
    using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
    std::map<face_descriptor, std::pair<std::size_t, Point_3>> at;
    if (!network_vertices.empty()) {
      Tree tree(faces(tm).first, faces(tm).second, tm, vpm);
      tree.accelerate_distance_queries();
      for (std::size_t v : network_vertices) {
        const auto hit = tree.closest_point_and_primitive(network.point(v));
        at.emplace(hit.second, std::make_pair(v, Point_3(hit.first.x(), hit.first.y(), hit.first.z())));
      }
    }
    const std::size_t before_count = s.vertex.size();
    std::vector<bool> reserved(s.vertex.size(), false);
    for (const Correspondence& c : fixed) reserved[c.template_vertex] = true;
    for (const auto& [f, vp] : at) {
      const std::size_t network_vertex = vp.first;
      const std::size_t t = s.insert_near(f, vp.second, reserved);
      reserved.resize(s.vertex.size(), false);
      reserved[t] = true;
      // A network vertex pinned before is re-pinned (never one of the user's pairs).
      bool users = false;
      for (std::size_t k = 0; k < fixed.size(); ++k) {
        if (fixed[k].network_vertex != network_vertex) continue;
        if (k < pairs.size()) {
          users = true;
        } else {
          fixed.erase(fixed.begin() + static_cast<std::ptrdiff_t>(k));
          break;
        }
      }
      if (users) continue;
      Correspondence c;
      c.template_vertex = t;
      c.network_vertex = network_vertex;
      fixed.push_back(c);
    }
    for (auto f : centroid_faces)
      if (!at.count(f)) s.split_face(f);
    return s.vertex.size() - before_count;
  }

  TriangleMesh& tm;
  const Curve_network& network;
  const std::vector<Correspondence>& pairs;
  const Deform_options& options;
  const std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  VPM vpm;
  Deform_state<TriangleMesh, VPM> s;
  Deformation_report report;
  std::vector<Correspondence> fixed;  // kept from round to round: the user's, then those made for density and flips
  std::vector<bool> used;             // by mesh vertex: on a face
  std::size_t max_vertices = 0;
  std::size_t refine_passes = 0, last_losers = SIZE_MAX;
  Closest_point_assignment assignment;
};

/// deform_fine on `tm` itself: the mesh changes as the work goes (a cancel or a failure leaves it
/// partly changed). For meshes the pipeline owns (a Stage_copy, fit's copy).
template <typename TriangleMesh>
Deformation_report deform_fine_impl(TriangleMesh& tm, const Curve_network& network,
                                    const std::vector<Correspondence>& pairs, const Deform_options& options) {
  return Thesis_fine_level<TriangleMesh>(tm, network, pairs, options).run();
}

/// The segments of `network` that the surface fine level keeps whole (does not cut at the mean
/// edge length `h`): those with both ends near the border (nearer to it than half an edge more
/// than to the surface, as in step 1). A curve along the border becomes the border arc (step 2),
/// whatever the length of its segments.
template <typename TriangleMesh, typename VPM>
std::vector<bool> segments_along_border(const TriangleMesh& tm, const VPM& vpm, const Curve_network& network, double h) {
  std::vector<Segment_3> border;
  for (auto e : edges(tm))
    if (is_border(e, tm)) border.emplace_back(get(vpm, source(e, tm)), get(vpm, target(e, tm)));
  std::vector<bool> whole(network.number_of_segments(), false);
  if (border.empty()) return whole;
  using Primitive = CGAL::AABB_face_graph_triangle_primitive<TriangleMesh, VPM>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  std::unique_ptr<Tree> tree;
  std::vector<int> near(network.number_of_vertices(), -1);  // unknown, no, yes
  auto near_border = [&](std::size_t v) {
    if (near[v] < 0) {
      if (!tree) {
        tree = std::make_unique<Tree>(faces(tm).first, faces(tm).second, tm, vpm);
        tree->accelerate_distance_queries();
      }
      const Point_3& p = network.point(v);
      const double reach = std::sqrt(tree->squared_distance(p)) + 0.5 * h;
      near[v] = 0;
      for (const Segment_3& b : border)
        if (CGAL::squared_distance(b, p) <= reach * reach) {
          near[v] = 1;
          break;
        }
    }
    return near[v] == 1;
  };
  for (std::size_t k = 0; k < whole.size(); ++k) {
    const auto& sk = network.segments()[k];
    whole[k] = CGAL::squared_distance(network.point(sk[0]), network.point(sk[1])) > 4 * h * h && near_border(sk[0]) &&
               near_border(sk[1]);
  }
  return whole;
}

/// Steps 1-4 of the surface fine level (fine_on_surface) on the network with its long segments
/// cut (`cut`, `cut_pairs`); the report in terms of the user's network.
inline Deformation_report fine_on_cut_network(Work_mesh& tm, const Curve_network& network,
                                              const std::vector<Correspondence>& pairs, const Resampled_network& cut,
                                              const std::vector<Correspondence>& cut_pairs,
                                              const Deform_options& options, bool split_for_paths,
                                              std::optional<Work_face_tree> tree = std::nullopt,
                                              const std::vector<double>* template_bending = nullptr) {
  Deformation_report r =
      cut.added == 0
          ? fine_on_surface(tm, network, pairs, options, split_for_paths, std::move(tree), template_bending)
          : fine_on_surface(tm, cut.network, cut_pairs, options, split_for_paths, std::move(tree), template_bending);
  if (cut.added > 0) {
    r.network_points_added = cut.added;
    std::vector<std::size_t> mesh_of(network.number_of_vertices());
    for (std::size_t v = 0; v < mesh_of.size(); ++v) mesh_of[v] = r.mesh_vertex_of_network_vertex[cut.vertex_of[v]];
    r.mesh_vertex_of_network_vertex = std::move(mesh_of);
    // Segments of the cut network, as the user's segments they are pieces of.
    auto uncut = [&](std::vector<std::size_t>& segments) {
      for (std::size_t& k : segments) k = cut.segment_of[k];
      std::sort(segments.begin(), segments.end());
      segments.erase(std::unique(segments.begin(), segments.end()), segments.end());
    };
    uncut(r.segments_not_embedded);
    uncut(r.segments_near_defects);
    r.segments_embedded = network.number_of_segments() - r.segments_not_embedded.size();
  }
  r.polylines_near_defects = network.polylines_of_segments(r.segments_near_defects);
  return r;
}

/// A mesh as points (through the point map, which may live outside the mesh) and triangles, to go
/// back to. Rebuilt in place, vertices and faces in their order (assigning a Surface_mesh would
/// leave the caller's property maps dangling); values of the caller's other properties on the
/// mesh are not carried over.
struct Mesh_snapshot {
  std::vector<Point_3> points;
  std::vector<std::array<std::size_t, 3>> triangles;

  template <typename TriangleMesh, typename VPM>
  static Mesh_snapshot of(const TriangleMesh& tm, const VPM& vpm) {
    Mesh_snapshot shot;
    for (auto v : vertices(tm)) {
      const auto p = get(vpm, v);
      shot.points.emplace_back(p.x(), p.y(), p.z());
    }
    auto index = get(CGAL::dynamic_vertex_property_t<std::size_t>(), tm);
    std::size_t i = 0;
    for (auto v : vertices(tm)) put(index, v, i++);
    for (auto f : faces(tm)) shot.triangles.push_back(triangle_corners(f, tm, index));
    return shot;
  }
  template <typename TriangleMesh, typename VPM>
  void restore(TriangleMesh& tm, const VPM& vpm) const {
    clear_mesh(tm);
    using P = typename boost::property_traits<VPM>::value_type;
    std::vector<typename boost::graph_traits<TriangleMesh>::vertex_descriptor> vertex;
    for (const Point_3& p : points) {
      vertex.push_back(add_vertex(tm));
      put(vpm, vertex.back(), P(p.x(), p.y(), p.z()));
    }
    for (const auto& t : triangles)
      if (CGAL::Euler::add_face(std::array{vertex[t[0]], vertex[t[1]], vertex[t[2]]}, tm) ==
          boost::graph_traits<TriangleMesh>::null_face())
        throw Numerical_error("deform: the mesh could not be rebuilt to run the fine level again");
  }
};

/// deform_fine_on_surface on `tm` itself: the mesh changes as the work goes (a cancel or a failure leaves it
/// partly changed). For meshes the pipeline owns (a Stage_copy, fit's copy).
template <typename TriangleMesh>
Deformation_report deform_fine_on_surface_impl(TriangleMesh& tm, const Curve_network& network,
                                    const std::vector<Correspondence>& pairs, const Deform_options& options,
                                    const std::vector<double>* template_bending = nullptr,
                                    std::size_t subdivisions = 0) {
  auto vpm = get_property_map(CGAL::vertex_point, tm);
  internal::check_pairs(pairs, num_vertices(tm), num_faces(tm), network);
  const double h = internal::mean_edge_length(tm, vpm);
  const internal::Resampled_network cut =
      internal::resample_long_segments(network, h, segments_along_border(tm, vpm, network, h));
  std::vector<Correspondence> cut_pairs = pairs;
  for (Correspondence& c : cut_pairs) c.network_vertex = cut.vertex_of[c.network_vertex];
  auto defects = [](const Deformation_report& r) {
    return r.segments_not_embedded.size() + r.remaining_flips + r.remaining_folds;
  };
  // Three starts, tried in turn until one leaves no defect: the coarse surface brought towards the
  // curves by non-rigid ICP (internal::approach_curves_icp), by the thin-plate field through the
  // nearest template vertices (internal::approach_curves), and as it is. Each approach is made
  // from the coarse surface; when none is clean, the start with the fewest defects is kept (the
  // earlier on a tie), unless the last one fails with a reason. When a start left a segment whose
  // ends the other chains wall off, the three are tried once more with such segments given a path
  // through split edges (fine_on_surface's split_for_paths): a fallback, so that what was clean
  // without it stays as it was.
  // A polyline far from the coarse surface is refused before any approach pulls the surface to it.
  // One face tree for that check and the first start's ICP, on the mesh as it is (a tree costs
  // 0.7 s at 1.3 million faces). A later start restores the coarse surface by rebuilding the
  // mesh, whose faces the tree would no longer know: ICP builds its own then.
  internal::Face_tree<TriangleMesh, decltype(vpm)> coarse_tree;
  internal::build_face_tree(tm, vpm, coarse_tree);
  internal::check_polylines_near(tm, vpm, coarse_tree, network);
  const Mesh_snapshot coarse = Mesh_snapshot::of(tm, vpm);
  // The shape between the curves that every start's step 3 gives the surface there: the
  // template's bending (`template_bending`, else the mesh's as given), or the approach's.
  // Fine_shape::automatic, when it resolves to the bending, falls back to the approach's shape if
  // no start is clean with the bending: a second pass over the starts (and rounds), the result
  // with the fewest defects of both passes kept (the bending's on a tie).
  const bool bend =
      resolved_fine_shape(options.fine_shape, tm, vpm, network, subdivisions) == Fine_shape::template_bending;
  const int passes = bend && options.fine_shape == Fine_shape::automatic ? 2 : 1;
  std::vector<double> own_bending;
  if (bend && !template_bending) own_bending = normal_bending(coarse.points, coarse.triangles);
  std::optional<Deformation_report> best;
  std::optional<Mesh_snapshot> best_mesh;
  std::size_t tried = 0;
  for (int pass = 0; pass < passes; ++pass) {
    const bool last_pass = pass + 1 == passes;
    const std::vector<double>* bending = !bend || pass == 1 ? nullptr : template_bending ? template_bending : &own_bending;
    bool walled = false;  // a start left a segment with no path
    for (int round = 0; round < 2 && (round == 0 || walled); ++round) {
      for (int start = 0; start < 3; ++start) {
        if (tried > 0) coarse.restore(tm, vpm);
        internal::Approach_result approach;
        std::optional<internal::Face_tree<TriangleMesh, decltype(vpm)>> tree_after;  // ICP's last tree, for step 1
        // Curves more than twice as dense as the template: no approach will give them room (step 2
        // refuses such inputs), and ICP would only move the template around.
        if (start == 0 && cut.network.number_of_vertices() <= 2 * num_vertices(tm))
          approach = internal::approach_curves_icp(tm, vpm, cut.network, cut_pairs, tried == 0 ? &coarse_tree : nullptr,
                                                   &tree_after);
        if (start == 1) approach = internal::approach_curves(tm, vpm, cut.network, cut_pairs);
        if (start < 2 && approach.scale == 0) continue;  // the approach made no motion: the same start as the last
        std::optional<Deformation_report> r;
        try {
          r = fine_on_cut_network(tm, network, pairs, cut, cut_pairs, options, round == 1, std::move(tree_after), bending);
        } catch (const Cancelled&) {
          throw;  // the caller's cancel, not a failure of this start
        } catch (const Algorithm_failure&) {
          // The last start's reason (from the coarse surface as it is) is said rather than a result
          // with defects kept.
          if (last_pass && start == 2 && (round == 1 || !walled)) throw;
        }
        ++tried;
        if (!r) continue;
        walled = walled || !r->segments_not_embedded.empty();
        r->approach_constraints = approach.constraints;
        r->approach_scale = approach.scale;
        r->approach_coarse_nodes = approach.coarse_nodes;
        r->approach = start == 0 ? Approach::icp : start == 1 ? Approach::nearest_vertices : Approach::none;
        r->approach_retried = tried > 1;
        if (!best || defects(*r) < defects(*best)) {
          best = r;
          best_mesh.reset();
          if (defects(*r) == 0) return *best;
          best_mesh = Mesh_snapshot::of(tm, vpm);
        }
      }
    }
  }
  if (best_mesh) best_mesh->restore(tm, vpm);
  return *best;
}

/// The template's bending (normal_bending) in the frame of the coarse surface: a curvature, it is
/// scaled by the square root of the ratio of the two surfaces' areas (the coarse level scales the
/// template to the curves' size).
inline std::vector<double> template_bending_after_coarse(const Mesh_snapshot& shape, const Mesh_snapshot& coarse) {
  auto area = [](const Mesh_snapshot& m) {
    double a = 0;
    for (const auto& t : m.triangles)
      a += std::sqrt(CGAL::cross_product(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]).squared_length());
    return a;
  };
  std::vector<double> bending = normal_bending(shape.points, shape.triangles);
  const double a = area(shape), c = area(coarse);
  const double scale = a > 0 && c > 0 && std::isfinite(a / c) ? std::sqrt(a / c) : 1;
  for (double& b : bending) b *= scale;
  return bending;
}

/// The defects Fine_level::surface left, worst first: segments not embedded, faces turned over,
/// faces beside a folded edge (compared in that order: a face turned over fails the fit, a fold
/// only beyond the template's own).
inline std::array<std::size_t, 3> fine_defects(const Deformation_report& r) {
  return {r.segments_not_embedded.size(), r.remaining_flips, r.remaining_folds};
}

/// The warps of `tm` onto the network that register_quadratic_warp offers (from its vertices on
/// faces and its faces, the user's pairs as constraints with their tolerances; `subdivisions`: how
/// many times the template was subdivided since the user gave it): the warp it returns, then the
/// Coherent Point Drift's when that is another one. Empty when every warp turns space over.
template <typename TriangleMesh>
std::vector<Quadratic_warp> registered_warps(TriangleMesh& tm, const Curve_network& network,
                                             const std::vector<Correspondence>& pairs, std::size_t subdivisions,
                                             Registration_report& report) {
  using GT = boost::graph_traits<TriangleMesh>;
  const auto vpm = get_property_map(CGAL::vertex_point, tm);
  const std::vector<typename GT::vertex_descriptor> vertex(vertices(tm).first, vertices(tm).second);
  std::vector<Point_3> points, network_points;
  auto index = get(CGAL::dynamic_vertex_property_t<std::size_t>(), tm);
  for (auto v : vertex)
    if (halfedge(v, tm) != GT::null_halfedge()) {
      put(index, v, points.size());
      points.push_back(point_of<TriangleMesh>(vpm, v));
    }
  std::vector<std::array<std::size_t, 3>> triangles;
  for (auto f : faces(tm)) {
    const auto h = halfedge(f, tm);
    triangles.push_back({get(index, source(h, tm)), get(index, target(h, tm)), get(index, target(next(h, tm), tm))});
  }
  for (std::size_t k = 0; k < network.number_of_vertices(); ++k) network_points.push_back(network.point(k));
  std::vector<std::pair<Point_3, Point_3>> fixed;
  // A pair's tolerance: the mean length of the template's edges at its vertex, as the user gave
  // the template (each subdivision halved them); none for a vertex on no face.
  std::vector<double> tolerance;
  for (const Correspondence& c : pairs) {
    const auto v = vertex[c.template_vertex];
    const Point_3 p = point_of<TriangleMesh>(vpm, v);
    fixed.emplace_back(p, network.point(c.network_vertex));
    if (halfedge(v, tm) == GT::null_halfedge()) {
      tolerance.push_back(std::numeric_limits<double>::infinity());
      continue;
    }
    double length = 0;
    std::size_t edges = 0;
    for (auto h : CGAL::halfedges_around_target(halfedge(v, tm), tm)) {
      length += std::sqrt(CGAL::squared_distance(p, point_of<TriangleMesh>(vpm, source(h, tm))));
      ++edges;
    }
    tolerance.push_back(std::ldexp(length / static_cast<double>(edges), static_cast<int>(subdivisions)));
  }
  std::optional<Quadratic_warp> drift;
  std::vector<Quadratic_warp> warps;
  if (const auto warp = register_quadratic_warp(points, triangles, network_points, fixed, tolerance, &report, &drift))
    warps.push_back(*warp);
  if (drift && report.method != Registration_method::coherent_point_drift) warps.push_back(*drift);
  return warps;
}

/// Moves `tm`'s vertices that lie on a face by `warp`.
template <typename TriangleMesh>
void warp_template(TriangleMesh& tm, const Quadratic_warp& warp) {
  using GT = boost::graph_traits<TriangleMesh>;
  const auto vpm = get_property_map(CGAL::vertex_point, tm);
  using P = typename boost::property_traits<decltype(vpm)>::value_type;
  for (auto v : vertices(tm))
    if (halfedge(v, tm) != GT::null_halfedge()) {
      const Point_3 q = warp(point_of<TriangleMesh>(vpm, v));
      put(vpm, v, P(q.x(), q.y(), q.z()));
    }
}

/// deform_template on the inputs as they are.
template <typename TriangleMesh>
Deformation_report deform_template_unscaled(TriangleMesh& tm, const Curve_network& network,
                                            const std::vector<Correspondence>& pairs, const Deform_options& options) {
  const bool coarse_only = options.coarse_only;
  const Fine_level level = options.fine_level;
  const Curve_density density = options.curve_density;
  // The surface fine level gives every network vertex a mesh vertex and needs free vertices
  // between the curves: a template with fewer than wanted_template_vertices is subdivided
  // (before the coarse level, so that the new vertices follow the RBF rather than the chords),
  // at most three times and to at most max_subdivided_faces faces.
  std::size_t subdivisions = 0;
  // Fine_shape::template_bending (or automatic, resolved after the coarse level): the template's
  // own shape, taken before the subdivision, whose flat faces bend only at their corners and
  // edges (the vertices it adds, after the template's, take their neighbours' bending:
  // fine_on_surface). That is not what makes the dense rows worse: ico2562-superellipsoid-
  // latlong-dense10 ends 2.02 % from the truth so, 2.03 % with the subdivided template's bending.
  std::optional<Mesh_snapshot> shape;
  if (level == Fine_level::surface && options.fine_shape != Fine_shape::approach && !coarse_only)
    shape = Mesh_snapshot::of(tm, get_property_map(CGAL::vertex_point, tm));
  const bool surface_refined = level == Fine_level::surface && density == Curve_density::refine && !coarse_only;
  if (surface_refined) {
    // Before the subdivision, whose new vertices would make an out-of-range template index valid.
    check_pairs(pairs, num_vertices(tm), num_faces(tm), network);
    while (subdivisions < 3 && static_cast<double>(num_vertices(tm)) < wanted_template_vertices(network) &&
           4 * num_faces(tm) <= max_subdivided_faces) {
      subdivide_at_midpoints(tm, get_property_map(CGAL::vertex_point, tm));
      ++subdivisions;
    }
  }
  if (level == Fine_level::thesis && !coarse_only) check_fine_rbf_memory(network, options);  // before any work
  // The surface level's second start (registration.h) begins from the template as it is now.
  const auto vpm = get_property_map(CGAL::vertex_point, tm);
  std::optional<Mesh_snapshot> second_start;
  if (level == Fine_level::surface && !coarse_only && options.coarse_registration)
    second_start = Mesh_snapshot::of(tm, vpm);
  // The coarse level, then the fine level, on `m`.
  auto levels = [&](TriangleMesh& m) {
    Deformation_report coarse = deform_coarse_impl(m, network, pairs, options);
    coarse.template_subdivisions = subdivisions;
    if (coarse.orientation_reversed || coarse_only) return coarse;
    if (surface_refined) refuse_oversampled_curves(m, get_property_map(CGAL::vertex_point, m), network, subdivisions);
    // Fine_shape::automatic is resolved on the coarse surface, against the template's edges before
    // the subdivision (deform_fine_on_surface_impl resolves it the same way).
    const bool bent = shape && resolved_fine_shape(options.fine_shape, m, get_property_map(CGAL::vertex_point, m),
                                                   network, subdivisions) == Fine_shape::template_bending;
    std::vector<double> bending;  // empty unless Fine_shape::template_bending
    if (bent) bending = template_bending_after_coarse(*shape, Mesh_snapshot::of(m, get_property_map(CGAL::vertex_point, m)));
    Deformation_report fine =
        level == Fine_level::surface
            ? deform_fine_on_surface_impl(m, network, pairs, options, bent ? &bending : nullptr, subdivisions)
            : deform_fine_impl(m, network, pairs, options);
    fine.coarse_fit = coarse.coarse_fit;
    fine.coarse_seconds = coarse.coarse_seconds;
    fine.coarse_flipped_faces = coarse.coarse_flipped_faces;
    fine.orientation_reversed = coarse.orientation_reversed;
    fine.coarse_affine_determinant = coarse.coarse_affine_determinant;
    fine.template_subdivisions = subdivisions;
    return fine;
  };
  Deformation_report report = levels(tm);
  if (!second_start || report.orientation_reversed || fine_defects(report) == std::array<std::size_t, 3>{}) return report;
  // Defects left: a second start from the template warped onto the curves as a whole
  // (registered_warps), which the RBF through the pairs then finishes; when that warp came from a
  // closest-point fit and the start still leaves defects, a third from the Coherent Point Drift's
  // warp (on ico2562-onto-pig, a sphere onto 3 sections of CGAL's pig, the drift's start is clean
  // and the closest-point fit's is not). The result with the fewest defects (fine_defects' order)
  // is kept, the earlier on a tie.
  Mesh_snapshot kept = Mesh_snapshot::of(tm, vpm);
  second_start->restore(tm, vpm);
  const std::vector<Quadratic_warp> warps = registered_warps(tm, network, pairs, subdivisions, report.registration);
  for (std::size_t k = 0; k < warps.size() && fine_defects(report) != std::array<std::size_t, 3>{}; ++k) {
    if (k > 0) second_start->restore(tm, vpm);
    warp_template(tm, warps[k]);
    // A start that cannot be made (a refusal of the fine level on this start) leaves the kept
    // result; a cancel ends the call.
    Deformation_report next;
    try {
      next = levels(tm);
    } catch (const Cancelled&) {
      throw;
    } catch (const Algorithm_failure&) {
      continue;
    } catch (const Numerical_error&) {
      continue;
    }
    if (next.orientation_reversed || !(fine_defects(next) < fine_defects(report))) continue;
    next.coarse_registered = true;
    next.registered_start = k + 1;
    next.registration = report.registration;
    report = next;
    kept = Mesh_snapshot::of(tm, vpm);
  }
  kept.restore(tm, vpm);
  return report;
}

/// deform_template on `tm` itself: the mesh changes as the work goes (a cancel or a failure leaves it
/// partly changed). For meshes the pipeline owns (a Stage_copy, fit's copy).
template <typename TriangleMesh>
Deformation_report deform_template_impl(TriangleMesh& tm, const Curve_network& network,
                                    const std::vector<Correspondence>& pairs, const Deform_options& options) {
  // The template and the network are each scaled to a unit-sized box, by powers of two of their
  // own: the coarse level maps the one onto the other whatever their relative size (a template
  // in millimetres, curves in metres), and everything after it works in the network's frame.
  const auto vpm = get_property_map(CGAL::vertex_point, tm);
  const double st = internal::unit_scale(internal::checked_template_box(tm, vpm));
  const double sn = internal::unit_scale(network.bbox());
  if (st == 1 && sn == 1) return internal::deform_template_unscaled(tm, network, pairs, options);
  const Curve_network unit_network = sn == 1 ? network : internal::scaled(network, sn);
  internal::scale_points(tm, vpm, st);
  Deformation_report r;
  try {
    r = internal::deform_template_unscaled(tm, unit_network, pairs, options);
  } catch (...) {
    internal::scale_points(tm, vpm, 1 / st);
    throw;
  }
  internal::scale_points(tm, vpm, 1 / sn);
  r.largest_projection_distance /= sn;
  return r;
}
}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_DEFORM_LEVELS_H
