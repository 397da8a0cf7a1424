#include <meshfit/deform.h>
#include <meshfit/fit.h>
#include <meshfit/io.h>
#include <meshfit/parameters.h>
#include <meshfit/partition.h>
#include <meshfit/smooth.h>

#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/generators.h>
#include <CGAL/boost/graph/graph_traits_Polyhedron_3.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/properties_Polyhedron_3.h>

// CGAL 5.5 still has PMP::smooth_mesh, in a deprecated header: included to check that meshfit's
// combined method does not clash with it.
#define CGAL_NO_DEPRECATION_WARNINGS
#include <CGAL/Polygon_mesh_processing/smooth_mesh.h>

#include <catch2/catch.hpp>

#include "oracle_helpers.h"
#include "test_helpers.h"

#include <filesystem>
#include <functional>
#include <map>
#include <regex>
#include <string>
#include <type_traits>
#include <vector>

namespace meshfit_parameters_test {  // one per file: the test files are compiled together (test/CMakeLists.txt)

namespace {

namespace np = meshfit::internal_np;
using CGAL::parameters::choose_parameter;
using CGAL::parameters::get_parameter;
using Surface = CGAL::Surface_mesh<meshfit::Point_3>;
using Polyhedron = CGAL::Polyhedron_3<meshfit::Kernel>;

struct Example {
  meshfit::Mesh_data mesh;
  meshfit::Curve_network network;
  std::vector<meshfit::Correspondence> pairs;
};

const Example& example() {
  static const Example e = [] {
    Example x;
    const std::string d = MESHFIT_EXAMPLE_DATA_DIR;
    Surface tm;
    meshfit::read_triangle_mesh(d + "/template.off", tm);
    x.mesh = meshfit::to_mesh_data(tm);
    x.network = meshfit::read_curve_network(d + "/curves.polylines.txt");
    x.pairs = meshfit::read_correspondences(d + "/pairs.txt", x.network);
    return x;
  }();
  return e;
}

template <typename TriangleMesh>
TriangleMesh make_mesh(const meshfit::Mesh_data& data) {
  TriangleMesh tm;
  meshfit::build_triangle_mesh(data, tm);
  return tm;
}

/// Counts the calls of each stage; returns nothing, so it never cancels.
struct Void_counter {
  std::map<std::string, std::size_t>* calls;
  void operator()(const meshfit::Progress_step& s) const { ++(*calls)[s.stage]; }
};

}  // namespace

namespace using_directives {
using namespace meshfit;
using namespace CGAL::Polygon_mesh_processing;

// Unqualified, as a user with both using-directives writes it: meshfit's is the only candidate
// (PMP::smooth_mesh was ambiguous with meshfit's former smooth_mesh, or chosen over it).
inline Smoothing_report smooth_unqualified(Surface& tm) { return smooth_fitted_mesh(tm); }
inline Smoothing_report smooth_unqualified(Surface& tm, int iterations) {
  return smooth_fitted_mesh(tm, CGAL::parameters::number_of_iterations(iterations));
}
}  // namespace using_directives

TEST_CASE("parameters: smooth_fitted_mesh does not clash with PMP::smooth_mesh under using-directives", "[parameters]") {
  Surface tm = make_mesh<Surface>(meshfit_test::octahedron());
  // meshfit's function ran: its report plans the default split, or the count asked for.
  const meshfit::Smoothing_report all = using_directives::smooth_unqualified(tm);
  CHECK(all.mean_curvature_iterations + all.laplacian_iterations == 100);
  const meshfit::Smoothing_report three = using_directives::smooth_unqualified(tm, 3);
  CHECK(three.mean_curvature_iterations + three.laplacian_iterations == 3);
}

TEST_CASE("parameters: deform_parameters gives deform_options every field back, the callback included",
          "[parameters]") {
  meshfit::Deform_options o;
  o.rbf_kernel = meshfit::Rbf_kernel::cubic;
  o.curve_density = meshfit::Curve_density::drop;
  o.fine_level = meshfit::Fine_level::thesis;
  o.coarse_only = true;
  o.flip_prevention_rounds = 7;
  o.memory_limit = 123456789;
  int calls = 0;
  o.progress = [&calls](const meshfit::Progress_step&) { return ++calls < 2; };
  const meshfit::Deform_options back = meshfit::deform_options(meshfit::deform_parameters(o));
  CHECK(back.rbf_kernel == meshfit::Rbf_kernel::cubic);
  CHECK(back.curve_density == meshfit::Curve_density::drop);
  CHECK(back.fine_level == meshfit::Fine_level::thesis);
  CHECK(back.coarse_only);
  CHECK(back.flip_prevention_rounds == 7);
  CHECK(back.memory_limit == 123456789);
  CHECK(back.progress(meshfit::Progress_step{"deform", "a", 0, 1}));
  CHECK_FALSE(back.progress(meshfit::Progress_step{"deform", "b", 1, 2}));
  CHECK(calls == 2);
  // No parameter: the struct's defaults.
  const meshfit::Deform_options none = meshfit::deform_options(meshfit::parameters::default_values());
  const meshfit::Deform_options defaults;
  CHECK(none.rbf_kernel == defaults.rbf_kernel);
  CHECK(none.curve_density == defaults.curve_density);
  CHECK(none.fine_level == defaults.fine_level);
  CHECK(none.coarse_only == defaults.coarse_only);
  CHECK(none.flip_prevention_rounds == defaults.flip_prevention_rounds);
  CHECK(none.memory_limit == defaults.memory_limit);
  CHECK(none.progress(meshfit::Progress_step{"deform", "c", 0, 1}));
}

TEST_CASE("parameters: a chain of meshfit and CGAL parameters reads back with its types and values",
          "[parameters]") {
  Surface tm = make_mesh<Surface>(meshfit_test::octahedron());
  const auto vpm = get(CGAL::vertex_point, tm);
  auto vcm = get(CGAL::dynamic_vertex_property_t<bool>(), tm);
  auto ecm = get(CGAL::dynamic_edge_property_t<bool>(), tm);
  auto fpm = get(CGAL::dynamic_face_property_t<int>(), tm);
  std::size_t calls = 0;
  auto cb = [&calls](const meshfit::Progress_step&) { ++calls; };

  const auto p = meshfit::parameters::rbf_kernel(meshfit::Rbf_kernel::cubic)
                     .progress(cb)
                     .number_of_iterations(5)
                     .curve_density(meshfit::Curve_density::drop)
                     .vertex_point_map(vpm)
                     .geom_traits(meshfit::Kernel())
                     .vertex_is_constrained_map(vcm)
                     .edge_is_constrained_map(ecm)
                     .face_patch_map(fpm)
                     .vertex_index_map(get(CGAL::vertex_index, tm))
                     .memory_limit(std::size_t(1) << 20)
                     .fine_level(meshfit::Fine_level::thesis)
                     .step_size(0.25)
                     .mean_curvature_iterations(3)
                     .laplacian_iterations(7)
                     .check_self_intersections(false)
                     .coarse_only(true)
                     .laplacian_weights(meshfit::Laplacian_weights::inverse_distance)
                     .laplacian_variant(meshfit::Laplacian_variant::alpha_original)
                     .laplacian_alpha(0.75)
                     .reference_points(std::vector<meshfit::Point_3>(2));

  // The pack is meshfit's own and is a CGAL pack.
  using Pack = std::decay_t<decltype(p)>;
  STATIC_REQUIRE(std::is_base_of_v<typename Pack::Cgal_named_parameters, Pack>);

  // Types.
  STATIC_REQUIRE(std::is_same_v<decltype(get_parameter(p, np::rbf_kernel)), meshfit::Rbf_kernel>);
  STATIC_REQUIRE(std::is_same_v<decltype(get_parameter(p, np::progress)), decltype(cb)>);
  STATIC_REQUIRE(std::is_same_v<decltype(get_parameter(p, CGAL::internal_np::number_of_iterations)), int>);
  STATIC_REQUIRE(std::is_same_v<decltype(get_parameter(p, CGAL::internal_np::vertex_point)), std::decay_t<decltype(vpm)>>);
  STATIC_REQUIRE(std::is_same_v<decltype(get_parameter(p, CGAL::internal_np::geom_traits)), meshfit::Kernel>);
  STATIC_REQUIRE(std::is_same_v<decltype(get_parameter(p, CGAL::internal_np::vertex_is_constrained)), decltype(vcm)>);
  STATIC_REQUIRE(std::is_same_v<decltype(get_parameter(p, CGAL::internal_np::edge_is_constrained)), decltype(ecm)>);
  STATIC_REQUIRE(std::is_same_v<decltype(get_parameter(p, CGAL::internal_np::face_patch)), decltype(fpm)>);
  STATIC_REQUIRE(std::is_same_v<decltype(get_parameter(p, np::memory_limit)), std::size_t>);
  STATIC_REQUIRE(std::is_same_v<decltype(get_parameter(p, np::step_size)), double>);
  STATIC_REQUIRE(std::is_same_v<decltype(get_parameter(p, np::reference_points)), std::vector<meshfit::Point_3>>);
  // A parameter that is not in the chain is not found, so its default applies.
  STATIC_REQUIRE(std::is_same_v<decltype(get_parameter(p, CGAL::internal_np::face_index)),
                                CGAL::internal_np::Param_not_found>);
  CHECK(choose_parameter(get_parameter(p, CGAL::internal_np::maximum_number_of_faces), 42) == 42);

  // Values.
  CHECK(get_parameter(p, np::rbf_kernel) == meshfit::Rbf_kernel::cubic);
  CHECK(get_parameter(p, CGAL::internal_np::number_of_iterations) == 5);
  CHECK(get_parameter(p, np::curve_density) == meshfit::Curve_density::drop);
  CHECK(choose_parameter(get_parameter(p, np::memory_limit), std::size_t(0)) == std::size_t(1) << 20);
  CHECK(get_parameter(p, np::fine_level) == meshfit::Fine_level::thesis);
  CHECK(get_parameter(p, np::step_size) == 0.25);
  CHECK(get_parameter(p, np::mean_curvature_iterations) == 3);
  CHECK(get_parameter(p, np::laplacian_iterations) == 7);
  CHECK(get_parameter(p, np::check_self_intersections) == false);
  CHECK(get_parameter(p, np::coarse_only) == true);
  CHECK(get_parameter(p, np::laplacian_weights) == meshfit::Laplacian_weights::inverse_distance);
  CHECK(get_parameter(p, np::laplacian_variant) == meshfit::Laplacian_variant::alpha_original);
  CHECK(get_parameter(p, np::laplacian_alpha) == 0.75);
  CHECK(get_parameter(p, np::reference_points).size() == 2);
  // The maps are the caller's: writing through what is read back shows in the mesh's own map.
  const auto v0 = *vertices(tm).begin();
  put(get_parameter(p, CGAL::internal_np::vertex_is_constrained), v0, true);
  CHECK(get(vcm, v0));
  put(get_parameter(p, CGAL::internal_np::face_patch), *faces(tm).begin(), 9);
  CHECK(get(fpm, *faces(tm).begin()) == 9);
  CHECK(get(get_parameter(p, CGAL::internal_np::vertex_point), v0) == tm.point(v0));
  get_parameter(p, np::progress)(meshfit::Progress_step{});
  CHECK(calls == 1);
}

TEST_CASE("parameters: chains start from meshfit's empty pack, and the nesting form still works from a CGAL pack",
          "[parameters]") {
  // A chain that begins with a CGAL parameter.
  const auto a = meshfit::parameters::default_values().number_of_iterations(4).step_size(0.5);
  CHECK(get_parameter(a, CGAL::internal_np::number_of_iterations) == 4);
  CHECK(get_parameter(a, np::step_size) == 0.5);

  // The two-argument form adds a meshfit parameter to a CGAL pack; the result chains on.
  const auto b = meshfit::parameters::step_size(0.125, CGAL::parameters::number_of_iterations(7)).rbf_kernel(
      meshfit::Rbf_kernel::cubic);
  CHECK(get_parameter(b, np::step_size) == 0.125);
  CHECK(get_parameter(b, CGAL::internal_np::number_of_iterations) == 7);
  CHECK(get_parameter(b, np::rbf_kernel) == meshfit::Rbf_kernel::cubic);

  // ... and to a meshfit pack, nested the old way.
  const auto c = meshfit::parameters::laplacian_alpha(0.25, b);
  CHECK(get_parameter(c, np::laplacian_alpha) == 0.25);
  CHECK(get_parameter(c, np::step_size) == 0.125);
  CHECK(get_parameter(c, CGAL::internal_np::number_of_iterations) == 7);
  const auto d = meshfit::parameters::rbf_kernel(meshfit::Rbf_kernel::linear,
                                                 meshfit::parameters::progress(Void_counter{nullptr},
                                                                               CGAL::parameters::number_of_iterations(5)));
  CHECK(get_parameter(d, np::rbf_kernel) == meshfit::Rbf_kernel::linear);
  CHECK(get_parameter(d, CGAL::internal_np::number_of_iterations) == 5);

  // A parameter that is not there is reported as not found, so defaults apply.
  using Missing = decltype(get_parameter(CGAL::parameters::number_of_iterations(1), np::step_size));
  CHECK(std::is_same_v<Missing, CGAL::internal_np::Param_not_found>);
  CHECK(choose_parameter(get_parameter(a, np::rbf_kernel), meshfit::Rbf_kernel::linear) == meshfit::Rbf_kernel::linear);
}

TEMPLATE_TEST_CASE("parameters: CGAL's functions accept a meshfit chain and read its CGAL parameters",
                   "[parameters][generic]", Surface, Polyhedron) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  TestType tm;
  CGAL::make_hexahedron(meshfit::Point_3(0, 0, 0), meshfit::Point_3(1, 0, 0), meshfit::Point_3(1, 1, 0),
                        meshfit::Point_3(0, 1, 0), meshfit::Point_3(0, 1, 1), meshfit::Point_3(0, 0, 1),
                        meshfit::Point_3(1, 0, 1), meshfit::Point_3(1, 1, 1), tm);
  REQUIRE(faces(tm).size() == 6);
  std::size_t calls = 0;
  const auto chain = meshfit::parameters::progress([&calls](const meshfit::Progress_step&) { ++calls; })
                         .rbf_kernel(meshfit::Rbf_kernel::cubic)
                         .vertex_point_map(get(CGAL::vertex_point, tm))
                         .geom_traits(meshfit::Kernel());
  CHECK(PMP::triangulate_faces(tm, chain));
  CHECK(faces(tm).size() == 12);
  CHECK(CGAL::is_triangle_mesh(tm));
  CHECK(PMP::area(tm, chain) == Approx(6.0));
  CHECK(PMP::area(tm, chain.cgal_parameters()) == Approx(6.0));  // the same pack as CGAL's type

