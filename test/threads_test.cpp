// set_number_of_threads: the limit reaches OpenMP and OpenBLAS, and a count below 1 is refused.
#include <meshfit/exceptions.h>
#include <meshfit/threads.h>

#include <catch2/catch.hpp>

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
