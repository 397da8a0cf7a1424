// The part of fit_template_to_curves that runs on meshfit's own mesh, compiled once: stages 1-3
// and the verification.
#include <meshfit/fit.h>
#include <meshfit/check.h>
#include <meshfit/internal/angle_flips.h>
#include <meshfit/internal/chain_spacing.h>
#include <meshfit/internal/fit_checks.h>
#include <meshfit/internal/unit_scale.h>
#include <meshfit/partition.h>
#include <meshfit/smooth.h>
#include <meshfit/surface_walk.h>

#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <exception>
#include <string>
#include <tuple>
#include <vector>

namespace meshfit {
namespace internal {
namespace {

std::size_t count_self_intersections(const Work_mesh& m) {
  using face_descriptor = boost::graph_traits<Work_mesh>::face_descriptor;
  std::vector<std::pair<face_descriptor, face_descriptor>> pairs;
  CGAL::Polygon_mesh_processing::self_intersections(m, std::back_inserter(pairs));
  return pairs.size();
}

// Meshes of fewer faces are tested in one piece: the threads would cost more than they save.
constexpr std::size_t parallel_self_intersection_faces = 20000;

// With the thesis level and Curve_density::drop no vertex is added for the curves, and each
// network vertex needs a template vertex of its own for its segments to become mesh edges: with
// more network vertices than template vertices the fit cannot succeed, which the counts say
// before a round of closest-point queries over every network vertex does (a 1.7 M-point
// polyline on a 2 562-vertex template: exit 3 after 65 s).
void refuse_dropping_density(const Curve_network& network, const Work_mesh& work, const Deform_options& options) {
  if (options.fine_level != Fine_level::thesis || options.curve_density != Curve_density::drop ||
      network.number_of_vertices() <= num_vertices(work))
    return;
  throw Algorithm_failure("deform",
                          "the curve density 'drop' gives each network vertex at most a template vertex of its own, "
                          "and there are " + std::to_string(network.number_of_vertices()) +
                              " network vertices but only " + std::to_string(num_vertices(work)) +
                              " template vertices: at least " +
                              std::to_string(network.number_of_vertices() - num_vertices(work)) +
                              " would be dropped and their segments could not be made mesh edges; use the "
                              "curve density 'refine' (the default) or a finer template",
                          {{"network_vertices", static_cast<double>(network.number_of_vertices())},
                           {"template_vertices", static_cast<double>(num_vertices(work))}});
}

// Stage 1 on `work` itself (its public form would copy it again); a result that reverses the
// orientation or drops network vertices ends the fit.
void deform_step(Work_mesh& work, const Curve_network& network, const std::vector<Correspondence>& pairs,
                 const Deform_options& options, Fit_report& report) {
  const auto t = std::chrono::steady_clock::now();
  report.deformation = deform_template_in_place(work, network, pairs, options);
  report.deform_seconds = seconds_since(t);
  const Deformation_report& d = report.deformation;
  if (d.orientation_reversed)
    throw Algorithm_failure("deform", orientation_reversal_message(d.coarse_affine_determinant),
                            {{"coarse_affine_determinant", d.coarse_affine_determinant},
                             {"coarse_flipped_faces", static_cast<double>(d.coarse_flipped_faces)}});
  if (!d.dropped_network_vertices.empty())
    throw Algorithm_failure("deform", std::to_string(d.dropped_network_vertices.size()) +
                                          " network vertices have no mesh vertex of their own, so their segments "
                                          "cannot be made mesh edges",
                            {{"dropped_network_vertices", static_cast<double>(d.dropped_network_vertices.size())}});
}

// Stage 3 with the curve edges and the network vertices held, then the needles smoothing leaves
// mended.
void smooth_step(Work_mesh& work, const Curve_network& network, const Fit_options& options, Work_edge_flags curve,
                 Fit_report& report) {
  const auto t = std::chrono::steady_clock::now();
  const auto wvpm = get(CGAL::vertex_point, work);
  // Network vertices stay where they are even when a segment of theirs is not a chain of edges.
  auto pinned = get(CGAL::dynamic_vertex_property_t<bool>(), work);
  {
    std::vector<bool> is_network(num_vertices(work), false);
    for (std::size_t k : report.mesh_vertex_of_network_vertex) is_network[k] = true;
    std::size_t i = 0;
    for (auto w : vertices(work)) put(pinned, w, bool(is_network[i++]));
  }
  if (options.mean_curvature_iterations + options.laplacian_iterations > 0)
    report.smoothing = smooth_fitted_mesh(work, parameters::mean_curvature_iterations(options.mean_curvature_iterations)
                                                    .laplacian_iterations(options.laplacian_iterations)
                                                    .step_size(options.step)
                                                    .smoothing_tolerance(options.smoothing_tolerance)
                                                    .progress(options.deform.progress)
                                                    .edge_is_constrained_map(curve)
                                                    .vertex_is_constrained_map(pinned));
  // Curve vertices bunched along a segment make needles that smoothing leaves: they are spaced
  // out along their segments first.
  report.chain_vertex_moves =
      space_chain_vertices(work, wvpm, curve, network, report.mesh_vertex_of_network_vertex, network.tolerance());
  // Needles that no vertex motion can mend (a free vertex between two close curve vertices, or
  // two free vertices pressed together) go by flipping edges where the surface is nearly flat.
  report.angle_flips = flip_for_angles(work, wvpm, curve, 20 * CGAL_PI / 180);
  report.smooth_seconds = seconds_since(t);
}

// The verification (Fit_verification) of the result in `work`, against the template's own folds
// and, when the result intersects itself, the template's intersections.
void verify_fit(const Work_mesh& work, const Mesh_data& template_data, const Curve_network& network,
                Work_edge_flags curve, std::size_t template_folded_edges, bool check_self_intersections,
                Fit_report& report) {
  const auto t = std::chrono::steady_clock::now();
  const auto wvpm = get(CGAL::vertex_point, work);
  Fit_verification& v = report.verification;
  std::vector<Work_mesh::Vertex_index> vertex_of;
  for (auto w : vertices(work)) vertex_of.push_back(w);
  v.network_vertices = network.number_of_vertices();
  for (std::size_t k = 0; k < network.number_of_vertices(); ++k)
    if (get(wvpm, vertex_of[report.mesh_vertex_of_network_vertex[k]]) != network.point(k)) ++v.network_vertices_missing;
  v.segments = network.number_of_segments();
  // Vertices moved onto a segment lie on it up to rounding: within the network's merge tolerance.
  const double tolerance = network.tolerance();
  for (const auto& s : network.segments()) {
    const auto a = vertex_of[report.mesh_vertex_of_network_vertex[s[0]]], b = vertex_of[report.mesh_vertex_of_network_vertex[s[1]]];
    if (segment_edge_chain(work, wvpm, curve, a, b, tolerance).size() < 2) ++v.segments_not_chains;
  }
  v.flips_remaining = report.deformation.remaining_flips;
  v.regions = report.partition.regions;
  if (const auto expected = expected_regions(work, network, curve)) {
    v.expected_regions_known = true;
    v.expected_regions = *expected;
  }
  std::tie(v.folded_edges, v.degenerate_faces) = folded_and_degenerate(work, wvpm);
  v.template_folded_edges = template_folded_edges;
  for (auto w : vertices(work)) {
    const auto& p = get(wvpm, w);
    v.non_finite_coordinates += !(std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()));
  }
  if (check_self_intersections && v.non_finite_coordinates == 0) {
    v.self_intersection_checked = true;
    const std::size_t slabs =
        num_faces(work) < parallel_self_intersection_faces ? 1 : static_cast<std::size_t>(omp_get_max_threads());
    v.self_intersects = does_self_intersect_in_slabs(work, slabs);
    if (v.self_intersects) {  // did the template have them already? (its mesh made again only then)
      Work_mesh template_mesh;
      build_triangle_mesh(template_data, template_mesh);
      v.template_self_intersecting_pairs = count_self_intersections(template_mesh);
      v.template_self_intersects = v.template_self_intersecting_pairs > 0;
      if (v.template_self_intersects) v.self_intersecting_pairs = count_self_intersections(work);
    }
  }
  report.verify_seconds = seconds_since(t);
}

}  // namespace

bool does_self_intersect_in_slabs(const Work_mesh& tm, std::size_t slabs) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  if (slabs <= 1 || num_faces(tm) < 2 * slabs) return PMP::does_self_intersect(tm);
  CGAL::Bbox_3 box;
  for (auto v : vertices(tm)) box += tm.point(v).bbox();
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (box.max(a) - box.min(a) > box.max(axis) - box.min(axis)) axis = a;
  // Each face's extent along the axis, and the quantiles of its centres (twice the centres: the
  // sum of the extent's ends, halved once at the end).
  std::vector<std::array<double, 2>> extent;
  std::vector<Work_mesh::Face_index> face_of;
  extent.reserve(num_faces(tm));
  face_of.reserve(num_faces(tm));
  for (auto f : faces(tm)) {
    const auto h = halfedge(f, tm);
    const double a = tm.point(source(h, tm))[axis], b = tm.point(target(h, tm))[axis],
                 c = tm.point(target(next(h, tm), tm))[axis];
    extent.push_back({std::min({a, b, c}), std::max({a, b, c})});
    face_of.push_back(f);
  }
  std::vector<double> centre(extent.size());
  for (std::size_t i = 0; i < extent.size(); ++i) centre[i] = extent[i][0] + extent[i][1];
  std::vector<double> q(slabs + 1);
  q.front() = -HUGE_VAL;
  q.back() = HUGE_VAL;
  for (std::size_t i = 1; i < slabs; ++i) {
    const auto at = centre.begin() + static_cast<std::ptrdiff_t>(centre.size() * i / slabs);
    std::nth_element(centre.begin(), at, centre.end());
    q[i] = *at / 2;
  }
  std::vector<std::vector<Work_mesh::Face_index>> slab(slabs);
  for (std::size_t f = 0; f < extent.size(); ++f)
    for (std::size_t i = 0; i < slabs; ++i)
      if (extent[f][1] >= q[i] && extent[f][0] <= q[i + 1]) slab[i].push_back(face_of[f]);
  std::vector<char> intersects(slabs, 0);
  std::exception_ptr failure;
#pragma omp parallel for schedule(dynamic, 1) num_threads(static_cast<int>(slabs))
  for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(slabs); ++i) {
    try {
      intersects[i] = PMP::does_self_intersect(slab[i], tm);
    } catch (...) {
#pragma omp critical(meshfit_self_intersection_failure)
      failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);
  return std::find(intersects.begin(), intersects.end(), 1) != intersects.end();
}