  // The chain's vertex_point_map is the one CGAL uses: a map of points twice as far from the
  // origin gives four times the area and the same normals.
  auto doubled = get(CGAL::dynamic_vertex_property_t<meshfit::Point_3>(), tm);
  for (auto v : vertices(tm)) put(doubled, v, CGAL::ORIGIN + 2 * (get(CGAL::vertex_point, tm, v) - CGAL::ORIGIN));
  const auto doubled_chain = meshfit::parameters::laplacian_alpha(0.5).vertex_point_map(doubled);
  CHECK(PMP::area(tm, doubled_chain) == Approx(24.0));
  for (auto f : faces(tm)) {
    const meshfit::Vector_3 n = PMP::compute_face_normal(f, tm, doubled_chain);
    const meshfit::Vector_3 m = PMP::compute_face_normal(f, tm, chain);
    CHECK(n.x() == Approx(m.x()).margin(1e-12));
    CHECK(n.y() == Approx(m.y()).margin(1e-12));
    CHECK(n.z() == Approx(m.z()).margin(1e-12));
  }
  CHECK(calls == 0);  // CGAL knows nothing of meshfit's progress callback
}

TEMPLATE_TEST_CASE("parameters: a meshfit stage reads the CGAL parameters of a chain", "[parameters][generic]", Surface,
                   Polyhedron) {
  TestType tm = make_mesh<TestType>(meshfit_test::grid(6));
  auto held = get(CGAL::dynamic_vertex_property_t<bool>(), tm);
  std::vector<meshfit::Point_3> before;
  std::size_t i = 0;
  for (auto v : vertices(tm)) {
    // Perturb the inner vertices (in the plane) so that there is something to smooth.
    meshfit::Point_3 p = get(CGAL::vertex_point, tm, v);
    if (p.x() > 0 && p.x() < 6 && p.y() > 0 && p.y() < 6)
      p = meshfit::Point_3(p.x() + 0.3 * ((i % 3) - 1.0), p.y() + 0.2 * ((i % 2) - 0.5), 0);
    put(get(CGAL::vertex_point, tm), v, p);
    put(held, v, i % 5 == 0);
    before.push_back(p);
    ++i;
  }
  std::vector<std::size_t> indices;
  const meshfit::Smoothing_report r = meshfit::laplacian_flow(
      tm, meshfit::parameters::step_size(0.5)
              .progress([&indices](const meshfit::Progress_step& s) { indices.push_back(s.index); })
              .number_of_iterations(7)
              .vertex_is_constrained_map(held)
              .vertex_point_map(get(CGAL::vertex_point, tm)));
  CHECK(r.iterations == 7);
  CHECK(indices == std::vector<std::size_t>{0, 1, 2, 3, 4, 5, 6});
  CHECK(r.max_displacement > 0);
  i = 0;
  std::size_t unmoved_held = 0, held_count = 0;
  for (auto v : vertices(tm)) {
    if (get(held, v)) {
      ++held_count;
      unmoved_held += get(CGAL::vertex_point, tm, v) == before[i];
    }
    ++i;
  }
  CHECK(held_count > 0);
  CHECK(unmoved_held == held_count);
}

