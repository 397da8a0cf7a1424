// fit_template_to_curves's internals (fit.h): its options resolved from the named parameters, and
// the compiled core (src/fit.cpp) that runs the stages and the verification.
#ifndef MESHFIT_INTERNAL_FIT_IMPL_H
#define MESHFIT_INTERNAL_FIT_IMPL_H

#include <meshfit/correspondence.h>
#include <meshfit/curve_network.h>
#include <meshfit/deform.h>
#include <meshfit/internal/commit_result.h>
#include <meshfit/internal/stage_support.h>
#include <meshfit/io.h>
#include <meshfit/parameters.h>
#include <meshfit/smooth.h>

#include <CGAL/Named_function_parameters.h>

#include <cstddef>
#include <vector>

namespace meshfit {

struct Fit_report;

namespace internal {

/// fit_template_to_curves's parameters, resolved from its named parameters.
struct Fit_options {
  Deform_options deform;  ///< stage 1's (and the progress callback)
  std::size_t mean_curvature_iterations = 0, laplacian_iterations = 0;  ///< smoothing_phases
  double step = Flow_settings().step;                                   ///< step_size
  double smoothing_tolerance = default_smoothing_tolerance;             ///< smoothing_tolerance
  bool check_self_intersections = true;                                 ///< check_self_intersections
};

/// fit_template_to_curves's named parameters, every one read (and checked) before any work:
/// stage 1's (all but coarse_only: fit runs every stage; the progress callback, which may return
/// void or bool, as one returning bool), smoothing's as smooth_fitted_mesh counts them, the
/// verification's.
/// \throws Invalid_input for a negative count.
template <typename NamedParameters>
Fit_options fit_options(const NamedParameters& np) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  Fit_options options;
  options.deform = deform_options(np);
  options.deform.coarse_only = false;
  const auto phases = smoothing_phases(np);
  options.mean_curvature_iterations = phases.mean_curvature;
  options.laplacian_iterations = phases.laplacian;
  options.step = choose_parameter(get_parameter(np, meshfit::internal_np::step_size), options.step);
  options.smoothing_tolerance = smoothing_tolerance(np);
  options.check_self_intersections = choose_parameter(get_parameter(np, meshfit::internal_np::check_self_intersections),
                                                      options.check_self_intersections);
  return options;
}

/// Stages 1-3 and the verification (compiled once, src/fit.cpp) on `work`, built from
/// `template_data` (the template scaled to a unit-sized box), against `network` scaled by `unit`.
/// Fills `report` (but for the template's counts and the total time) and `result`: the result,
/// scaled back to the network's frame, with its curve edges and regions.
/// \throws as fit_template_to_curves.
void fit_work(const Mesh_data& template_data, const Curve_network& network, const std::vector<Correspondence>& pairs,
              const Fit_options& options, double unit, Fit_report& report, Work_mesh& work, Mesh_data& result);
}  // namespace internal

}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_FIT_IMPL_H