void fit_work(const Mesh_data& template_data, const Curve_network& network, const std::vector<Correspondence>& pairs,
              const Fit_options& options, double unit, Fit_report& report, Work_mesh& work, Mesh_data& result) {
  build_triangle_mesh(template_data, work);
  // What the template had before the stages: the verification counts only what they made (the
  // template scaled by a power of two, which no predicate sees).
  const std::size_t template_folded_edges = folded_and_degenerate(work, get(CGAL::vertex_point, work)).first;
  refuse_dropping_density(network, work, options.deform);

  deform_step(work, network, pairs, options.deform, report);

  const auto t = std::chrono::steady_clock::now();
  auto curve = get(CGAL::dynamic_edge_property_t<bool>(), work);
  auto region = get(CGAL::dynamic_face_property_t<std::size_t>(), work);
  report.partition = partition_work(work, network, options.deform.progress, curve, nullptr, &region);
  report.partition_seconds = seconds_since(t);
  report.mesh_vertex_of_network_vertex = report.partition.mesh_vertex_of_network_vertex;

  smooth_step(work, network, options, curve, report);

  report_progress(options.deform.progress, "fit", "verifying the result", 0, 1);
  verify_fit(work, template_data, network, curve, template_folded_edges, options.check_self_intersections, report);
  report.vertices = num_vertices(work);
  report.faces = num_faces(work);

  // The result, in the network's frame: the caller writes it into its mesh.
  result = to_mesh_data(work, CGAL::parameters::edge_is_constrained_map(curve).face_patch_map(region));
  report.minimum_angle_deg = minimum_angle_degrees(result);
  for (Point_3& p : result.points) p = scaled(p, 1 / unit);
  report.deformation.largest_projection_distance /= unit;
  report.smoothing.mean_displacement /= unit;
  report.smoothing.max_displacement /= unit;
  report.smoothing.last_step_max_displacement /= unit;
}

}  // namespace internal
}  // namespace meshfit