TEMPLATE_TEST_CASE("parameters: a progress callback returning void is called by every stage and never cancels",
                   "[parameters][progress][generic]", Surface, Polyhedron) {
  const Example& e = example();
  std::map<std::string, std::size_t> calls;
  const Void_counter counter{&calls};

  TestType tm = make_mesh<TestType>(e.mesh);
  const meshfit::Deformation_report d =
      meshfit::deform_template(tm, e.network, e.pairs, meshfit::parameters::progress(counter).number_of_iterations(10));
  CHECK(d.remaining_flips == 0);
  CHECK(calls["deform"] > 0);

  // Stage 2 on the deformed mesh, whose vertices include the network's.
  auto curve = get(CGAL::dynamic_edge_property_t<bool>(), tm);
  auto region = get(CGAL::dynamic_face_property_t<std::size_t>(), tm);
  const meshfit::Partition_report p = meshfit::partition_mesh(
      tm, e.network, meshfit::parameters::progress(counter).edge_is_constrained_map(curve).face_patch_map(region));
  CHECK(p.regions == 12);
  CHECK(calls["partition"] > 0);

  const meshfit::Smoothing_report s = meshfit::smooth_fitted_mesh(
      tm, meshfit::parameters::progress(counter).number_of_iterations(10).edge_is_constrained_map(curve));
  CHECK(s.iterations == 10);
  CHECK(calls["smooth"] == 10);

  calls.clear();
  TestType fitted = make_mesh<TestType>(e.mesh);
  meshfit::fit_template_to_curves(
      fitted, e.network, e.pairs,
      meshfit::parameters::progress(counter).mean_curvature_iterations(2).laplacian_iterations(3));
  CHECK(meshfit_test::oracle_passes(meshfit_test::check_example_fit(fitted)));
  CHECK(calls["deform"] > 0);
  CHECK(calls["partition"] > 0);
  CHECK(calls["smooth"] == 5);
  CHECK(calls["fit"] == 1);

  // A std::function returning void is accepted as well.
  calls.clear();
  const std::function<void(const meshfit::Progress_step&)> as_function = counter;
  TestType again = make_mesh<TestType>(e.mesh);
  meshfit::smooth_fitted_mesh(again, meshfit::parameters::progress(as_function).number_of_iterations(3));
  CHECK(calls["smooth"] == 3);
}

