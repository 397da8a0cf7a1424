// set_number_of_threads: the limit reaches OpenMP and OpenBLAS, and a count below 1 is refused;
// the number_of_threads named parameter limits a stage for the call only.
#include <meshfit/correspondence.h>
#include <meshfit/curve_network.h>
#include <meshfit/deform.h>
#include <meshfit/exceptions.h>
#include <meshfit/fit.h>
#include <meshfit/io.h>
#include <meshfit/partition.h>
#include <meshfit/smooth.h>
#include <meshfit/threads.h>

#include <CGAL/Surface_mesh.h>

#include <map>
#include <set>
#include <string>

#include <catch2/catch.hpp>

namespace meshfit_threads_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

extern "C" int openblas_get_num_threads(void);

TEST_CASE("threads: set_number_of_threads limits OpenMP and OpenBLAS and refuses fewer than one", "[threads]") {
  const int before = meshfit::number_of_threads();
  REQUIRE(before >= 1);

  meshfit::set_number_of_threads(1);
  CHECK(meshfit::number_of_threads() == 1);
  CHECK(openblas_get_num_threads() == 1);
  meshfit::set_number_of_threads(3);
  CHECK(meshfit::number_of_threads() == 3);
  // OpenBLAS caps the count at the threads it was built for (its own maximum), never above 3.
  CHECK(openblas_get_num_threads() >= 1);
  CHECK(openblas_get_num_threads() <= 3);

  for (const int bad : {0, -1, -1000}) {
    INFO(bad);
    CHECK_THROWS_AS(meshfit::set_number_of_threads(bad), meshfit::Invalid_input);
    CHECK(meshfit::number_of_threads() == 3);  // a refused count changes nothing
  }

  meshfit::set_number_of_threads(before);  // as the other tests expect: every core
  CHECK(meshfit::number_of_threads() == before);
}

TEST_CASE("threads: the number_of_threads parameter limits each stage for its call and puts the count back",
          "[threads]") {
  using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;
  const std::string dir = MESHFIT_EXAMPLE_DATA_DIR;
  const auto network = meshfit::read_curve_network(dir + "/curves.polylines.txt");
  const auto pairs = meshfit::read_correspondences(dir + "/pairs.txt", network);
  Mesh template_mesh;
  meshfit::read_triangle_mesh(dir + "/template.off", template_mesh);
  const int before = meshfit::number_of_threads();

  for (const int n : {1, 2}) {
    INFO("number_of_threads(" << n << ")");
    // What the stages see, per stage name, at every step of their progress.
    std::map<std::string, std::set<int>> seen;
    auto record = [&](const meshfit::Progress_step& s) { seen[s.stage].insert(meshfit::number_of_threads()); };
    const auto np = meshfit::parameters::progress(record).number_of_threads(n);
    Mesh tm = template_mesh;
    meshfit::fit_template_to_curves(tm, network, pairs, np);
    Mesh d = template_mesh;
    meshfit::deform_template(d, network, pairs, np);
    meshfit::partition_mesh(d, network, np);
    meshfit::smooth_fitted_mesh(d, np.number_of_iterations(5));
    meshfit::laplacian_flow(d, np.number_of_iterations(2));
    for (const char* stage : {"deform", "partition", "smooth", "fit"}) {
      INFO(stage);
      CHECK(seen[stage] == std::set<int>{n});
    }
    CHECK(meshfit::number_of_threads() == before);
    CHECK(openblas_get_num_threads() >= 1);
  }

  // A count below 1 is refused before any work; the counts are unchanged.
  Mesh tm = template_mesh;
  for (const int bad : {0, -2}) {
    INFO(bad);
    CHECK_THROWS_AS(meshfit::fit_template_to_curves(tm, network, pairs, meshfit::parameters::number_of_threads(bad)),
                    meshfit::Invalid_input);
    CHECK_THROWS_AS(meshfit::smooth_fitted_mesh(tm, meshfit::parameters::number_of_threads(bad)), meshfit::Invalid_input);
    CHECK(num_vertices(tm) == num_vertices(template_mesh));
    CHECK(meshfit::number_of_threads() == before);
  }

  // A stage that throws puts the count back too.
  std::size_t steps = 0;
  CHECK_THROWS_AS(meshfit::fit_template_to_curves(tm, network, pairs,
                                                  meshfit::parameters::number_of_threads(1).progress(
                                                      [&](const meshfit::Progress_step&) { return ++steps < 3; })),
                  meshfit::Algorithm_failure);
  CHECK(meshfit::number_of_threads() == before);
}

}  // namespace meshfit_threads_test
