// meshfit internal: vertex attributes (texture coordinates, normals, colours) carried from the
// template's vertices to the vertices the pipeline adds.
//
// The template's vertices keep their values. The added vertices get the discrete harmonic
// extension of the template's values over the result's edge graph (displacement.h at order 1:
// each added vertex's value is the mean of its neighbours', with the template's vertices fixed),
// channel by channel. The uniform weights are positive on every mesh, so each added value is a
// convex combination of template values and lies in the convex hull of its neighbours' values (a
// discrete maximum principle): UVs stay inside the template's UV range, colours inside [0, 255].
// Normals are interpolated the same way and normalised: a template vertex keeps the caller's
// normal (which may be authored, with creases), and an added vertex between two template
// vertices gets a normal between theirs, consistent with them; where the mean cancels out (less
// than 1e-9 long) the result's geometric normal is taken (normalise_added_normals). fit's
// Carried_attributes and the command line's deform both carry attributes this way.
#ifndef MESHFIT_INTERNAL_VERTEX_ATTRIBUTES_H
#define MESHFIT_INTERNAL_VERTEX_ATTRIBUTES_H

#include <meshfit/displacement.h>
#include <meshfit/exceptions.h>
#include <meshfit/internal/stage_support.h>
#include <meshfit/io.h>

#include <CGAL/IO/Color.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

namespace meshfit {
namespace internal {

/// The neighbours of every vertex of `mesh` (by the edges of its triangles).
inline Vertex_adjacency adjacency_of(const Mesh_data& mesh) { return triangle_adjacency(mesh.points.size(), mesh.triangles); }

/// Values of N channels on the first `fixed.size()` vertices, extended harmonically to the
/// others (see the top of this file). `what` names the attribute in error messages.
/// \throws Invalid_input when a template value is not finite.
template <std::size_t N>
std::vector<std::array<double, N>> harmonic_extension(const Vertex_adjacency& adjacency,
                                                      const std::vector<std::array<double, N>>& fixed,
                                                      const char* what) {
  const std::size_t n = adjacency.size();
  for (std::size_t i = 0; i < fixed.size(); ++i)
    for (double c : fixed[i])
      if (!std::isfinite(c))
        throw Invalid_input(std::string("fit: the ") + what + " of template vertex " + std::to_string(i) +
                            " is not finite");
  std::vector<std::array<double, N>> out(n);
  std::copy(fixed.begin(), fixed.end(), out.begin());
  if (n == fixed.size()) return out;
  std::vector<bool> constrained(n, false);
  std::fill(constrained.begin(), constrained.begin() + fixed.size(), true);
  // interpolate_displacements solves for three channels at a time.
  for (std::size_t c0 = 0; c0 < N; c0 += 3) {
    auto channel = [&](const std::array<double, N>& a, std::size_t c) { return c0 + c < N ? a[c0 + c] : 0.0; };
    std::vector<Vector_3> given(n, Vector_3(0, 0, 0));
    for (std::size_t i = 0; i < fixed.size(); ++i)
      given[i] = Vector_3(channel(fixed[i], 0), channel(fixed[i], 1), channel(fixed[i], 2));
    const std::vector<Vector_3> d = interpolate_displacements(adjacency, constrained, given, 1);
    for (std::size_t i = fixed.size(); i < n; ++i)
      for (std::size_t c = 0; c < 3 && c0 + c < N; ++c) out[i][c0 + c] = d[i][int(c)];
  }
  return out;
}

/// Normalises the normals of the added vertices of `result` (k ≥ `template_count`). A normal that
/// the extension cancels out (less than 1e-9 long) becomes the result's geometric normal at the
/// vertex: the sum of its triangles' normals weighted by their areas, normalised (left as it is
/// when that sum is zero too).
inline void normalise_added_normals(std::vector<std::array<double, 3>>& normals, std::size_t template_count,
                                    const Mesh_data& result) {
  auto length = [](const std::array<double, 3>& n) { return std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]); };
  std::vector<std::size_t> cancelled;
  for (std::size_t k = template_count; k < normals.size(); ++k) {
    const double len = length(normals[k]);
    if (len > 1e-9)
      for (double& c : normals[k]) c /= len;
    else
      cancelled.push_back(k);
  }
  if (cancelled.empty()) return;
  std::vector<Vector_3> area_normal(result.points.size(), Vector_3(0, 0, 0));
  for (const auto& t : result.triangles) {
    const Vector_3 n = CGAL::cross_product(result.points[t[1]] - result.points[t[0]], result.points[t[2]] - result.points[t[0]]);
    for (std::size_t v : t) area_normal[v] = area_normal[v] + n;
  }
  for (std::size_t k : cancelled) {
    const Vector_3& n = area_normal[k];
    normals[k] = {n.x(), n.y(), n.z()};
    const double len = length(normals[k]);
    if (len > 0)
      for (double& c : normals[k]) c /= len;
  }
}

