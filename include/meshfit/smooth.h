// meshfit: stage 3, smoothing the fitted mesh without shrinking it and without moving the curves
// (thesis ch. 4, "Mesh smoothing algorithm").
//
//   laplacian_flow                eq. 4.1–4.6  umbrella operator, uniform or inverse-distance
//                                              weights, optionally Vollmer's α variants
//   mean_curvature_flow           eq. 4.7–4.8  cotangent weights, area normalisation
//   modified_mean_curvature_flow  eq. 4.9, 4.12  the step is projected onto the previous
//                                              iteration's surface
//   modified_laplacian_flow       eq. 4.10, 4.11, 4.13  the step is projected onto the surface
//                                              before smoothing (each vertex stays on it)
//   smooth_fitted_mesh            §4.3: modified mean curvature, then modified Laplacian
//
// Every function works on any triangle mesh (`TriangleMesh`, a model of FaceListGraph with a
// vertex point map of 3D points), never changes its connectivity, and returns a
// Smoothing_report. The iterations are Jacobi steps: every new position is computed from the
// positions of the previous iteration, so the result does not depend on vertex order or on the
// number of threads.
//
// Fixed vertices (thesis §4.3.3, eq. 4.12/4.13: p^{k+1} = p^0 for p in V_f): a vertex is never
// moved when the caller's `vertex_is_constrained_map` says so, when it lies on the mesh boundary
// (an open template keeps its rim), or when it is incident to an edge of the caller's
// `edge_is_constrained_map` (a curve edge). The thesis fixes every vertex of the curves, inner
// curve vertices included, and so does meshfit: curves keep their exact polylines, and since
// connectivity never changes, curve edges stay edges. The projections of the modified flows also
// never carry a vertex across a curve edge, so every vertex stays in its region.
// How the flows are computed (the guards, the walk on the reference surface): src/smooth.cpp.
#ifndef MESHFIT_SMOOTH_H
#define MESHFIT_SMOOTH_H

#include <meshfit/exceptions.h>
#include <meshfit/internal/stage_support.h>
#include <meshfit/kernel.h>
#include <meshfit/parameters.h>

#include <CGAL/Named_function_parameters.h>
#include <CGAL/boost/graph/helpers.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

namespace meshfit {

/// The weights w_i of the umbrella operator (eq. 4.2).
enum class Laplacian_weights {
  uniform,          ///< w_i = 1 (eq. 4.3, and eq. 4.10 of the modified flow). Default.
  inverse_distance  ///< w_i = 1 / |p^k − q_i| (eq. 4.4)
};

/// Vollmer's variants of the Laplacian flow (eq. 4.5, 4.6), which replace eq. 4.1. Both include
/// the vertex itself in the weighted average (q_0 = p^k, with weight 1 for uniform weights and
/// the mean of the neighbours' weights for inverse-distance weights, since 1/|p^k − p^k| is not
/// defined); α is the named parameter `laplacian_alpha`, and λ is not used.
enum class Laplacian_variant {
  none,              ///< eq. 4.1: p^{k+1} = p^k + λ Δ(p^k). Default.
  alpha_current,     ///< eq. 4.5: p^{k+1} = α p^k + (1 − α) Σ_{i≥0} w_i q_i / Σ_{i≥0} w_i
  alpha_original     ///< eq. 4.6: p^{k+1} = α p^0 + (1 − α) Σ_{i≥0} w_i q_i / Σ_{i≥0} w_i
};

/// What a smoothing call did.
struct Smoothing_report {
  std::size_t iterations = 0;             ///< iterations run (both phases for smooth_fitted_mesh)
  /// smooth_fitted_mesh: the most iterations of the first phase (fewer are run when
  /// smoothing_tolerance ends it: `iterations` counts those run)
  std::size_t mean_curvature_iterations = 0;
  std::size_t laplacian_iterations = 0;  ///< smooth_fitted_mesh: the most iterations of the second phase
  std::size_t vertices = 0;               ///< vertices of the mesh
  std::size_t fixed_vertices = 0;         ///< never moved (constrained, boundary, curve vertices)
  double mean_displacement = 0;           ///< mean over all vertices of |p_final − p_initial|
  double max_displacement = 0;            ///< largest |p_final − p_initial|
  double last_step_max_displacement = 0;  ///< largest move in the last iteration (convergence)
  double seconds = 0;                     ///< time of the call
  std::size_t steps_reduced = 0;    ///< vertex steps halved because a face would flip (all iterations)
  std::size_t steps_cancelled = 0;  ///< of those, steps set to zero after 4 halvings
  std::size_t clamped_cotangents = 0;  ///< cotangent weights bounded by cot(1°) (needles, zero-area faces)
  std::size_t projections_clamped = 0;  ///< projections ended at a face's closest point (ridge, curve, boundary)
};

}  // namespace meshfit

