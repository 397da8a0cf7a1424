/// \file
/// meshfit: named parameters of meshfit's own, chaining with each other and with CGAL's.
///
/// A pack is started by any meshfit parameter function and read left to right:
/// `meshfit::parameters::rbf_kernel(meshfit::Rbf_kernel::cubic).progress(cb).flip_prevention_rounds(5)`.
/// Every meshfit tag and every CGAL 5.5 tag (number_of_iterations, vertex_point_map, geom_traits,
/// vertex_is_constrained_map, edge_is_constrained_map, face_patch_map, vertex_index_map, …) is a
/// member function of the pack (meshfit::Named_parameters), which derives from
/// CGAL::Named_function_parameters: `CGAL::parameters::get_parameter(np,
/// meshfit::internal_np::rbf_kernel)` reads it back and CGAL's own functions accept it.
/// `meshfit::parameters::default_values()` starts an empty pack (to begin a chain with a CGAL tag).
/// Starting from a CGAL pack, the two-argument form adds a meshfit tag (and the result chains on):
/// `meshfit::parameters::step_size(0.5, CGAL::parameters::number_of_iterations(5))`.
///
/// The tags, their types and defaults (each function's "Optional named parameters" say which it
/// reads; the defaults shown are read from the code when the reference is built):
///
/// | tag | type | default | read by |
/// |-----|------|---------|---------|
/// | `progress` | callable (`const Progress_step&`), returns `bool` (`false` cancels) or `void` | none (never cancels) | every stage |
/// | `rbf_kernel` | meshfit::Rbf_kernel | \default_rbf_kernel (φ(r) = r) | deform_coarse, deform_fine, deform_template, fit_template_to_curves |
/// | `curve_density` | meshfit::Curve_density | \default_curve_density | deform_fine, deform_template, fit_template_to_curves |
/// | `coarse_only` | `bool`: deform_template stops after the coarse level | \default_coarse_only | deform_template |
/// | `step_size` | `double` λ in (0, 1] (smooth.h) | \default_flow_step | the flows of smooth.h, fit_template_to_curves |
/// | `laplacian_weights` | meshfit::Laplacian_weights | \default_flow_weights | laplacian_flow, modified_laplacian_flow, smooth_fitted_mesh |
/// | `laplacian_variant` | meshfit::Laplacian_variant (eq. 4.5/4.6) | \default_flow_variant | laplacian_flow |
/// | `laplacian_alpha` | `double` α in [0, 1] (eq. 4.5/4.6) | \default_flow_alpha | laplacian_flow (every flow checks the range) |
/// | `reference_points` | `std::vector<Point_3>`, one per vertex | the positions at the call | modified_laplacian_flow |
/// | `mean_curvature_iterations` | integer: smooth_fitted_mesh's 1st phase | `number_of_iterations / 5` (\default_mean_curvature_iterations) | smooth_fitted_mesh, fit_template_to_curves |
/// | `laplacian_iterations` | integer: smooth_fitted_mesh's 2nd phase | the rest (\default_laplacian_iterations) | smooth_fitted_mesh, fit_template_to_curves |
/// | `smoothing_tolerance` | `double` ≥ 0: smooth_fitted_mesh ends a phase after an iteration that moves no vertex farther than this times the mean edge length (0: every iteration) | \default_smoothing_tolerance | smooth_fitted_mesh, fit_template_to_curves |
/// | `check_self_intersections` | `bool`: fit's final verification | \default_fit_check_self_intersections | fit_template_to_curves |
/// | `fine_level` | meshfit::Fine_level (deform.h) | \default_fine_level | deform_template, fit_template_to_curves |
/// | `fine_shape` | meshfit::Fine_shape (deform.h): the shape between the curves that Fine_level::surface gives | \default_fine_shape | deform_fine_on_surface, deform_template, fit_template_to_curves |
/// | `coarse_registration` | `bool`: a second start from the template warped onto the curves (registration.h) when Fine_level::surface leaves defects | \default_coarse_registration | deform_template, fit_template_to_curves |
/// | `memory_limit` | `std::size_t`, bytes (memory_limit.h) | default_memory_limit(): RAM / 8, at most 2 GiB (also when 0) | the coarse level's RBF and deform_fine's (so deform_coarse, deform_template and fit_template_to_curves) |
/// | `flip_prevention_rounds` | integer ≥ 0: the most rounds of flip prevention (thesis level) or untangling (surface level) | \default_flip_prevention_rounds | deform_fine, deform_fine_on_surface, deform_template, fit_template_to_curves |
/// | `number_of_threads` | integer ≥ 1: the most threads (OpenMP's and OpenBLAS's) the call uses; put back after it (threads.h) | unchanged: every core, or OMP_NUM_THREADS / set_number_of_threads() | every stage but project_segment |
///
/// CGAL parameters meshfit reads: `vertex_point_map` (every function over a mesh);
/// `number_of_iterations` (always smoothing iterations: smooth's flows, and fit's smoothing, split
/// as smooth_fitted_mesh splits it; deform does not read it); `face_patch_map` and
/// `edge_is_constrained_map` (outputs of partition_mesh and fit_template_to_curves; io; smooth:
/// curve edges as input; project_segment: edges not to cross); `vertex_is_constrained_map` (smooth,
/// partition_mesh, project_segment); `geom_traits` (every stage: it must be a Cartesian kernel over
/// double, checked at compile time, as the points of the mesh must have double coordinates; the
/// stages compute on meshfit's own copies in meshfit::Kernel, exactly from the same doubles).
#ifndef MESHFIT_PARAMETERS_H
#define MESHFIT_PARAMETERS_H