/// The template's vertex attributes (`template_data`'s UVs, colours and normals, each when
/// present) carried to `result`, whose first vertices are the template's.
inline void extend_vertex_attributes(const Mesh_data& template_data, Mesh_data& result) {
  if (template_data.vertex_uvs.empty() && template_data.vertex_colors.empty() && template_data.vertex_normals.empty())
    return;
  const Vertex_adjacency adjacency = adjacency_of(result);
  if (!template_data.vertex_uvs.empty())
    result.vertex_uvs = harmonic_extension<2>(adjacency, template_data.vertex_uvs, "texture coordinates");
  if (!template_data.vertex_colors.empty())
    result.vertex_colors = harmonic_extension<4>(adjacency, template_data.vertex_colors, "colours");
  if (template_data.vertex_normals.empty()) return;
  result.vertex_normals = harmonic_extension<3>(adjacency, template_data.vertex_normals, "normals");
  normalise_added_normals(result.vertex_normals, template_data.points.size(), result);
}

/// Texture coordinates: any value with `x()`, `y()` and a constructor from two coordinates
/// (CGAL's Point_2 and Vector_2).
struct Texture_channels {
  static constexpr std::size_t size = 2;
  static constexpr const char* name = "texture coordinate";
  template <typename T>
  static std::array<double, 2> read(const T& t) {
    return {double(t.x()), double(t.y())};
  }
  template <typename T>
  static T make(const std::array<double, 2>& c) {
    return T(c[0], c[1]);
  }
};

/// Normals: any value with `x()`, `y()`, `z()` and a constructor from three coordinates.
struct Normal_channels {
  static constexpr std::size_t size = 3;
  static constexpr const char* name = "normal";
  template <typename T>
  static std::array<double, 3> read(const T& t) {
    return {double(t.x()), double(t.y()), double(t.z())};
  }
  template <typename T>
  static T make(const std::array<double, 3>& c) {
    return T(c[0], c[1], c[2]);
  }
};

/// Colours: CGAL::IO::Color (red, green, blue, alpha), rounded to the nearest integer.
struct Color_channels {
  static constexpr std::size_t size = 4;
  static constexpr const char* name = "colour";
  static std::array<double, 4> read(const CGAL::IO::Color& c) {
    return {double(c.r()), double(c.g()), double(c.b()), double(c.a())};
  }
  template <typename T>
  static T make(const std::array<double, 4>& c) {
    auto byte = [](double x) { return static_cast<unsigned char>(std::clamp(std::lround(x), 0L, 255L)); };
    return T(byte(c[0]), byte(c[1]), byte(c[2]), byte(c[3]));
  }
};

/// The values of the vertex attribute `map` on the template's vertices, extended to the result's
/// (adjacency) added vertices; empty when the map is not given.
template <typename Channels, typename Map, typename VertexRange>
std::vector<std::array<double, Channels::size>> extended_attribute(const Map& map, const VertexRange& template_vertices,
                                                                   const Vertex_adjacency& adjacency) {
  if constexpr (!is_given_v<Map>) {
    return {};
  } else {
    std::vector<std::array<double, Channels::size>> fixed;
    fixed.reserve(template_vertices.size());
    for (auto v : template_vertices) fixed.push_back(Channels::read(get(map, v)));
    return harmonic_extension(adjacency, fixed, Channels::name);
  }
}

