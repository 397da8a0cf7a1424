// meshfit: what every stage's front end needs: timing, the progress callback, the point map.
#ifndef MESHFIT_INTERNAL_STAGE_SUPPORT_H
#define MESHFIT_INTERNAL_STAGE_SUPPORT_H

#include <meshfit/exceptions.h>
#include <meshfit/kernel.h>
#include <meshfit/parameters.h>
#include <meshfit/threads.h>

#include <CGAL/Named_function_parameters.h>
#include <CGAL/boost/graph/properties.h>
#include <boost/graph/graph_traits.hpp>

#include <chrono>
#include <cstddef>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace meshfit {
namespace internal {

/// "polyline 3" or "polylines 1, 4, 7" (1-based, in file order), at most ten named.
inline std::string name_polylines(const std::vector<std::size_t>& polylines) {
  std::ostringstream os;
  os << (polylines.size() == 1 ? "polyline " : "polylines ");
  for (std::size_t k = 0; k < polylines.size() && k < 10; ++k) os << (k ? ", " : "") << polylines[k] + 1;
  if (polylines.size() > 10) os << " and " << polylines.size() - 10 << " more";
  return os.str();
}

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Calls a progress callback with `step`; `false` means cancel. The callback may return `bool` (or
/// anything convertible to it) or `void` (never cancels).
template <typename Callback>
bool call_progress(const Callback& callback, const Progress_step& step) {
  static_assert(std::is_invocable_v<const Callback&, const Progress_step&>,
                "meshfit: the progress callback must be callable with a const meshfit::Progress_step&");
  using Result = std::invoke_result_t<const Callback&, const Progress_step&>;
  if constexpr (std::is_void_v<Result>) {
    callback(step);
    return true;
  } else {
    static_assert(std::is_constructible_v<bool, Result>,
                  "meshfit: the progress callback must return void or a value convertible to bool");
    return static_cast<bool>(callback(step));
  }
}

/// The `progress` named parameter (the result of get_parameter) as a Progress_callback: one that
/// never cancels when it is not given, `true` for every step of a callback returning `void`.
template <typename Progress>
Progress_callback progress_callback(const Progress& progress) {
  if constexpr (std::is_same_v<Progress, CGAL::internal_np::Param_not_found>)
    return [](const Progress_step&) { return true; };
  else
    return [progress](const Progress_step& step) { return call_progress(progress, step); };
}

/// Calls the `progress` named parameter, if given; a `false` answer cancels the stage.
template <typename Progress>
void report_progress(const Progress& progress, const char* stage, const char* step, std::size_t index,
                     std::size_t total) {
  if constexpr (!std::is_same_v<Progress, CGAL::internal_np::Param_not_found>) {
    if (!call_progress(progress, Progress_step{stage, step, index, total}))
      throw Cancelled(stage);
  }
}

/// The position of `v` as meshfit's Point_3, whatever the point type of the map.
template <typename TriangleMesh, typename VPM>
Point_3 point_of(const VPM& vpm, typename boost::graph_traits<TriangleMesh>::vertex_descriptor v) {
  const auto& p = get(vpm, v);
  return Point_3(p.x(), p.y(), p.z());
}

/// A count-valued named parameter's value `n` as a std::size_t.
/// \throws Invalid_input ("<stage>: <what> must not be negative, not <n>") when it is negative.
template <typename T>
std::size_t non_negative_count(const T& n, const char* stage, const char* what) {
  if constexpr (std::is_signed_v<T>) {
    if (n < 0)
      throw Invalid_input(std::string(stage) + ": " + what + " must not be negative, not " + std::to_string(n));
  }
  return static_cast<std::size_t>(n);
}

/// Whether a named parameter was given.
template <typename T>
constexpr bool is_given_v = !std::is_same_v<std::decay_t<T>, CGAL::internal_np::Param_not_found>;
template <typename T>
constexpr bool is_given(const T&) {
  return is_given_v<T>;
}

/// The `number_of_threads` named parameter as Scoped_number_of_threads takes it: 0 when not given.
/// \throws Invalid_input ("<stage>: number_of_threads must be at least 1, not <n>") when it is less than 1.
template <typename NamedParameters>
int threads_of(const NamedParameters& np, const char* stage) {
  const auto n = CGAL::parameters::get_parameter(np, meshfit::internal_np::number_of_threads);
  if constexpr (is_given_v<decltype(n)>) {
    if (!(n >= 1))
      throw Invalid_input(std::string(stage) + ": number_of_threads must be at least 1, not " + std::to_string(n));
    return n > 4096 ? 4096 : static_cast<int>(n);
  } else {
    return 0;
  }
}

/// Whether a point type has double Cartesian coordinates (x(), y(), z() of type double): every
/// Cartesian kernel over double (Epick, Simple_cartesian<double>, Cartesian<double>), not Epeck.
template <typename Point>
constexpr bool has_double_coordinates_v =
    std::is_same_v<std::decay_t<decltype(std::declval<const Point&>().x())>, double> &&
    std::is_same_v<std::decay_t<decltype(std::declval<const Point&>().y())>, double> &&
    std::is_same_v<std::decay_t<decltype(std::declval<const Point&>().z())>, double>;

/// Refuses, at compile time, a point type or a `geom_traits` whose coordinates are not doubles.
/// A class, so that the assertions fire where it is named (`sizeof(Kernel_check<…>)`), before the
/// errors that such points cause further on.
template <typename Point, typename NamedParameters>
struct Kernel_check {
  static_assert(has_double_coordinates_v<Point>,
                "meshfit: the mesh's points (its vertex_point_map) must have double Cartesian coordinates, as "
                "the points of Epick or Simple_cartesian<double> have: meshfit computes on copies of the "
                "coordinates as doubles (exact predicates on them) and writes doubles back, which an exact "
                "kernel such as Epeck cannot take without rounding; convert the mesh to Epick first "
                "(CGAL::copy_face_graph with a CGAL::Cartesian_converter)");
  using Traits = typename CGAL::internal_np::Lookup_named_param_def<CGAL::internal_np::geom_traits_t,
                                                                     NamedParameters, Kernel>::type;
  static_assert(std::is_same_v<std::decay_t<typename Traits::FT>, double>,
                "meshfit: geom_traits must be a Cartesian kernel over double (FT = double), such as Epick or "
                "Simple_cartesian<double>; an exact kernel such as Epeck is not supported");
};
/// The `vertex_point_map` of `np`, or the mesh's own; checks its point type (check_kernel).
template <typename TriangleMesh, typename NamedParameters>
auto vertex_point_map_of(TriangleMesh& tm, const NamedParameters& np) {
  using CGAL::parameters::choose_parameter;
  using CGAL::parameters::get_parameter;
  auto vpm = choose_parameter(get_parameter(np, CGAL::internal_np::vertex_point),
                              get_property_map(CGAL::vertex_point, tm));
  static_cast<void>(sizeof(Kernel_check<typename boost::property_traits<decltype(vpm)>::value_type, NamedParameters>));
  return vpm;
}

/// `p` as the point type `P` of a caller's map (any point type with double coordinates).
template <typename P>
P point_as(const Point_3& p) {
  if constexpr (std::is_same_v<P, Point_3>)
    return p;
  else
    return P(p.x(), p.y(), p.z());
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_STAGE_SUPPORT_H