#include <CGAL/Named_function_parameters.h>

#include <cstddef>
#include <functional>
#include <string>
#include <type_traits>

namespace meshfit {

/// One step of a stage, passed to the `progress` callback. A callback returning `bool` cancels the
/// stage cleanly by returning `false` (the stage throws meshfit::Algorithm_failure naming the stage);
/// a callback returning `void` never cancels.
struct Progress_step {
  std::string stage;      ///< "read", "deform", "partition", "smooth", …
  std::string step;       ///< what is being done
  std::size_t index = 0;  ///< 0-based step number within the stage
  std::size_t total = 0;  ///< number of steps in the stage, 0 when unknown
};
/// The callback type the stages use inside; any callable taking `const Progress_step&` and
/// returning `bool` or `void` may be passed as the `progress` parameter.
using Progress_callback = std::function<bool(const Progress_step&)>;

/// The one list of meshfit's named parameters: `X(name)` for each. It generates the tag types and
/// values (`meshfit::internal_np::name_t`, `name`), the member functions of
/// meshfit::Named_parameters and the functions of `meshfit::parameters`.
#define MESHFIT_NAMED_PARAMETERS(X) \
  X(progress)                       \
  X(rbf_kernel)                     \
  X(curve_density)                  \
  X(coarse_only)                    \
  X(step_size)                      \
  X(laplacian_weights)              \
  X(laplacian_variant)              \
  X(laplacian_alpha)                \
  X(reference_points)               \
  X(mean_curvature_iterations)      \
  X(laplacian_iterations)           \
  X(smoothing_tolerance)            \
  X(check_self_intersections)       \
  X(fine_level)                     \
  X(fine_shape)                     \
  X(coarse_registration)            \
  X(memory_limit)                   \
  X(flip_prevention_rounds)         \
  X(number_of_threads)

namespace internal_np {
#define MESHFIT_NAMED_PARAMETER_TAG(NAME) enum NAME##_t { NAME };
MESHFIT_NAMED_PARAMETERS(MESHFIT_NAMED_PARAMETER_TAG)
#undef MESHFIT_NAMED_PARAMETER_TAG
}  // namespace internal_np

/// A pack of named parameters whose member functions add any meshfit or CGAL parameter, so that a
/// pack reads left to right: `meshfit::parameters::rbf_kernel(k).progress(cb).number_of_iterations(5)`.
/// There is one member function template per tag, `template <typename K> Named_parameters<K, tag,
/// self> name(const K& k) const`, for each of meshfit's tags (the table of parameters.h) and each
/// of CGAL's (made from CGAL's own list; they hide the base class's members, which would return a
/// CGAL pack).
/// It is a `CGAL::Named_function_parameters<T, Tag, Base>` (by derivation; the base class and its
/// `base` type are CGAL's own), so `CGAL::parameters::get_parameter()` and `choose_parameter()`
/// read it and CGAL's functions accept it (one limit of the derivation: where CGAL overloads a
/// function on `const CGAL::Named_function_parameters<…>&` against one taking any type in that
/// place, the pack, not being exactly CGAL's type, may pick the other overload; `cgal_parameters()`
/// gives the pack as CGAL's type for such a call). `Base` is the rest of the pack: another
/// meshfit::Named_parameters, a CGAL pack, or `CGAL::internal_np::No_property`.
template <typename T, typename Tag, typename Base = CGAL::internal_np::No_property>
struct Named_parameters : CGAL::Named_function_parameters<T, Tag, Base> {
  /// The CGAL pack this one is (do not name it `base`: CGAL's lookup uses that name).
  using Cgal_named_parameters = CGAL::Named_function_parameters<T, Tag, Base>;
  /// This type.
  using self = Named_parameters<T, Tag, Base>;

