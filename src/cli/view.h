// Private to the command: the page `meshfit view` writes.
#ifndef MESHFIT_SRC_CLI_VIEW_H
#define MESHFIT_SRC_CLI_VIEW_H

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
  double merge_tolerance = 1e-9;
};

/// `text` as a JSON string. "</" is written "<\/", so that the text is also safe inside an HTML
/// <script> element (the page embeds reports this way).
std::string json_string(const std::string& text);

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
