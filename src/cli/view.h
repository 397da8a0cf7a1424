// Private to the command: the page `meshfit view` writes.
#ifndef MESHFIT_SRC_CLI_VIEW_H
#define MESHFIT_SRC_CLI_VIEW_H

#include <meshfit/curve_network.h>
#include <meshfit/io.h>

#include <iosfwd>
#include <string>
#include <vector>

namespace meshfit_cli {

struct View_inputs {
  std::string template_path;
  std::string curves_path;
  std::string correspondences_path;  ///< "" when none
  std::vector<std::string> results;  ///< meshes to show (fit's output, or one per stage)
  std::vector<std::string> reports;  ///< report k belongs to result k; at most one per result
  double merge_tolerance = meshfit::default_merge_tolerance;
};

/// `text` as a JSON string. "</" is written "<\/", so that the text is also safe inside an HTML
/// <script> element (the page embeds reports this way).
std::string json_string(const std::string& text);

/// Gives `mesh`, read from `path` without curve edges, those of the file meshfit writes beside its
/// outputs (`<path>.curves.polylines.txt`, exact decimals: each point is a vertex of the mesh).
/// Returns that file's path, or "" when the mesh has curve edges or there is no such file.
/// \throws meshfit::Invalid_input naming the file when it is malformed or a point is not a vertex.
std::string add_curve_edges_beside(meshfit::Mesh_data& mesh, const std::string& path);

/// What went into the page, for the command's summary line.
struct View_summary {
  std::size_t template_faces = 0;
  std::size_t network_vertices = 0;
  std::size_t pairs = 0;
  std::size_t result_faces = 0;  ///< all results together
};

/// Reads the inputs and writes one self-contained HTML page (three.js, the viewer and the meshes
/// inlined; meshes as base64 little-endian typed arrays) to `os`.
/// \throws meshfit::Invalid_input naming the file for unreadable or malformed inputs, and for a
///         pair whose template vertex does not exist.
View_summary write_view_page(std::ostream& os, const View_inputs& in);

}  // namespace meshfit_cli

#endif  // MESHFIT_SRC_CLI_VIEW_H
