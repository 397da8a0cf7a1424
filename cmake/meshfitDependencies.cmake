# Imported targets for the two libraries meshfit's core links that ship no CMake package on Debian 12:
# LAPACKE (liblapacke-dev; Eigen's LAPACKE back end in the RBF's LU) and CHOLMOD (libsuitesparse-dev;
# the thin-plate displacement's sparse Cholesky). The build includes this file, and so does the
# installed meshfitConfig.cmake (for a static libmeshfit, whose consumers link them): the exported
# target names meshfit::lapacke and meshfit::cholmod, never a path, and each consumer finds the
# files again on its own system. The cache entries (MESHFIT_LAPACKE_LIBRARY, ...) may be set by hand.
#
# Out: the targets, and _meshfit_missing_dependencies (what was not found; empty when all was).
set(_meshfit_missing_dependencies "")
if(NOT TARGET meshfit::lapacke)
  find_library(MESHFIT_LAPACKE_LIBRARY NAMES lapacke)
  if(MESHFIT_LAPACKE_LIBRARY)
    add_library(meshfit::lapacke UNKNOWN IMPORTED)
    set_target_properties(meshfit::lapacke PROPERTIES IMPORTED_LOCATION "${MESHFIT_LAPACKE_LIBRARY}")
  else()
    list(APPEND _meshfit_missing_dependencies "LAPACKE (liblapacke)")
  endif()
endif()
if(NOT TARGET meshfit::cholmod)
  find_path(MESHFIT_CHOLMOD_INCLUDE_DIR NAMES cholmod.h PATH_SUFFIXES suitesparse)
  find_library(MESHFIT_CHOLMOD_LIBRARY NAMES cholmod)
  if(MESHFIT_CHOLMOD_LIBRARY AND MESHFIT_CHOLMOD_INCLUDE_DIR)
    add_library(meshfit::cholmod UNKNOWN IMPORTED)
    set_target_properties(meshfit::cholmod PROPERTIES IMPORTED_LOCATION "${MESHFIT_CHOLMOD_LIBRARY}"
                          INTERFACE_INCLUDE_DIRECTORIES "${MESHFIT_CHOLMOD_INCLUDE_DIR}")
  else()
    list(APPEND _meshfit_missing_dependencies "CHOLMOD (libcholmod, cholmod.h)")
  endif()
endif()
