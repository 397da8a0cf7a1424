// meshfit internal: the front end of stage 3 (smooth.h): the named parameters read into the
// settings of a flow, the mesh copied into the arrays of the compiled core (src/smooth.cpp, where
// the flows themselves are) and written back.
#ifndef MESHFIT_INTERNAL_SMOOTH_IMPL_H
#define MESHFIT_INTERNAL_SMOOTH_IMPL_H

// Included by smooth.h after its types (Smoothing_report, the flow enums), not on its own.
#include <meshfit/internal/format_number.h>
#include <meshfit/internal/triangle_corners.h>

#include <CGAL/Dynamic_property_map.h>
#include <CGAL/boost/graph/iterator.h>
#include <CGAL/boost/graph/named_params_helper.h>

namespace meshfit {
namespace internal {

/// Which flow the core runs.
enum class Flow_kind { laplacian, mean_curvature, modified_mean_curvature, modified_laplacian };

/// The mesh as the compiled core sees it. `points` holds x y z per vertex and receives the result.
struct Smoothing_arrays {
  std::vector<double> points;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<unsigned char> fixed;  ///< per vertex; 1: never moves
  std::vector<std::array<std::uint32_t, 2>> constrained_edges;  ///< the projection walks never cross them
  /// Positions (x y z per vertex) of the reference surface of the modified Laplacian flow; empty:
  /// the positions at the start of the flow.
  std::vector<double> reference_points;
  /// Positions (x y z per vertex) against which the flip guard also judges faces; empty: the
  /// positions at the start of the flow (smooth_fitted_mesh sets them so that its two phases together
  /// reverse no face of the input).
  std::vector<double> orientation_points;
};

// The defaults of stage 3's counts, written here only: the functions read them, and the reference
// (Doxygen) shows them through aliases that CMake reads from this file (cmake/meshfit_doc_defaults.cmake).
/// smooth_fitted_mesh's iterations in all when `number_of_iterations` is not given.
constexpr std::size_t default_smoothing_iterations = 100;
/// smooth_fitted_mesh's `smoothing_tolerance` when it is not given: a phase ends after an
/// iteration that moves no vertex farther than this times the mean edge length. On four battery
/// cases (dense10 bumpy and superellipsoid, 2562- and 10 242-vertex lat/long) the smallest angle
/// and its 5th percentile change by less than 0.6 degrees between 20 and 100 iterations; on the
/// 81 920-face scale case the largest move falls below a hundredth of an edge after 3 mean
/// curvature and 39 Laplacian iterations (the full battery: same passes, angles within 0.4
/// degrees but one 1.4 higher, Hausdorff within 0.03 % of the diagonal).
constexpr double default_smoothing_tolerance = 0.01;
/// laplacian_flow's `number_of_iterations` when it is not given.
constexpr std::size_t default_laplacian_flow_iterations = 20;
/// mean_curvature_flow's.
constexpr std::size_t default_mean_curvature_flow_iterations = 60;
/// modified_mean_curvature_flow's.
constexpr std::size_t default_modified_mean_curvature_flow_iterations = 50;
/// modified_laplacian_flow's.
constexpr std::size_t default_modified_laplacian_flow_iterations = 50;

/// A flow's settings, with their defaults (flow_settings reads the named parameters into them).
struct Flow_settings {
  Flow_kind kind = Flow_kind::laplacian;
  std::size_t iterations = 0;
  double step = 1;
  Laplacian_weights weights = Laplacian_weights::uniform;
  Laplacian_variant variant = Laplacian_variant::none;
  double alpha = 0.5;
  /// The run ends after an iteration that moves no vertex farther than this times the mean edge
  /// length (0: never; smooth_fitted_mesh's smoothing_tolerance).
  double stop_below = 0;
  /// Called before iteration `index` (0-based) of `total`; returning false cancels.
  std::function<bool(std::size_t index, std::size_t total)> on_iteration;
  std::size_t progress_offset = 0, progress_total = 0;  ///< smooth_fitted_mesh numbers both phases together
};

/// The compiled core (src/smooth.cpp): runs the flow on the arrays, in place. The report's
/// counters are added to `report` (iterations included); displacements are not filled in.
/// \throws Algorithm_failure("smooth", …) when `on_iteration` returns false (the arrays are then
///         partly smoothed: the front ends write back only after a complete run);
///         Numerical_error if a position became non-finite (the guards are meant to prevent it).
void run_flow(Smoothing_arrays& mesh, const Flow_settings& settings, Smoothing_report& report);

/// run_flow for each of `flows` in turn, on one copy of the connectivity and one set of work arrays.
void run_flows(Smoothing_arrays& mesh, const std::vector<Flow_settings>& flows, Smoothing_report& report);

/// Checks the arrays (finite coordinates, indices in range, no repeated corner).
/// \throws Invalid_input naming the vertex or face.
void check_smoothing_input(const Smoothing_arrays& mesh);

/// Fills mean_displacement and max_displacement from the positions before and after.
void fill_displacements(const std::vector<double>& before, const std::vector<double>& after,
                        Smoothing_report& report);

template <typename NamedParameters>
std::size_t iterations_parameter(const NamedParameters& np, std::size_t fallback) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  return non_negative_count(choose_parameter(get_parameter(np, CGAL::internal_np::number_of_iterations), fallback),
                            "smooth", "number_of_iterations");
}

/// The iterations of smooth_fitted_mesh's two phases: `number_of_iterations` (default 100) split
/// one fifth modified mean curvature, the rest modified Laplacian, unless
/// `mean_curvature_iterations` or `laplacian_iterations` give a phase's own count.
/// \throws Invalid_input for a negative count.
struct Smoothing_phases {
  std::size_t mean_curvature = 0, laplacian = 0;
};
template <typename NamedParameters>
Smoothing_phases smoothing_phases(const NamedParameters& np) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  const std::size_t total = iterations_parameter(np, default_smoothing_iterations);
  return {non_negative_count(choose_parameter(get_parameter(np, meshfit::internal_np::mean_curvature_iterations), total / 5),
                             "smooth", "mean_curvature_iterations"),
          non_negative_count(
              choose_parameter(get_parameter(np, meshfit::internal_np::laplacian_iterations), total - total / 5),
              "smooth", "laplacian_iterations")};
}

