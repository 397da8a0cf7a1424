// `meshfit view`: the inputs and results written into one self-contained HTML page. The page
// itself (viewer.html, viewer.js, three.js) is embedded at build time by cmake/embed_viewer.cmake;
// this file only adds the data: a small JSON block and the meshes as base64 typed arrays (a
// 1e6-face mesh as JSON numbers would be several times larger and slower to parse).
#include "view.h"

#include "viewer_page.h"

#include <meshfit/correspondence.h>
#include <meshfit/curve_network.h>
#include <meshfit/exceptions.h>
#include <meshfit/io.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <ostream>
#include <set>
#include <sstream>

namespace meshfit_cli {

std::string json_string(const std::string& text) {
  std::ostringstream os;
  os << '"';
  char previous = 0;
  for (const char c : text) {
    if (c == '"' || c == '\\') os << '\\' << c;
    else if (c == '/' && previous == '<') os << "\\/";
    else if (static_cast<unsigned char>(c) < 0x20)
      os << "\\u" << std::hex << std::setw(4) << std::setfill('0') << int(c) << std::dec;
    else os << c;
    previous = c;
  }
  os << '"';
  return os.str();
}

namespace {

std::string base_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

/// Typed arrays as the page decodes them: little-endian, whatever the host.
class Blobs {
 public:
  explicit Blobs(std::ostream& os) : m_os(os) {}

  template <typename T, typename Get>
  std::string write(std::size_t count, Get get) {
    static_assert(sizeof(T) == 4 || sizeof(T) == 8, "32- or 64-bit values");
    std::vector<unsigned char> bytes(count * sizeof(T));
    for (std::size_t i = 0; i < count; ++i) {
      const T value = get(i);
      std::uint64_t bits = 0;
      if constexpr (sizeof(T) == 4) {
        std::uint32_t b32;
        std::memcpy(&b32, &value, 4);
        bits = b32;
      } else {
        std::memcpy(&bits, &value, 8);
      }
      for (std::size_t k = 0; k < sizeof(T); ++k) bytes[i * sizeof(T) + k] = static_cast<unsigned char>(bits >> (8 * k));
    }
    const std::string id = "mf-blob-" + std::to_string(m_next++);
    m_os << "<script type=\"application/octet-stream\" id=\"" << id << "\">";
    write_base64(bytes);
    m_os << "</script>\n";
    return id;
  }

 private:
  void write_base64(const std::vector<unsigned char>& b) {
    static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string line;
    line.reserve(4 * (b.size() / 3 + 1));
    std::size_t i = 0;
    for (; i + 2 < b.size(); i += 3) {
      const std::uint32_t v = (std::uint32_t(b[i]) << 16) | (std::uint32_t(b[i + 1]) << 8) | b[i + 2];
      line += digits[v >> 18];
      line += digits[(v >> 12) & 63];
      line += digits[(v >> 6) & 63];
      line += digits[v & 63];
    }
    if (i < b.size()) {
      const bool two = i + 1 < b.size();
      const std::uint32_t v = (std::uint32_t(b[i]) << 16) | (two ? std::uint32_t(b[i + 1]) << 8 : 0);
      line += digits[v >> 18];
      line += digits[(v >> 12) & 63];
      line += two ? digits[(v >> 6) & 63] : '=';
      line += '=';
    }
    m_os << line;
  }