  /// An empty pack (with `T` = `bool` and `Tag` = `CGAL::internal_np::all_default_t`, see
  /// parameters::default_values()).
  Named_parameters() : Cgal_named_parameters() {}
  /// A pack of one parameter, `value` for `Tag`.
  explicit Named_parameters(const T& value) : Cgal_named_parameters(value) {}
  /// `value` for `Tag`, added to the pack `rest`.
  Named_parameters(const T& value, const Base& rest) : Cgal_named_parameters(value, rest) {}

  /// This pack as CGAL's own type (the same parameters).
  const Cgal_named_parameters& cgal_parameters() const { return *this; }

#define MESHFIT_NAMED_PARAMETER_MEMBER(NAME)                                    \
  template <typename K>                                                         \
  Named_parameters<K, meshfit::internal_np::NAME##_t, self> NAME(const K& k) const { \
    return Named_parameters<K, meshfit::internal_np::NAME##_t, self>(k, *this);  \
  }
  MESHFIT_NAMED_PARAMETERS(MESHFIT_NAMED_PARAMETER_MEMBER)
#undef MESHFIT_NAMED_PARAMETER_MEMBER

  // Every CGAL parameter, from CGAL's own list (the one CGAL::Named_function_parameters's members
  // are made from); these hide the base class's members, which would return a CGAL pack. (Hidden
  // from the reference, as CGAL hides code from its own: doxygen does not read CGAL's list.)
#ifndef DOXYGEN_RUNNING
#define CGAL_add_named_parameter(X, Y, Z)                                    \
  template <typename K>                                                      \
  Named_parameters<K, CGAL::internal_np::X, self> Z(const K& k) const {      \
    return Named_parameters<K, CGAL::internal_np::X, self>(k, *this);        \
  }
#include <CGAL/STL_Extension/internal/parameters_interface.h>
#undef CGAL_add_named_parameter
#endif  // DOXYGEN_RUNNING
};

namespace parameters {

/// An empty meshfit pack, to begin a chain with a CGAL parameter:
/// `meshfit::parameters::default_values().number_of_iterations(5).progress(cb)`.
inline Named_parameters<bool, CGAL::internal_np::all_default_t> default_values() {
  return Named_parameters<bool, CGAL::internal_np::all_default_t>();
}

/// Generates, for each meshfit parameter, `name(value)` (starts a pack) and `name(value, pack)`
/// (adds it to a CGAL or meshfit pack; kept from the nesting form, the result chains on).
#define MESHFIT_NAMED_PARAMETER_FUNCTIONS(NAME)                                                         \
  template <typename T>                                                                                 \
  Named_parameters<T, meshfit::internal_np::NAME##_t> NAME(const T& value) {                            \
    return Named_parameters<T, meshfit::internal_np::NAME##_t>(value);                                  \
  }                                                                                                     \
  template <typename T, typename BT, typename BTag, typename BBase>                                     \
  Named_parameters<T, meshfit::internal_np::NAME##_t, CGAL::Named_function_parameters<BT, BTag, BBase>> \
  NAME(const T& value, const CGAL::Named_function_parameters<BT, BTag, BBase>& base) {                  \
    return Named_parameters<T, meshfit::internal_np::NAME##_t,                                          \
                            CGAL::Named_function_parameters<BT, BTag, BBase>>(value, base);             \
  }                                                                                                     \
  template <typename T, typename BT, typename BTag, typename BBase>                                     \
  Named_parameters<T, meshfit::internal_np::NAME##_t, Named_parameters<BT, BTag, BBase>> NAME(          \
      const T& value, const Named_parameters<BT, BTag, BBase>& base) {                                  \
    return Named_parameters<T, meshfit::internal_np::NAME##_t, Named_parameters<BT, BTag, BBase>>(value, \
                                                                                                base);  \
  }
MESHFIT_NAMED_PARAMETERS(MESHFIT_NAMED_PARAMETER_FUNCTIONS)
#undef MESHFIT_NAMED_PARAMETER_FUNCTIONS

}  // namespace parameters
}  // namespace meshfit

namespace CGAL {

template <typename PolygonMesh, typename NamedParametersGT, typename NamedParametersVPM>
class GetGeomTraits;

/// As CGAL does for its own packs (CGAL/Polygon_mesh_processing/measure.h): where an overload
/// takes the pack's place for a mesh (`PMP::area(tm, np)` also matches `area(face_range, tm)` with
/// the pack as the mesh), the geometric traits of a pack must fail substitution quietly instead of
/// instantiating a property map of the pack.
template <typename T, typename Tag, typename Base, typename NamedParametersGT, typename NamedParametersVPM>
class GetGeomTraits<meshfit::Named_parameters<T, Tag, Base>, NamedParametersGT, NamedParametersVPM> {
 public:
  struct type {};
};

}  // namespace CGAL

#endif  // MESHFIT_PARAMETERS_H