/// Puts `values[k]` on `vertex_of[k]` through `map` for the added vertices (k ≥ `template_count`).
template <typename Channels, typename Map, typename VertexRange>
void put_extended_attribute(const Map& map, const VertexRange& vertex_of, std::size_t template_count,
                            const std::vector<std::array<double, Channels::size>>& values) {
  if constexpr (is_given_v<Map>) {
    using Value = typename boost::property_traits<Map>::value_type;
    for (std::size_t k = template_count; k < values.size(); ++k)
      put(map, vertex_of[k], Channels::template make<Value>(values[k]));
  }
}

/// The vertex attributes fit_template_to_curves carries to the added vertices: the caller's maps
/// (each possibly not given) and their values on the result's vertices.
template <typename TextureMap, typename NormalMap, typename ColorMap>
struct Carried_attributes {
  TextureMap texture_map;
  NormalMap normal_map;
  ColorMap color_map;
  std::size_t template_count = 0;
  std::vector<std::array<double, Texture_channels::size>> uvs;
  std::vector<std::array<double, Normal_channels::size>> normals;
  std::vector<std::array<double, Color_channels::size>> colors;

  Carried_attributes(const TextureMap& t, const NormalMap& n, const ColorMap& c)
      : texture_map(t), normal_map(n), color_map(c) {}

  /// The values of the given maps on the template's vertices (those of `tm`), extended to the
  /// added vertices of `result`; normals normalised (normalise_added_normals).
  /// \throws Invalid_input when a template value is not finite.
  template <typename TriangleMesh>
  void extend(const TriangleMesh& tm, const Mesh_data& result) {
    using GT = boost::graph_traits<TriangleMesh>;
    const std::vector<typename GT::vertex_descriptor> template_vertices(vertices(tm).begin(), vertices(tm).end());
    template_count = template_vertices.size();
    const Vertex_adjacency adjacency = is_given(texture_map) || is_given(normal_map) || is_given(color_map)
                                           ? adjacency_of(result)
                                           : Vertex_adjacency();
    uvs = extended_attribute<Texture_channels>(texture_map, template_vertices, adjacency);
    normals = extended_attribute<Normal_channels>(normal_map, template_vertices, adjacency);
    colors = extended_attribute<Color_channels>(color_map, template_vertices, adjacency);
    normalise_added_normals(normals, template_count, result);
  }

  /// Puts the added vertices' values, `vertex_of[k]` being the result's vertex k.
  template <typename VertexRange>
  void write(const VertexRange& vertex_of) const {
    put_extended_attribute<Texture_channels>(texture_map, vertex_of, template_count, uvs);
    put_extended_attribute<Color_channels>(color_map, vertex_of, template_count, colors);
    put_extended_attribute<Normal_channels>(normal_map, vertex_of, template_count, normals);
  }
};

/// The Carried_attributes of `np`'s `vertex_texture_map`, `vertex_normal_map` and
/// `vertex_color_map`, with no values yet.
template <typename NamedParameters>
auto carried_attributes(const NamedParameters& np) {
  using CGAL::parameters::get_parameter;
  const auto texture_map = get_parameter(np, CGAL::internal_np::vertex_texture_map);
  const auto normal_map = get_parameter(np, CGAL::internal_np::vertex_normal_map);
  const auto color_map = get_parameter(np, CGAL::internal_np::vertex_color_map);
  return Carried_attributes<std::decay_t<decltype(texture_map)>, std::decay_t<decltype(normal_map)>,
                            std::decay_t<decltype(color_map)>>(texture_map, normal_map, color_map);
}

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_INTERNAL_VERTEX_ATTRIBUTES_H