  std::ostream& m_os;
  int m_next = 0;
};

/// Positions as float32 relative to `origin` (a 1e6-translated mesh keeps its precision) and
/// multiplied by `scale` (a mesh at 1e40 does not overflow float32, one at 1e-45 does not vanish),
/// and triangles, regions and curve edges of `mesh`, as the page's JSON object for a mesh.
std::string write_mesh(Blobs& blobs, const meshfit::Mesh_data& mesh, const std::string& path,
                       const meshfit::Point_3& origin, double scale) {
  const auto& p = mesh.points;
  const auto& t = mesh.triangles;
  std::ostringstream js;
  js << "{\"name\": " << json_string(base_name(path)) << ", \"vertices\": " << p.size()
     << ", \"faces\": " << t.size() << ", \"positions\": \""
     << blobs.write<float>(3 * p.size(), [&](std::size_t i) {
          return static_cast<float>((p[i / 3][int(i % 3)] - origin[int(i % 3)]) * scale);
        })
     << "\", \"triangles\": \""
     << blobs.write<std::uint32_t>(3 * t.size(), [&](std::size_t i) { return std::uint32_t(t[i / 3][i % 3]); })
     << "\"";
  if (!mesh.face_patch.empty()) {
    const std::set<int> regions(mesh.face_patch.begin(), mesh.face_patch.end());
    js << ", \"regions\": " << regions.size() << ", \"patch\": \""
       << blobs.write<std::int32_t>(t.size(), [&](std::size_t i) { return std::int32_t(mesh.face_patch[i]); })
       << "\"";
  }
  if (!mesh.curve_edges.empty())
    js << ", \"curve_edges\": " << mesh.curve_edges.size() << ", \"curves\": \""
       << blobs.write<std::uint32_t>(2 * mesh.curve_edges.size(),
                                     [&](std::size_t i) { return std::uint32_t(mesh.curve_edges[i / 2][i % 2]); })
       << "\"";
  js << "}";
  return js.str();
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw meshfit::Invalid_input(meshfit::Input_location{path, 0, meshfit::Input_location::no_offset},
                                        "cannot be read");
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

}  // namespace

/// A result written without curve edges in the mesh file has them beside it
/// (`<result>.curves.polylines.txt`, written with exact decimals): their points are vertices.
std::string add_curve_edges_beside(meshfit::Mesh_data& mesh, const std::string& path) {
  const std::string beside = meshfit::curve_edges_path(path);
  if (!mesh.curve_edges.empty() || !std::filesystem::is_regular_file(beside)) return "";
  const meshfit::Curve_network curves = meshfit::read_curve_network(beside);
  std::map<std::array<double, 3>, std::size_t> vertex_at;
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    vertex_at.emplace(std::array<double, 3>{mesh.points[i].x(), mesh.points[i].y(), mesh.points[i].z()}, i);
  for (const auto& s : curves.segments()) {
    std::array<std::size_t, 2> e{};
    for (int k = 0; k < 2; ++k) {
      const meshfit::Point_3& p = curves.point(s[k]);
      const auto it = vertex_at.find({p.x(), p.y(), p.z()});
      if (it == vertex_at.end())
        throw meshfit::Invalid_input(meshfit::Input_location{beside, 0, meshfit::Input_location::no_offset},
                                     "a curve point is not a vertex of " + path);
      e[k] = it->second;
    }
    mesh.curve_edges.push_back(e);
  }
  return beside;
}


View_summary write_view_page(std::ostream& os, const View_inputs& in) {
  View_summary summary;
  const meshfit::Mesh_data templ = meshfit::read_mesh_data(in.template_path);
  const meshfit::Curve_network network = meshfit::read_curve_network(in.curves_path, in.merge_tolerance);
  std::vector<meshfit::Correspondence> pairs;
  if (!in.correspondences_path.empty()) {
    pairs = meshfit::read_correspondences(in.correspondences_path, network);
    for (const auto& c : pairs)
      if (c.template_vertex >= templ.points.size())
        throw meshfit::Invalid_input(c.where, "template vertex " + std::to_string(c.template_vertex) +
                                                  " does not exist (the template has " +
                                                  std::to_string(templ.points.size()) + " vertices)");
  }
  std::vector<meshfit::Mesh_data> results;
  std::vector<std::string> reports;
  for (const std::string& r : in.results) {
    results.push_back(meshfit::read_mesh_data(r));
    add_curve_edges_beside(results.back(), r);
  }
  for (const std::string& r : in.reports) reports.push_back(r.empty() ? std::string() : read_text(r));

  const meshfit::Bbox_3& box = network.bbox();
  const meshfit::Point_3 origin((box.xmin() + box.xmax()) / 2, (box.ymin() + box.ymax()) / 2,
                                (box.zmin() + box.zmax()) / 2);
  // The page draws in a frame where the network's largest side is in [1, 2): a power of two, so
  // that the page's file coordinates map to it exactly.
  const double side = std::max({box.xmax() - box.xmin(), box.ymax() - box.ymin(), box.zmax() - box.zmin()});
  const double scale = side > 0 && std::isfinite(side) ? std::ldexp(1.0, -std::ilogb(side)) : 1.0;
  for (const char* chunk : viewer_page_head) os << chunk;
  Blobs blobs(os);
  std::ostringstream js;
  js << std::setprecision(17);
  js << "{\"format\": 1, \"origin\": [" << origin.x() << ", " << origin.y() << ", " << origin.z() << "], "
     << "\"scale\": " << scale << ", \"tolerance\": " << network.tolerance()
     << ",\n\"template\": " << write_mesh(blobs, templ, in.template_path, origin, scale);
  const auto& np = network.points();
  js << ",\n\"network\": {\"name\": " << json_string(base_name(in.curves_path)) << ", \"vertices\": " << np.size()
     << ", \"segments\": " << network.number_of_segments() << ", \"points\": \""
     << blobs.write<double>(3 * np.size(), [&](std::size_t i) { return np[i / 3][int(i % 3)]; })
     << "\", \"segment_ends\": \""
     << blobs.write<std::uint32_t>(2 * network.number_of_segments(),
                                   [&](std::size_t i) { return std::uint32_t(network.segments()[i / 2][i % 2]); })
     << "\", \"feature_points\": " << network.feature_points().size() << "}";
  js << ",\n\"pairs_name\": "
     << json_string(in.correspondences_path.empty() ? "pairs.txt" : base_name(in.correspondences_path))
     << ", \"pairs\": [";
  for (std::size_t k = 0; k < pairs.size(); ++k)
    js << (k ? ", " : "") << "[" << pairs[k].template_vertex << ", " << pairs[k].network_vertex << "]";
  js << "],\n\"results\": [";
  for (std::size_t k = 0; k < results.size(); ++k) {
    std::string mesh = write_mesh(blobs, results[k], in.results[k], origin, scale);
    mesh.pop_back();  // the closing brace: the report goes inside the result's object
    const bool has_report = k < reports.size() && !in.reports[k].empty();
    js << (k ? ",\n" : "") << mesh << ", \"report_name\": " << (has_report ? json_string(base_name(in.reports[k])) : "null")
       << ", \"report\": " << (has_report ? json_string(reports[k]) : "null") << "}";
    summary.result_faces += results[k].triangles.size();
  }
  js << "]}";
  os << "<script type=\"application/json\" id=\"mf-data\">" << js.str() << "</script>\n";
  for (const char* chunk : viewer_page_tail) os << chunk;

  summary.template_faces = templ.triangles.size();
  summary.network_vertices = np.size();
  summary.pairs = pairs.size();
  return summary;
}

}  // namespace meshfit_cli
