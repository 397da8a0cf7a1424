#include <meshfit/parameters.h>

#include <catch2/catch.hpp>

#include <type_traits>

TEST_CASE("parameters: meshfit's parameters chain with CGAL's both ways", "[parameters]") {
  using CGAL::parameters::get_parameter;
  namespace np = meshfit::internal_np;

  const auto a = meshfit::parameters::merge_tolerance(1e-7).number_of_iterations(5);
  CHECK(get_parameter(a, np::merge_tolerance) == 1e-7);
  CHECK(get_parameter(a, CGAL::internal_np::number_of_iterations) == 5);

  const auto b = meshfit::parameters::merge_tolerance(2e-7, CGAL::parameters::number_of_iterations(7));
  CHECK(get_parameter(b, np::merge_tolerance) == 2e-7);
  CHECK(get_parameter(b, CGAL::internal_np::number_of_iterations) == 7);

  const auto c = meshfit::parameters::input_file_name(std::string("x.off"), b);
  CHECK(get_parameter(c, np::input_file_name) == "x.off");
  CHECK(get_parameter(c, np::merge_tolerance) == 2e-7);

  // A parameter that is not there is reported as not found, so defaults apply.
  using Missing = decltype(get_parameter(CGAL::parameters::number_of_iterations(1), np::merge_tolerance));
  CHECK(std::is_same_v<Missing, CGAL::internal_np::Param_not_found>);
  CHECK(CGAL::parameters::choose_parameter(get_parameter(CGAL::parameters::number_of_iterations(1),
                                                         np::merge_tolerance), 1e-9) == 1e-9);
}