TEMPLATE_TEST_CASE("parameters: a progress callback returning false still cancels every stage", "[parameters][progress][generic]",
                   Surface, Polyhedron) {
  const Example& e = example();
  auto cancel_in = [](const char* stage) {
    return [stage](const meshfit::Progress_step& s) { return s.stage != stage; };
  };
  auto cancelled = [](const std::function<void()>& run, const char* stage) {
    try {
      run();
    } catch (const meshfit::Algorithm_failure& x) {
      return x.stage() == stage && std::string(x.what()).find("cancelled") != std::string::npos;
    }
    return false;
  };

  TestType tm = make_mesh<TestType>(e.mesh);
  CHECK(cancelled([&] { meshfit::deform_template(tm, e.network, e.pairs, meshfit::parameters::progress(cancel_in("deform"))); },
                  "deform"));
  TestType deformed = make_mesh<TestType>(e.mesh);
  meshfit::deform_template(deformed, e.network, e.pairs, meshfit::parameters::progress(cancel_in("none")));
  CHECK(cancelled([&] { meshfit::partition_mesh(deformed, e.network, meshfit::parameters::progress(cancel_in("partition"))); },
                  "partition"));
  TestType smoothed = make_mesh<TestType>(e.mesh);
  CHECK(cancelled([&] { meshfit::smooth_fitted_mesh(smoothed, meshfit::parameters::progress(cancel_in("smooth"))); },
                  "smooth"));
  for (const char* stage : {"deform", "partition", "smooth", "fit"}) {
    INFO("fit cancelled in " << stage);
    TestType fitted = make_mesh<TestType>(e.mesh);
    CHECK(cancelled(
        [&] {
          meshfit::fit_template_to_curves(fitted, e.network, e.pairs,
                                          meshfit::parameters::progress(cancel_in(stage)).number_of_iterations(10));
        },
        stage));
  }
  // A callback that returns true throughout cancels nothing.
  TestType whole = make_mesh<TestType>(e.mesh);
  CHECK_NOTHROW(meshfit::fit_template_to_curves(whole, e.network, e.pairs, meshfit::parameters::progress(cancel_in("none"))));
}

