// meshfit: validating the inputs of a fit against each other, and summarising them.
#ifndef MESHFIT_CHECK_H
#define MESHFIT_CHECK_H

#include <meshfit/correspondence.h>
#include <meshfit/curve_network.h>
#include <meshfit/io.h>

#include <cstddef>
#include <string>
#include <vector>

namespace meshfit {

/// Topology of a triangle mesh.
struct Mesh_summary {
  std::size_t vertices = 0;           ///< vertices, isolated ones included
  std::size_t faces = 0;              ///< triangles
  std::size_t edges = 0;              ///< edges of the triangles
  std::size_t boundaries = 0;         ///< boundary cycles
  std::size_t components = 0;         ///< connected components with at least one face
  std::size_t genus = 0;              ///< summed over components
  std::size_t isolated_vertices = 0;  ///< vertices no face uses
};

/// Computes the topology of `mesh`. \pre `mesh` passed the checks of read_mesh_data.
Mesh_summary summarize_mesh(const Mesh_data& mesh);

/// Smallest interior angle of the mesh's triangles, in degrees (floating point, a quality figure;
/// 0 for a degenerate triangle; 180 for a mesh without triangles).
double minimum_angle_degrees(const Mesh_data& mesh);

/// What `meshfit check` reports.
struct Check_summary {
  Mesh_summary mesh;                   ///< topology of the template
  Mesh_read_report mesh_report;        ///< what reading the template found
  std::size_t network_vertices = 0;    ///< Curve_network::number_of_vertices()
  std::size_t network_segments = 0;    ///< Curve_network::number_of_segments()
  std::size_t feature_points = 0;      ///< network vertices of more than two segments
  std::size_t endpoints = 0;           ///< network vertices of one segment
  std::size_t closed_polylines = 0;    ///< Curve_network::number_of_closed_polylines()
  std::size_t curves = 0;              ///< Curve_network::curves()
  std::size_t independent_cycles = 0;  ///< Curve_network::number_of_independent_cycles()
  std::size_t network_components = 0;  ///< Curve_network::number_of_components()
  std::size_t correspondences = 0;     ///< pairs read
  /// Things that do not stop a fit but that a user should know (degenerate faces, …).
  std::vector<std::string> problems;
};

/// Reads the three inputs of a fit and validates them against each other.
/// \throws Invalid_input naming the file, the line or element and the problem.
Check_summary check_inputs(const std::string& template_path, const std::string& curves_path,
                           const std::string& correspondences_path,
                           double relative_merge_tolerance = default_merge_tolerance);

}  // namespace meshfit

#endif  // MESHFIT_CHECK_H
