// Must not compile (ctest kernel_static_assert_*, which look for meshfit's messages): meshfit takes
// any Cartesian kernel over double and refuses an exact kernel with a static_assert that says why.
//   MESHFIT_CASE 1: a Surface_mesh of Epeck points;
//   MESHFIT_CASE 2: an Epick mesh with geom_traits(Epeck()).
// Without MESHFIT_CASE both, in one compilation (what the tests do: the two cases are separate
// instantiations, and each prints its own message; compiling the headers once instead of twice saves
// about 9 s of CPU).
#include <meshfit/fit.h>
#include <meshfit/smooth.h>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

int main() {
#if !defined(MESHFIT_CASE) || MESHFIT_CASE == 1
  {
    CGAL::Surface_mesh<CGAL::Epeck::Point_3> tm;
    meshfit::smooth_fitted_mesh(tm);
    meshfit::partition_mesh(tm, meshfit::Curve_network());
  }
#endif
#if !defined(MESHFIT_CASE) || MESHFIT_CASE == 2
  {
    CGAL::Surface_mesh<meshfit::Point_3> tm;
    meshfit::smooth_fitted_mesh(tm, CGAL::parameters::geom_traits(CGAL::Epeck()));
  }
#endif
}
