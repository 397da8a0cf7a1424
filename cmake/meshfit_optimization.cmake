# The programs that only check or show the library (the test suite, the example programs, the
# battery's generator and scorer, the fuzz targets) are compiled at MESHFIT_CHECK_OPTIMIZATION
# (default -O1) in Release builds instead of -O3: their work is done in the compiled library and the
# command, which keep the build type's flags, and most of their compile time is -O3's code
# generation for CGAL's and meshfit's header templates (the two test translation units: 227 s of
# CPU at -O3, 163 s at -O1; the tests themselves ran in 62 s and 64 s). The header templates stay
# checked at -O3 by the command-line tests (the command is compiled at -O3) and by
# install_and_consume (a Release consumer of fit_template_to_curves on Surface_mesh and
# Polyhedron_3). Empty: the build type's flags.
set(MESHFIT_CHECK_OPTIMIZATION "-O1" CACHE STRING
    "Optimisation flag of the tests, examples, battery programs and fuzz targets in Release builds (empty: the build type's)")
function(meshfit_check_optimization target)
  if(MESHFIT_CHECK_OPTIMIZATION)
    # After CMAKE_CXX_FLAGS_RELEASE on the command line, so it wins over its -O3.
    target_compile_options(${target} PRIVATE $<$<CONFIG:Release>:${MESHFIT_CHECK_OPTIMIZATION}>)
  endif()
endfunction()