/// smooth_fitted_mesh's `smoothing_tolerance`.
/// \throws Invalid_input when it is negative or not finite.
template <typename NamedParameters>
double smoothing_tolerance(const NamedParameters& np) {
  const double t = CGAL::parameters::choose_parameter(
      CGAL::parameters::get_parameter(np, meshfit::internal_np::smoothing_tolerance), default_smoothing_tolerance);
  if (!(std::isfinite(t) && t >= 0))
    throw Invalid_input("smooth: smoothing_tolerance must be finite and not negative, not " + internal::format_number(t));
  return t;
}

template <typename NamedParameters>
Flow_settings flow_settings(const NamedParameters& np, Flow_kind kind, std::size_t default_iterations) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  Flow_settings s;
  s.kind = kind;
  s.iterations = iterations_parameter(np, default_iterations);
  s.step = choose_parameter(get_parameter(np, meshfit::internal_np::step_size), s.step);
  if (!(s.step > 0 && s.step <= 1))
    throw Invalid_input("smooth: step_size (lambda) must be in (0, 1], not " + std::to_string(s.step));
  s.weights = choose_parameter(get_parameter(np, meshfit::internal_np::laplacian_weights), s.weights);
  s.variant = choose_parameter(get_parameter(np, meshfit::internal_np::laplacian_variant), s.variant);
  s.alpha = choose_parameter(get_parameter(np, meshfit::internal_np::laplacian_alpha), s.alpha);
  if (!(s.alpha >= 0 && s.alpha <= 1))
    throw Invalid_input("smooth: laplacian_alpha must be in [0, 1], not " + internal::format_number(s.alpha));
  auto progress = get_parameter(np, meshfit::internal_np::progress);
  if constexpr (!std::is_same_v<decltype(progress), CGAL::internal_np::Param_not_found>) {
    s.on_iteration = [progress](std::size_t index, std::size_t total) {
      return call_progress(progress, Progress_step{"smooth", "iteration", index, total});
    };
  }
  return s;
}

/// The mesh in flat arrays, with the vertex descriptors in the order of vertices(tm).
template <typename TriangleMesh, typename NamedParameters>
struct Smoothing_front_end {
  using GT = boost::graph_traits<TriangleMesh>;
  using vertex_descriptor = typename GT::vertex_descriptor;

  TriangleMesh& tm;
  // A copy of the map (decayed: choose_parameter returns a reference to get_parameter's temporary
  // when the caller gives a vertex_point_map).
  std::decay_t<decltype(CGAL::parameters::choose_parameter(
      CGAL::parameters::get_parameter(std::declval<const NamedParameters&>(), CGAL::internal_np::vertex_point),
      get_property_map(CGAL::vertex_point, std::declval<TriangleMesh&>())))> vpm;
  std::vector<vertex_descriptor> vertex;
  Smoothing_arrays arrays;

