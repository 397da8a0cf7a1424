// meshfit: named parameters of meshfit's own, chaining with CGAL's.
//
// Every meshfit parameter function comes in two forms:
//   meshfit::parameters::merge_tolerance(1e-8)                      // starts a pack
//   meshfit::parameters::merge_tolerance(1e-8, CGAL::parameters::number_of_iterations(5))
// and the pack it returns is a CGAL::Named_function_parameters, so CGAL's parameters chain after
// it (`.number_of_iterations(5)`), and CGAL::parameters::get_parameter(np,
// meshfit::internal_np::merge_tolerance) reads it back.
//
// The tags, their types and defaults:
//   | tag               | type                                    | default                        |
//   |-------------------|-----------------------------------------|--------------------------------|
//   | merge_tolerance   | double, relative to the bbox diagonal   | 1e-9                           |
//   | progress          | callable bool(const Progress_step&)     | none (never cancels)           |
//   | input_file_name   | std::string, used in error messages     | the path read, or "<stream>"   |
//   | rbf_kernel        | meshfit::Rbf_kernel                     | Rbf_kernel::linear (φ(r) = r)  |
//   | curve_density     | meshfit::Curve_density                  | Curve_density::refine          |
//   | coarse_only       | bool: deform_template stops after coarse| false                          |
//   | step_size         | double λ in (0, 1] (smooth.h)           | 1                              |
//   | laplacian_weights | meshfit::Laplacian_weights              | Laplacian_weights::uniform     |
//   | laplacian_variant | meshfit::Laplacian_variant (eq. 4.5/4.6)| Laplacian_variant::none        |
//   | laplacian_alpha   | double α in [0, 1] (eq. 4.5/4.6)        | 0.5                            |
//   | reference_points  | std::vector<Point_3>, one per vertex    | the positions at the call      |
//   | mean_curvature_iterations | smooth_mesh's first phase       | number_of_iterations / 5 (20)  |
//   | laplacian_iterations      | smooth_mesh's second phase      | the rest (80)                  |
//   | check_self_intersections  | bool: fit's final verification | true                           |
//   | fine_level        | meshfit::Fine_level (deform.h)          | Fine_level::surface            |
//   | memory_limit      | std::size_t, bytes (memory_limit.h)     | default_memory_limit(): RAM / 8|
// CGAL parameters meshfit reads: vertex_point_map; number_of_iterations (deform: the most flip
// prevention rounds, default 10; smooth: the iterations); face_patch_map and
// edge_is_constrained_map (io; smooth: curve edges); vertex_is_constrained_map (smooth).
#ifndef MESHFIT_PARAMETERS_H
#define MESHFIT_PARAMETERS_H

#include <CGAL/Named_function_parameters.h>

#include <cstddef>
#include <functional>
#include <string>

namespace meshfit {

/// One step of a stage, passed to the `progress` callback. Returning `false` from the callback
/// cancels the stage cleanly (it throws meshfit::Algorithm_failure naming the stage).
struct Progress_step {
  std::string stage;      ///< "read", "deform", "partition", "smooth", …
  std::string step;       ///< what is being done
  std::size_t index = 0;  ///< 0-based step number within the stage
  std::size_t total = 0;  ///< number of steps in the stage, 0 when unknown
};
using Progress_callback = std::function<bool(const Progress_step&)>;

namespace internal_np {
enum merge_tolerance_t { merge_tolerance };
enum progress_t { progress };
enum input_file_name_t { input_file_name };
enum rbf_kernel_t { rbf_kernel };
enum curve_density_t { curve_density };
enum coarse_only_t { coarse_only };
enum step_size_t { step_size };
enum laplacian_weights_t { laplacian_weights };
enum laplacian_variant_t { laplacian_variant };
enum laplacian_alpha_t { laplacian_alpha };
enum reference_points_t { reference_points };
enum mean_curvature_iterations_t { mean_curvature_iterations };
enum laplacian_iterations_t { laplacian_iterations };
enum check_self_intersections_t { check_self_intersections };
enum fine_level_t { fine_level };
enum memory_limit_t { memory_limit };
}  // namespace internal_np

namespace parameters {

/// Generates `name(value)` and `name(value, base_pack)`.
#define MESHFIT_NAMED_PARAMETER(NAME)                                                          \
  template <typename T>                                                                        \
  CGAL::Named_function_parameters<T, meshfit::internal_np::NAME##_t> NAME(const T& value) {    \
    return CGAL::Named_function_parameters<T, meshfit::internal_np::NAME##_t>(value);          \
  }                                                                                            \
  template <typename T, typename BT, typename BTag, typename BBase>                            \
  CGAL::Named_function_parameters<T, meshfit::internal_np::NAME##_t,                           \
                                  CGAL::Named_function_parameters<BT, BTag, BBase>>            \
  NAME(const T& value, const CGAL::Named_function_parameters<BT, BTag, BBase>& base) {         \
    return CGAL::Named_function_parameters<T, meshfit::internal_np::NAME##_t,                  \
                                           CGAL::Named_function_parameters<BT, BTag, BBase>>(  \
        value, base);                                                                          \
  }

MESHFIT_NAMED_PARAMETER(merge_tolerance)
MESHFIT_NAMED_PARAMETER(progress)
MESHFIT_NAMED_PARAMETER(input_file_name)
MESHFIT_NAMED_PARAMETER(rbf_kernel)
MESHFIT_NAMED_PARAMETER(curve_density)
MESHFIT_NAMED_PARAMETER(coarse_only)
MESHFIT_NAMED_PARAMETER(step_size)
MESHFIT_NAMED_PARAMETER(laplacian_weights)
MESHFIT_NAMED_PARAMETER(laplacian_variant)
MESHFIT_NAMED_PARAMETER(laplacian_alpha)
MESHFIT_NAMED_PARAMETER(reference_points)
MESHFIT_NAMED_PARAMETER(mean_curvature_iterations)
MESHFIT_NAMED_PARAMETER(laplacian_iterations)
MESHFIT_NAMED_PARAMETER(check_self_intersections)
MESHFIT_NAMED_PARAMETER(fine_level)
MESHFIT_NAMED_PARAMETER(memory_limit)

#undef MESHFIT_NAMED_PARAMETER

}  // namespace parameters
}  // namespace meshfit

#endif  // MESHFIT_PARAMETERS_H
