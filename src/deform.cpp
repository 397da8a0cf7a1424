// The levels of stage 1 (deform.h) compiled once, for meshfit's own mesh: every caller of the
// public functions (whatever its mesh type and named parameters) runs this code on a copy.
#include <meshfit/internal/deform_levels.h>

namespace meshfit {
namespace internal {

Deformation_report deform_coarse_in_place(Work_mesh& tm, const Curve_network& network,
                                          const std::vector<Correspondence>& pairs, const Deform_options& options) {
  return deform_coarse_impl(tm, network, pairs, options);
}
Deformation_report deform_fine_in_place(Work_mesh& tm, const Curve_network& network,
                                        const std::vector<Correspondence>& pairs, const Deform_options& options) {
  return deform_fine_impl(tm, network, pairs, options);
}
Deformation_report deform_fine_on_surface_in_place(Work_mesh& tm, const Curve_network& network,
                                                   const std::vector<Correspondence>& pairs,
                                                   const Deform_options& options) {
  return deform_fine_on_surface_impl(tm, network, pairs, options);
}
Deformation_report deform_template_in_place(Work_mesh& tm, const Curve_network& network,
                                            const std::vector<Correspondence>& pairs, const Deform_options& options) {
  return deform_template_impl(tm, network, pairs, options);
}

}  // namespace internal
}  // namespace meshfit
