// Private: what the mesh parsers produce before the mesh is checked and triangulated.
#ifndef MESHFIT_SRC_POLYGON_SOUP_H
#define MESHFIT_SRC_POLYGON_SOUP_H

#include <meshfit/io.h>

#include <algorithm>
#include <string>
#include <string_view>

namespace meshfit {
namespace internal {

struct Polygon_soup {
  std::string file;
  bool binary = false;  ///< locations are byte offsets rather than line numbers
  bool one_based = false;  ///< the file numbers vertices from 1 (OBJ): messages do too
  std::vector<Point_3> points;
  // Polygon p has corners corners[start[p]] .. corners[start[p+1]-1].
  std::vector<std::size_t> corners;
  std::vector<std::size_t> start{0};
  std::vector<std::size_t> polygon_where;  ///< line or byte offset of each polygon
  std::vector<int> polygon_patch;          ///< empty, or a region per polygon
  std::vector<std::array<std::size_t, 2>> edges;
  std::vector<std::size_t> edge_where;
  std::size_t ignored_edges = 0;  ///< listed edges that are not curve edges (PLY without `curve`)
  /// Per-vertex attributes kept (Mesh_data::vertex_uvs, …): empty or one per point.
  std::vector<std::array<double, 2>> vertex_uvs;
  std::vector<std::array<double, 3>> vertex_normals;
  std::vector<std::array<double, 4>> vertex_colors;
  /// Attributes read and not kept (Mesh_read_report::dropped_attributes); add with drop().
  std::vector<std::string> dropped_attributes;

  void drop(const std::string& attribute) {
    if (std::find(dropped_attributes.begin(), dropped_attributes.end(), attribute) == dropped_attributes.end())
      dropped_attributes.push_back(attribute);
  }

  std::size_t number_of_polygons() const { return start.size() - 1; }
  void end_polygon(std::size_t where) {
    start.push_back(corners.size());
    polygon_where.push_back(where);
  }
  Input_location location(std::size_t where) const {
    return binary ? Input_location::at_byte(file, where) : Input_location::at_line(file, where);
  }
};

Polygon_soup parse_off(std::string_view text, const std::string& name);
Polygon_soup parse_obj(std::string_view text, const std::string& name);
Polygon_soup parse_ply(std::string_view text, const std::string& name);
Polygon_soup parse_stl(std::string_view text, const std::string& name);
Polygon_soup parse_ase(std::string_view text, const std::string& name);

/// Checks the soup and triangulates its polygons (see io.h for what is checked).
Mesh_data validate_polygon_soup(const Polygon_soup& soup, Mesh_read_report* report);

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_SRC_POLYGON_SOUP_H
