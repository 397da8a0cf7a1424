# The defaults the reference shows, read from the one place the code writes them, as Doxygen
# aliases: the headers write `\cgalParamDefault{\default_flip_prevention_rounds}`, not `10`.
#   - the fields of meshfit::Deform_options (include/meshfit/deform.h): \default_<field>;
#   - the fields of internal::Fit_options (include/meshfit/internal/fit_impl.h): \default_fit_<field>;
#   - the fields of internal::Flow_settings (include/meshfit/internal/smooth_impl.h): \default_flow_<field>;
#   - its `constexpr std::size_t default_<name> = <n>;` counts and `constexpr double` values:
#     \default_<name>, and fit's and
#     smooth_fitted_mesh's split of default_smoothing_iterations, \default_mean_curvature_iterations
#     and \default_laplacian_iterations.
# Sets MESHFIT_DOC_DEFAULT_ALIASES (lines `ALIASES += "name=value"` for the Doxyfile). A default that
# cannot be found is a configuration error, so that the reference never shows a stale value.
function(meshfit_doc_defaults source_dir)
  set(aliases "")
  set(found "")
  # Fields `Type name = value;` of struct `struct` in `file`, as aliases `prefix<name>`.
  function(read_struct_defaults file struct prefix out_aliases out_found)
    file(READ "${file}" text)
    string(REGEX MATCH "struct ${struct} {[^}]*" body "${text}")
    if(NOT body)
      message(FATAL_ERROR "meshfit_doc_defaults: no struct ${struct} in ${file}")
    endif()
    string(REGEX MATCHALL "\n  [A-Za-z_:]+ [a-z_]+ = [A-Za-z0-9_:.]+" fields "${body}")
    set(a "${${out_aliases}}")
    set(f "${${out_found}}")
    foreach(field IN LISTS fields)
      string(REGEX REPLACE "\n  [A-Za-z_:]+ ([a-z_]+) = (.+)" "\\1" name "${field}")
      string(REGEX REPLACE "\n  [A-Za-z_:]+ ([a-z_]+) = (.+)" "\\2" value "${field}")
      if(value MATCHES "::")
        set(value "meshfit::${value}")
      endif()
      string(APPEND a "ALIASES += \"${prefix}${name}=`${value}`\"\n")
      list(APPEND f "${prefix}${name}")
    endforeach()
    set(${out_aliases} "${a}" PARENT_SCOPE)
    set(${out_found} "${f}" PARENT_SCOPE)
  endfunction()
  read_struct_defaults("${source_dir}/include/meshfit/deform.h" Deform_options default_ aliases found)
  read_struct_defaults("${source_dir}/include/meshfit/internal/fit_impl.h" Fit_options default_fit_ aliases found)
  set(smooth "${source_dir}/include/meshfit/internal/smooth_impl.h")
  read_struct_defaults("${smooth}" Flow_settings default_flow_ aliases found)
  file(STRINGS "${smooth}" counts REGEX "^constexpr (std::size_t|double) default_[a-z_]+ = [0-9.]+;")
  foreach(line IN LISTS counts)
    string(REGEX REPLACE "^constexpr [a-z:_]+ (default_[a-z_]+) = ([0-9.]+);" "\\1" name "${line}")
    string(REGEX REPLACE "^constexpr [a-z:_]+ (default_[a-z_]+) = ([0-9.]+);" "\\2" value "${line}")
    string(APPEND aliases "ALIASES += \"${name}=`${value}`\"\n")
    list(APPEND found "${name}")
    if(name STREQUAL "default_smoothing_iterations")
      # As internal::smoothing_phases splits it: a fifth (rounded down), then the rest.
      math(EXPR mean_curvature "${value} / 5")
      math(EXPR laplacian "${value} - ${value} / 5")
      string(APPEND aliases "ALIASES += \"default_mean_curvature_iterations=`${mean_curvature}`\"\n")
      string(APPEND aliases "ALIASES += \"default_laplacian_iterations=`${laplacian}`\"\n")
    endif()
  endforeach()
  # The ones the headers use must all be there.
  foreach(name default_flip_prevention_rounds default_rbf_kernel default_curve_density default_fine_level
               default_coarse_only default_coarse_registration default_memory_limit default_fit_check_self_intersections default_flow_step default_flow_weights default_flow_variant
               default_flow_alpha default_smoothing_iterations default_laplacian_flow_iterations
               default_mean_curvature_flow_iterations default_modified_mean_curvature_flow_iterations
               default_modified_laplacian_flow_iterations default_smoothing_tolerance)
    if(NOT name IN_LIST found)
      message(FATAL_ERROR "meshfit_doc_defaults: the default ${name} was not found in the headers")
    endif()
  endforeach()
  set(MESHFIT_DOC_DEFAULT_ALIASES "${aliases}" PARENT_SCOPE)
endfunction()