#include <meshfit/internal/smooth_impl.h>

namespace meshfit {

/// Laplacian flow (eq. 4.1–4.4): p^{k+1} = p^k + λ Δ(p^k), Δ the umbrella operator with
/// `laplacian_weights` (uniform, eq. 4.3, default; inverse distance, eq. 4.4); with
/// `laplacian_variant` alpha_current or alpha_original, Vollmer's eq. 4.5 or 4.6 instead (α from
/// `laplacian_alpha`, default 0.5). Shrinks the shape (that is the thesis's point).
/// Fixed vertices, flip guard: see the top of this file.
/// \pre `tm` is a triangle mesh.
/// \tparam TriangleMesh a model of `FaceListGraph` whose faces are triangles (tested:
///         CGAL::Surface_mesh, CGAL::Polyhedron_3)
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param tm the mesh, smoothed in place (its connectivity does not change)
/// \param np an optional sequence of named parameters among the ones listed below
/// \return what the flow did (Smoothing_report)
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{number_of_iterations}
///     \cgalParamDescription{the number of iterations}
///     \cgalParamType{an integer type}
///     \cgalParamDefault{\default_laplacian_flow_iterations}
///     \cgalParamExtra{A negative value throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{step_size}
///     \cgalParamDescription{the step λ (of the umbrella operator, or of λ h̄² for the mean curvature, h̄ the mean edge
///       length at the call)}
///     \cgalParamType{`double` in (0, 1]}
///     \cgalParamDefault{\default_flow_step}
///     \cgalParamExtra{A value outside (0, 1] throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{laplacian_weights}
///     \cgalParamDescription{the weights of the umbrella operator (eq. 4.3 or 4.4)}
///     \cgalParamType{meshfit::Laplacian_weights}
///     \cgalParamDefault{\default_flow_weights}
///   \cgalParamNEnd
///   \cgalParamNBegin{laplacian_variant}
///     \cgalParamDescription{Vollmer's variant (eq. 4.5, 4.6) instead of eq. 4.1}
///     \cgalParamType{meshfit::Laplacian_variant}
///     \cgalParamDefault{\default_flow_variant}
///   \cgalParamNEnd
///   \cgalParamNBegin{laplacian_alpha}
///     \cgalParamDescription{α of the variants}
///     \cgalParamType{`double` in [0, 1]}
///     \cgalParamDefault{\default_flow_alpha}
///     \cgalParamExtra{A value outside [0, 1] throws meshfit::Invalid_input (checked by every flow).}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_is_constrained_map}
///     \cgalParamDescription{input: vertices that must not move}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: no vertex is constrained by the caller}
///     \cgalParamExtra{Boundary vertices and the vertices of constrained edges never move either.}
///   \cgalParamNEnd
///   \cgalParamNBegin{edge_is_constrained_map}
///     \cgalParamDescription{input: the curve edges; their vertices do not move, and the projections of the modified
///       flows never cross them}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%edge_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: no edge is constrained}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `ReadWritePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///       meshfit::Point_3 as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for `CGAL::vertex_point_t` must be
///       available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{progress}
///     \cgalParamDescription{a callback called at each step with a meshfit::Progress_step (stage `"smooth"`)}
///     \cgalParamType{a callable taking `const meshfit::Progress_step&` and returning `bool` (`false` cancels) or
///       `void` (never cancels)}
///     \cgalParamDefault{none: no calls, no cancelling}
///     \cgalParamExtra{One call per iteration. When it returns `false`, the flow throws meshfit::Algorithm_failure and
///       `tm` is unchanged.}
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
/// \cgalNamedParamsEnd///
/// \throws Invalid_input for a face that is not a triangle, a non-finite coordinate, λ outside
///         (0, 1], α outside [0, 1] or a negative iteration count.
/// \throws Algorithm_failure when the progress callback returns false (`tm` is then unchanged).
/// \throws Numerical_error if a position became non-finite (the guards are meant to prevent it).
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Smoothing_report laplacian_flow(TriangleMesh& tm, const NamedParameters& np = CGAL::parameters::default_values()) {
  return internal::run_single_flow(tm, np, internal::Flow_kind::laplacian, internal::default_laplacian_flow_iterations);
}

/// Mean-curvature flow (eq. 4.7–4.8): p^{k+1} = p^k + τ H(p^k), H = Σ (cot α_i + cot β_i)(q_i − p^k)
/// / (4A), A the area of the faces around p^k, τ = λ h̄² (h̄ the mean edge length at the call),
/// bounded per vertex as described at the top of this file (cotangents clamped at 1°, zero area
/// → no motion). The Laplacian weights and variants do not apply.
/// \tparam TriangleMesh a model of `FaceListGraph` whose faces are triangles (tested:
///         CGAL::Surface_mesh, CGAL::Polyhedron_3)
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param tm the mesh, smoothed in place (its connectivity does not change)
/// \param np an optional sequence of named parameters among the ones listed below
/// \return what the flow did (Smoothing_report)
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{number_of_iterations}
///     \cgalParamDescription{the number of iterations}
///     \cgalParamType{an integer type}
///     \cgalParamDefault{\default_mean_curvature_flow_iterations}
///     \cgalParamExtra{A negative value throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{step_size}
///     \cgalParamDescription{the step λ (of the umbrella operator, or of λ h̄² for the mean curvature, h̄ the mean edge
///       length at the call)}
///     \cgalParamType{`double` in (0, 1]}
///     \cgalParamDefault{\default_flow_step}
///     \cgalParamExtra{A value outside (0, 1] throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_is_constrained_map}
///     \cgalParamDescription{input: vertices that must not move}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: no vertex is constrained by the caller}
///     \cgalParamExtra{Boundary vertices and the vertices of constrained edges never move either.}
///   \cgalParamNEnd
///   \cgalParamNBegin{edge_is_constrained_map}
///     \cgalParamDescription{input: the curve edges; their vertices do not move, and the projections of the modified
///       flows never cross them}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%edge_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: no edge is constrained}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `ReadWritePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///       meshfit::Point_3 as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for `CGAL::vertex_point_t` must be
///       available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{progress}
///     \cgalParamDescription{a callback called at each step with a meshfit::Progress_step (stage `"smooth"`)}
///     \cgalParamType{a callable taking `const meshfit::Progress_step&` and returning `bool` (`false` cancels) or
///       `void` (never cancels)}
///     \cgalParamDefault{none: no calls, no cancelling}
///     \cgalParamExtra{One call per iteration. When it returns `false`, the flow throws meshfit::Algorithm_failure and
///       `tm` is unchanged.}
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
/// \cgalNamedParamsEnd///
/// \throws Invalid_input for a face that is not a triangle, a non-finite coordinate, λ outside
///         (0, 1], α outside [0, 1] or a negative iteration count.
/// \throws Algorithm_failure when the progress callback returns false (`tm` is then unchanged).
/// \throws Numerical_error if a position became non-finite (the guards are meant to prevent it).
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Smoothing_report mean_curvature_flow(TriangleMesh& tm, const NamedParameters& np = CGAL::parameters::default_values()) {
  return internal::run_single_flow(tm, np, internal::Flow_kind::mean_curvature,
                                   internal::default_mean_curvature_flow_iterations);
}

/// Modified mean-curvature flow (eq. 4.9, 4.12): the mean-curvature step of mean_curvature_flow,
/// projected onto the surface of the previous iteration (the walk described at the top of this
/// file): vertices slide on the previous surface, which removes noise while shrinking far less.
/// The Laplacian weights and variants do not apply.
/// \tparam TriangleMesh a model of `FaceListGraph` whose faces are triangles (tested:
///         CGAL::Surface_mesh, CGAL::Polyhedron_3)
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param tm the mesh, smoothed in place (its connectivity does not change)
/// \param np an optional sequence of named parameters among the ones listed below
/// \return what the flow did (Smoothing_report)
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{number_of_iterations}
///     \cgalParamDescription{the number of iterations}
///     \cgalParamType{an integer type}
///     \cgalParamDefault{\default_modified_mean_curvature_flow_iterations}
///     \cgalParamExtra{A negative value throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{step_size}
///     \cgalParamDescription{the step λ (of the umbrella operator, or of λ h̄² for the mean curvature, h̄ the mean edge
///       length at the call)}
///     \cgalParamType{`double` in (0, 1]}
///     \cgalParamDefault{\default_flow_step}
///     \cgalParamExtra{A value outside (0, 1] throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_is_constrained_map}
///     \cgalParamDescription{input: vertices that must not move}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: no vertex is constrained by the caller}
///     \cgalParamExtra{Boundary vertices and the vertices of constrained edges never move either.}
///   \cgalParamNEnd
///   \cgalParamNBegin{edge_is_constrained_map}
///     \cgalParamDescription{input: the curve edges; their vertices do not move, and the projections of the modified
///       flows never cross them}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%edge_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: no edge is constrained}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `ReadWritePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///       meshfit::Point_3 as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for `CGAL::vertex_point_t` must be
///       available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{progress}
///     \cgalParamDescription{a callback called at each step with a meshfit::Progress_step (stage `"smooth"`)}
///     \cgalParamType{a callable taking `const meshfit::Progress_step&` and returning `bool` (`false` cancels) or
///       `void` (never cancels)}
///     \cgalParamDefault{none: no calls, no cancelling}
///     \cgalParamExtra{One call per iteration. When it returns `false`, the flow throws meshfit::Algorithm_failure and
///       `tm` is unchanged.}
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
/// \cgalNamedParamsEnd///
/// \throws Invalid_input for a face that is not a triangle, a non-finite coordinate, λ outside
///         (0, 1], α outside [0, 1] or a negative iteration count.
/// \throws Algorithm_failure when the progress callback returns false (`tm` is then unchanged).
/// \throws Numerical_error if a position became non-finite (the guards are meant to prevent it).
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Smoothing_report modified_mean_curvature_flow(TriangleMesh& tm,
                                              const NamedParameters& np = CGAL::parameters::default_values()) {
  return internal::run_single_flow(tm, np, internal::Flow_kind::modified_mean_curvature,
                                   internal::default_modified_mean_curvature_flow_iterations);
}

/// Modified Laplacian flow (eq. 4.10, 4.11, 4.13): the umbrella step λ Δ(p^k) (uniform weights,
/// eq. 4.10, unless `laplacian_weights` says otherwise) projected onto the reference surface,
/// which is the mesh as it is at the call (the thesis's p^0 surface), or, with the named
/// parameter `reference_points` (a std::vector<Point_3>, one point per vertex in the order of
/// vertices(tm)), `tm`'s connectivity at those positions. Every free vertex ends each iteration
/// on the reference surface (eq. 4.11 writes p^0 + projected Δ(p^k); the text and fig. 4.12 put
/// p^{k+1} on the face of the original surface, which is what is done: p^k + projected step,
/// landing on that face). Evens out the triangles without changing the shape. The variants do
/// not apply.
/// \tparam TriangleMesh a model of `FaceListGraph` whose faces are triangles (tested:
///         CGAL::Surface_mesh, CGAL::Polyhedron_3)
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param tm the mesh, smoothed in place (its connectivity does not change)
/// \param np an optional sequence of named parameters among the ones listed below
/// \return what the flow did (Smoothing_report)
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{number_of_iterations}
///     \cgalParamDescription{the number of iterations}
///     \cgalParamType{an integer type}
///     \cgalParamDefault{\default_modified_laplacian_flow_iterations}
///     \cgalParamExtra{A negative value throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{step_size}
///     \cgalParamDescription{the step λ (of the umbrella operator, or of λ h̄² for the mean curvature, h̄ the mean edge
///       length at the call)}
///     \cgalParamType{`double` in (0, 1]}
///     \cgalParamDefault{\default_flow_step}
///     \cgalParamExtra{A value outside (0, 1] throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{laplacian_weights}
///     \cgalParamDescription{the weights of the umbrella operator (eq. 4.3 or 4.4)}
///     \cgalParamType{meshfit::Laplacian_weights}
///     \cgalParamDefault{\default_flow_weights (eq. 4.10)}
///   \cgalParamNEnd
///   \cgalParamNBegin{reference_points}
///     \cgalParamDescription{the positions of the reference surface, one per vertex in the order of `vertices(tm)`
///       (`tm`'s connectivity at those positions)}
///     \cgalParamType{`std::vector<meshfit::Point_3>`}
///     \cgalParamDefault{the positions at the call}
///     \cgalParamExtra{A vector of another size throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_is_constrained_map}
///     \cgalParamDescription{input: vertices that must not move}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: no vertex is constrained by the caller}
///     \cgalParamExtra{Boundary vertices and the vertices of constrained edges never move either.}
///   \cgalParamNEnd
///   \cgalParamNBegin{edge_is_constrained_map}
///     \cgalParamDescription{input: the curve edges; their vertices do not move, and the projections of the modified
///       flows never cross them}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%edge_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: no edge is constrained}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `ReadWritePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///       meshfit::Point_3 as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for `CGAL::vertex_point_t` must be
///       available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{progress}
///     \cgalParamDescription{a callback called at each step with a meshfit::Progress_step (stage `"smooth"`)}
///     \cgalParamType{a callable taking `const meshfit::Progress_step&` and returning `bool` (`false` cancels) or
///       `void` (never cancels)}
///     \cgalParamDefault{none: no calls, no cancelling}
///     \cgalParamExtra{One call per iteration. When it returns `false`, the flow throws meshfit::Algorithm_failure and
///       `tm` is unchanged.}
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
/// \cgalNamedParamsEnd///
/// \throws Invalid_input for a face that is not a triangle, a non-finite coordinate, λ outside
///         (0, 1], α outside [0, 1] or a negative iteration count.
/// \throws Algorithm_failure when the progress callback returns false (`tm` is then unchanged).
/// \throws Numerical_error if a position became non-finite (the guards are meant to prevent it).
/// \throws Invalid_input when `reference_points` has the wrong size.
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Smoothing_report modified_laplacian_flow(TriangleMesh& tm,
                                         const NamedParameters& np = CGAL::parameters::default_values()) {
  return internal::run_single_flow(tm, np, internal::Flow_kind::modified_laplacian,
                                   internal::default_modified_laplacian_flow_iterations);
}

/// The thesis's method (§4.3, §4.4): modified_mean_curvature_flow to remove the distortion, then
/// modified_laplacian_flow to even out the triangles, whose reference surface is the mesh after
/// the first phase (projecting back onto the noisy input would restore the noise).
/// `reference_points` is not used.
/// Why one fifth: on the noisy sphere and torus of test/smooth_test.cpp the modified mean
/// curvature has removed the noise after about 20 iterations; later iterations only shrink the
/// shape a little more (each lands the vertices on the chords of the previous surface) and
/// stretch the triangles along the cotangent weights' tangential drift, which the Laplacian
/// phase then has to undo (measured: 20/80 keeps 98.9% of the sphere's volume, 50/50 98.4%).
///
/// \tparam TriangleMesh a model of `FaceListGraph` whose faces are triangles (tested:
///         CGAL::Surface_mesh, CGAL::Polyhedron_3)
/// \tparam NamedParameters a sequence of named parameters (CGAL's or meshfit's)
/// \param tm the mesh, smoothed in place (its connectivity does not change)
/// \param np an optional sequence of named parameters among the ones listed below
/// \return what the flow did (Smoothing_report)
///
/// \cgalNamedParamsBegin
///   \cgalParamNBegin{number_of_iterations}
///     \cgalParamDescription{the iterations of both phases: one fifth (rounded down) modified mean curvature, the rest
///       modified Laplacian}
///     \cgalParamType{an integer type}
///     \cgalParamDefault{\default_smoothing_iterations}
///     \cgalParamExtra{A negative value throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{mean_curvature_iterations}
///     \cgalParamDescription{the iterations of the first phase (modified mean curvature), overriding the split}
///     \cgalParamType{an integer type}
///     \cgalParamDefault{`number_of_iterations / 5` (integer division): \default_mean_curvature_iterations}
///     \cgalParamExtra{A negative value throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{laplacian_iterations}
///     \cgalParamDescription{the iterations of the second phase (modified Laplacian), overriding the split}
///     \cgalParamType{an integer type}
///     \cgalParamDefault{`number_of_iterations - number_of_iterations / 5`: \default_laplacian_iterations}
///     \cgalParamExtra{A negative value throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{smoothing_tolerance}
///     \cgalParamDescription{a phase ends after an iteration that moves no vertex farther than this times the mean edge
///       length at the phase's start: the iteration counts are the most each phase makes (the report's `iterations`
///       says how many were made)}
///     \cgalParamType{`double`, not negative}
///     \cgalParamDefault{\default_smoothing_tolerance}
///     \cgalParamExtra{Zero makes every iteration; a negative or non-finite value throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{step_size}
///     \cgalParamDescription{the step of both phases λ (of the umbrella operator, or of λ h̄² for the mean curvature, h̄ the mean edge
///       length at the call)}
///     \cgalParamType{`double` in (0, 1]}
///     \cgalParamDefault{\default_flow_step}
///     \cgalParamExtra{A value outside (0, 1] throws meshfit::Invalid_input.}
///   \cgalParamNEnd
///   \cgalParamNBegin{laplacian_weights}
///     \cgalParamDescription{the weights of the umbrella operator (eq. 4.3 or 4.4)}
///     \cgalParamType{meshfit::Laplacian_weights}
///     \cgalParamDefault{\default_flow_weights (the second phase's umbrella operator)}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_is_constrained_map}
///     \cgalParamDescription{input: vertices that must not move}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: no vertex is constrained by the caller}
///     \cgalParamExtra{Boundary vertices and the vertices of constrained edges never move either.}
///   \cgalParamNEnd
///   \cgalParamNBegin{edge_is_constrained_map}
///     \cgalParamDescription{input: the curve edges; their vertices do not move, and the projections of the modified
///       flows never cross them}
///     \cgalParamType{a class model of `ReadablePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%edge_descriptor` as key type and `bool` as value type}
///     \cgalParamDefault{none: no edge is constrained}
///   \cgalParamNEnd
///   \cgalParamNBegin{vertex_point_map}
///     \cgalParamDescription{a property map associating points to the vertices of `tm`}
///     \cgalParamType{a class model of `ReadWritePropertyMap` with
///       `boost::graph_traits<TriangleMesh>::%vertex_descriptor` as key type and
///       meshfit::Point_3 as value type}
///     \cgalParamDefault{`boost::get(CGAL::vertex_point, tm)`}
///     \cgalParamExtra{If this parameter is omitted, an internal property map for `CGAL::vertex_point_t` must be
///       available in `TriangleMesh`.}
///   \cgalParamNEnd
///   \cgalParamNBegin{progress}
///     \cgalParamDescription{a callback called at each step with a meshfit::Progress_step (stage `"smooth"`)}
///     \cgalParamType{a callable taking `const meshfit::Progress_step&` and returning `bool` (`false` cancels) or
///       `void` (never cancels)}
///     \cgalParamDefault{none: no calls, no cancelling}
///     \cgalParamExtra{One call per iteration of either phase, numbered through both. When it returns `false`,
///       smooth_fitted_mesh throws meshfit::Algorithm_failure and `tm` is unchanged.}
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
/// \cgalNamedParamsEnd///
/// \throws Invalid_input for a face that is not a triangle, a non-finite coordinate, λ outside
///         (0, 1], α outside [0, 1] or a negative iteration count.
/// \throws Algorithm_failure when the progress callback returns false (`tm` is then unchanged).
/// \throws Numerical_error if a position became non-finite (the guards are meant to prevent it).
///
/// Named `smooth_fitted_mesh`, not `smooth_mesh`: with `using namespace meshfit;` and `using
/// namespace CGAL::Polygon_mesh_processing;` a `smooth_mesh(tm)` call was ambiguous with CGAL's
/// (deprecated) `PMP::smooth_mesh`, and `smooth_mesh(tm, CGAL::parameters::…)` silently called
/// CGAL's. No `meshfit::smooth_mesh` alias is kept: any function of that name would clash again.
template <typename TriangleMesh, typename NamedParameters = CGAL::parameters::Default_named_parameters>
Smoothing_report smooth_fitted_mesh(TriangleMesh& tm, const NamedParameters& np = CGAL::parameters::default_values()) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto [mc, lap] = internal::smoothing_phases(np);
  internal::Flow_settings first = internal::flow_settings(np, internal::Flow_kind::modified_mean_curvature, 0);
  internal::Flow_settings second = internal::flow_settings(np, internal::Flow_kind::modified_laplacian, 0);
  first.iterations = mc;
  second.iterations = lap;
  first.stop_below = second.stop_below = internal::smoothing_tolerance(np);
  first.progress_total = second.progress_total = mc + lap;
  second.progress_offset = mc;
  const Scoped_number_of_threads threads(internal::threads_of(np, "smooth"));
  internal::Smoothing_front_end<TriangleMesh, NamedParameters> fe(tm, np);
  Smoothing_report report;
  report.vertices = fe.vertex.size();
  report.fixed_vertices = fe.fixed_count();
  report.mean_curvature_iterations = mc;
  report.laplacian_iterations = lap;
  const std::vector<double> before = fe.arrays.points;
  fe.arrays.reference_points.clear();  // the second phase projects onto the first one's result
  fe.arrays.orientation_points = before;
  internal::run_flows(fe.arrays, {first, second}, report);
  internal::fill_displacements(before, fe.arrays.points, report);
  fe.write_back();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace meshfit

#endif  // MESHFIT_SMOOTH_H