  Smoothing_front_end(TriangleMesh& m, const NamedParameters& np)
      : tm(m),
        vpm(CGAL::parameters::choose_parameter(CGAL::parameters::get_parameter(np, CGAL::internal_np::vertex_point),
                                               get_property_map(CGAL::vertex_point, m))) {
    using CGAL::parameters::get_parameter;
    static_cast<void>(sizeof(Kernel_check<typename boost::property_traits<decltype(vpm)>::value_type, NamedParameters>));
    auto index = get(CGAL::dynamic_vertex_property_t<std::size_t>(), tm);
    vertex.reserve(num_vertices(tm));
    arrays.points.reserve(3 * num_vertices(tm));
    for (auto v : vertices(tm)) {
      put(index, v, vertex.size());
      vertex.push_back(v);
      const auto& p = get(vpm, v);
      arrays.points.insert(arrays.points.end(), {double(p.x()), double(p.y()), double(p.z())});
    }
    if (vertex.size() >= std::size_t(UINT32_MAX))
      throw Invalid_input("smooth: more than 2^32 - 1 vertices are not supported");
    arrays.fixed.assign(vertex.size(), 0);
    arrays.triangles.reserve(num_faces(tm));
    for (auto f : faces(tm)) {
      const auto c = triangle_corners(f, tm, index);
      arrays.triangles.push_back({std::uint32_t(c[0]), std::uint32_t(c[1]), std::uint32_t(c[2])});
    }
    for (std::size_t i = 0; i < vertex.size(); ++i)
      if (CGAL::is_border(vertex[i], tm)) arrays.fixed[i] = 1;
    auto vcm = get_parameter(np, CGAL::internal_np::vertex_is_constrained);
    if constexpr (!std::is_same_v<decltype(vcm), CGAL::internal_np::Param_not_found>) {
      for (std::size_t i = 0; i < vertex.size(); ++i)
        if (get(vcm, vertex[i])) arrays.fixed[i] = 1;
    }
    auto ecm = get_parameter(np, CGAL::internal_np::edge_is_constrained);
    if constexpr (!std::is_same_v<decltype(ecm), CGAL::internal_np::Param_not_found>) {
      for (auto e : edges(tm))
        if (get(ecm, e)) {
          const std::uint32_t a = std::uint32_t(get(index, source(e, tm))), b = std::uint32_t(get(index, target(e, tm)));
          arrays.fixed[a] = arrays.fixed[b] = 1;
          arrays.constrained_edges.push_back({a, b});
        }
    }
    auto ref = get_parameter(np, meshfit::internal_np::reference_points);
    if constexpr (!std::is_same_v<decltype(ref), CGAL::internal_np::Param_not_found>) {
      if (ref.size() != vertex.size())
        throw Invalid_input("smooth: reference_points has " + std::to_string(ref.size()) + " points for " +
                            std::to_string(vertex.size()) + " vertices");
      arrays.reference_points.reserve(3 * ref.size());
      for (const auto& p : ref) arrays.reference_points.insert(arrays.reference_points.end(), {double(p.x()), double(p.y()), double(p.z())});
    }
    check_smoothing_input(arrays);
  }

  void write_back() {
    using P = typename boost::property_traits<decltype(vpm)>::value_type;
    for (std::size_t i = 0; i < vertex.size(); ++i)
      put(vpm, vertex[i], P(arrays.points[3 * i], arrays.points[3 * i + 1], arrays.points[3 * i + 2]));
  }
  std::size_t fixed_count() const {
    std::size_t n = 0;
    for (unsigned char f : arrays.fixed) n += f;
    return n;
  }
};

template <typename TriangleMesh, typename NamedParameters>
Smoothing_report run_single_flow(TriangleMesh& tm, const NamedParameters& np, Flow_kind kind,
                                 std::size_t default_iterations) {
  const auto t0 = std::chrono::steady_clock::now();
  Flow_settings settings = flow_settings(np, kind, default_iterations);
  const Scoped_number_of_threads threads(threads_of(np, "smooth"));
  Smoothing_front_end<TriangleMesh, NamedParameters> fe(tm, np);
  Smoothing_report report;
  report.vertices = fe.vertex.size();
  report.fixed_vertices = fe.fixed_count();
  const std::vector<double> before = fe.arrays.points;
  run_flow(fe.arrays, settings, report);
  fill_displacements(before, fe.arrays.points, report);
  fe.write_back();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_SMOOTH_IMPL_H