TEST_CASE("parameters: the reference shows the code's defaults, read from the code, none written by hand",
          "[parameters][doc]") {
  // No default in a public header's \cgalParamDefault is a literal number, bool or enumerator.
  const std::regex literal(R"(\\cgalParamDefault\{[^\n]*`([0-9.]+|true|false|meshfit::[A-Za-z_]+::[a-z_]+)`)");
  for (const auto& entry : std::filesystem::directory_iterator(std::string(MESHFIT_SOURCE_DIR) + "/include/meshfit")) {
    if (entry.path().extension() != ".h") continue;
    const std::string text = meshfit_test::read_text(entry.path().string());
    std::smatch m;
    INFO(entry.path().string());
    CHECK_FALSE(std::regex_search(text, m, literal));
  }
#ifndef MESHFIT_DOXYFILE
  WARN("Doxygen was not found when configuring: no reference, its aliases not checked");
#else
  // The aliases the headers use, as CMake wrote them into the Doxyfile, are the code's values.
  const std::string doxyfile = meshfit_test::read_text(MESHFIT_DOXYFILE);
  auto alias = [&](const std::string& name) {
    const std::string key = "ALIASES += \"" + name + "=`";
    const std::size_t at = doxyfile.find(key);
    INFO(name);
    REQUIRE(at != std::string::npos);
    return doxyfile.substr(at + key.size(), doxyfile.find('`', at + key.size()) - at - key.size());
  };
  const meshfit::Deform_options d;
  CHECK(alias("default_flip_prevention_rounds") == std::to_string(d.flip_prevention_rounds));
  CHECK(alias("default_memory_limit") == std::to_string(d.memory_limit));
  CHECK(alias("default_coarse_only") == (d.coarse_only ? "true" : "false"));
  CHECK((alias("default_rbf_kernel") == "meshfit::Rbf_kernel::linear" && d.rbf_kernel == meshfit::Rbf_kernel::linear));
  CHECK((alias("default_curve_density") == "meshfit::Curve_density::refine" &&
         d.curve_density == meshfit::Curve_density::refine));
  CHECK((alias("default_fine_level") == "meshfit::Fine_level::surface" && d.fine_level == meshfit::Fine_level::surface));
  CHECK(alias("default_fit_check_self_intersections") ==
        (meshfit::internal::Fit_options().check_self_intersections ? "true" : "false"));
  const meshfit::internal::Flow_settings f;
  CHECK(std::stod(alias("default_flow_step")) == f.step);
  CHECK(std::stod(alias("default_flow_alpha")) == f.alpha);
  CHECK((alias("default_flow_weights") == "meshfit::Laplacian_weights::uniform" &&
         f.weights == meshfit::Laplacian_weights::uniform));
  CHECK((alias("default_flow_variant") == "meshfit::Laplacian_variant::none" &&
         f.variant == meshfit::Laplacian_variant::none));
  // The iteration counts, as the functions run them when not given.
  auto iterations = [](auto flow) {
    Surface tm;
    meshfit::build_triangle_mesh(meshfit_test::grid(4), tm);
    return std::to_string(flow(tm).iterations);
  };
  CHECK(alias("default_smoothing_iterations") ==
        iterations([](Surface& tm) { return meshfit::smooth_fitted_mesh(tm, meshfit::parameters::smoothing_tolerance(0.0)); }));
  CHECK(std::stod(alias("default_smoothing_tolerance")) == meshfit::internal::default_smoothing_tolerance);
  const auto phases = meshfit::internal::smoothing_phases(CGAL::parameters::default_values());
  CHECK(alias("default_mean_curvature_iterations") == std::to_string(phases.mean_curvature));
  CHECK(alias("default_laplacian_iterations") == std::to_string(phases.laplacian));
  CHECK(alias("default_laplacian_flow_iterations") == iterations([](Surface& tm) { return meshfit::laplacian_flow(tm); }));
  CHECK(alias("default_mean_curvature_flow_iterations") ==
        iterations([](Surface& tm) { return meshfit::mean_curvature_flow(tm); }));
  CHECK(alias("default_modified_mean_curvature_flow_iterations") ==
        iterations([](Surface& tm) { return meshfit::modified_mean_curvature_flow(tm); }));
  CHECK(alias("default_modified_laplacian_flow_iterations") ==
        iterations([](Surface& tm) { return meshfit::modified_laplacian_flow(tm); }));
#endif
}

}  // namespace meshfit_parameters_test
