// Mesh writers (OFF, OBJ with regions and curve edges, PLY with patch_id and edges, STL) and the
// dispatch of mesh reading by format. Files are written under a temporary name and renamed.
#include "polygon_soup.h"
#include "text_parser.h"
#include "write_file.h"

#include <algorithm>
#include <charconv>
#include <cstring>
#include <fstream>
#include <ostream>
#include <sstream>

namespace meshfit {

Mesh_format mesh_format_of(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of("/\\");
  std::string ext = (dot == std::string::npos || (slash != std::string::npos && dot < slash))
                        ? std::string()
                        : path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == "off") return Mesh_format::off;
  if (ext == "obj") return Mesh_format::obj;
  if (ext == "ply") return Mesh_format::ply;
  if (ext == "stl") return Mesh_format::stl;
  throw Invalid_input(Input_location{path, 0, Input_location::no_offset},
                      "unknown mesh format " + internal::quote(ext) +
                          "; expected .off, .obj, .ply or .stl");
}

const char* to_string(Mesh_format format) {
  switch (format) {
    case Mesh_format::off: return "OFF";
    case Mesh_format::obj: return "OBJ";
    case Mesh_format::ply: return "PLY";
    case Mesh_format::stl: return "STL";
  }
  return "?";
}

Mesh_data parse_mesh_data(const std::string& content, Mesh_format format, const std::string& name,
                          Mesh_read_report* report) {
  internal::Polygon_soup soup;
  switch (format) {
    case Mesh_format::off: soup = internal::parse_off(content, name); break;
    case Mesh_format::obj: soup = internal::parse_obj(content, name); break;
    case Mesh_format::ply: soup = internal::parse_ply(content, name); break;
    case Mesh_format::stl: soup = internal::parse_stl(content, name); break;
  }
  if (report) {
    *report = Mesh_read_report();
    report->format = format;
  }
  return internal::validate_polygon_soup(soup, report);
}

Mesh_data read_mesh_data(std::istream& in, Mesh_format format, const std::string& name,
                         Mesh_read_report* report) {
  return parse_mesh_data(internal::read_all(in, name), format, name, report);
}

Mesh_data read_mesh_data(const std::string& path, Mesh_read_report* report) {
  const Mesh_format format = mesh_format_of(path);
  return parse_mesh_data(internal::read_file(path), format, path, report);
}

namespace {

// Shortest text that reads back to the same double.
class Number_writer {
 public:
  explicit Number_writer(std::ostream& out) : m_out(out) {}
  Number_writer& operator<<(double v) {
    if (v == 0) v = 0;  // no "-0"
    const auto r = std::to_chars(m_buf, m_buf + sizeof m_buf, v);
    m_out.write(m_buf, r.ptr - m_buf);
    return *this;
  }
  Number_writer& operator<<(std::size_t v) {
    const auto r = std::to_chars(m_buf, m_buf + sizeof m_buf, v);
    m_out.write(m_buf, r.ptr - m_buf);
    return *this;
  }
  Number_writer& operator<<(int v) {
    const auto r = std::to_chars(m_buf, m_buf + sizeof m_buf, v);
    m_out.write(m_buf, r.ptr - m_buf);
    return *this;
  }
  Number_writer& operator<<(char c) {
    m_out.put(c);
    return *this;
  }
  Number_writer& operator<<(const char* s) {
    m_out << s;
    return *this;
  }

 private:
  std::ostream& m_out;
  char m_buf[64];
};

void check_indices(const Mesh_data& mesh) {
  const std::size_t n = mesh.points.size();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (std::size_t v : mesh.triangles[t])
      if (v >= n) throw Invalid_input("triangle " + std::to_string(t) + " refers to vertex " +
                                      std::to_string(v) + " of " + std::to_string(n));
  for (std::size_t e = 0; e < mesh.curve_edges.size(); ++e)
    for (std::size_t v : mesh.curve_edges[e])
      if (v >= n) throw Invalid_input("curve edge " + std::to_string(e) + " refers to vertex " +
                                      std::to_string(v) + " of " + std::to_string(n));
  if (!mesh.face_patch.empty() && mesh.face_patch.size() != mesh.triangles.size())
    throw Invalid_input("face_patch has " + std::to_string(mesh.face_patch.size()) +
                        " entries for " + std::to_string(mesh.triangles.size()) + " triangles");
  for (const Point_3& p : mesh.points)
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || !std::isfinite(p.z()))
      throw Invalid_input("the mesh has a non-finite coordinate: refusing to write it");
}

void write_off(std::ostream& os, const Mesh_data& mesh) {
  Number_writer w(os);
  w << "OFF\n" << mesh.points.size() << ' ' << mesh.triangles.size() << " 0\n";
  for (const Point_3& p : mesh.points) w << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const auto& t : mesh.triangles) w << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
}

void write_obj(std::ostream& os, const Mesh_data& mesh) {
  Number_writer w(os);
  w << "# written by meshfit: faces grouped by region (g region_<k>), curve edges as l\n";
  for (const Point_3& p : mesh.points) w << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  // One group per region, in increasing region order (faces of a region keep their order), as
  // DESIGN.md fixes; so the faces of an OBJ come back grouped, not in the mesh's face order.
  std::vector<std::size_t> order(mesh.triangles.size());
  for (std::size_t f = 0; f < order.size(); ++f) order[f] = f;
  if (!mesh.face_patch.empty())
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return mesh.face_patch[a] < mesh.face_patch[b]; });
  bool first = true;
  int current = 0;
  for (std::size_t f : order) {
    if (!mesh.face_patch.empty() && (first || mesh.face_patch[f] != current)) {
      current = mesh.face_patch[f];
      if (current >= 0) w << "g region_" << current << '\n';
      else w << "g unassigned\n";
    }
    first = false;
    const auto& t = mesh.triangles[f];
    w << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  }
  for (const auto& e : mesh.curve_edges) w << "l " << e[0] + 1 << ' ' << e[1] + 1 << '\n';
}

template <typename T>
void put_le(std::ostream& os, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  os.write(b, sizeof(T));
}

void write_ply(std::ostream& os, const Mesh_data& mesh, Ply_encoding encoding) {
  if (mesh.points.size() > static_cast<std::size_t>(INT32_MAX))
    throw Invalid_input("PLY output is limited to 2^31-1 vertices");
  const bool patches = !mesh.face_patch.empty();
  Number_writer w(os);
  w << "ply\nformat " << (encoding == Ply_encoding::ascii ? "ascii" : "binary_little_endian")
    << " 1.0\ncomment written by meshfit\n"
    << "element vertex " << mesh.points.size()
    << "\nproperty double x\nproperty double y\nproperty double z\n"
    << "element face " << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\n";
  if (patches) w << "property int patch_id\n";
  w << "element edge " << mesh.curve_edges.size()
    << "\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  if (encoding == Ply_encoding::ascii) {
    for (const Point_3& p : mesh.points) w << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
      const auto& t = mesh.triangles[f];
      w << "3 " << t[0] << ' ' << t[1] << ' ' << t[2];
      if (patches) w << ' ' << mesh.face_patch[f];
      w << '\n';
    }
    for (const auto& e : mesh.curve_edges) w << e[0] << ' ' << e[1] << '\n';
    return;
  }
  for (const Point_3& p : mesh.points) {
    put_le<double>(os, p.x());
    put_le<double>(os, p.y());
    put_le<double>(os, p.z());
  }
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    put_le<std::uint8_t>(os, 3);
    for (std::size_t v : mesh.triangles[f]) put_le<std::int32_t>(os, static_cast<std::int32_t>(v));
    if (patches) put_le<std::int32_t>(os, mesh.face_patch[f]);
  }
  for (const auto& e : mesh.curve_edges) {
    put_le<std::int32_t>(os, static_cast<std::int32_t>(e[0]));
    put_le<std::int32_t>(os, static_cast<std::int32_t>(e[1]));
  }
}

void write_stl(std::ostream& os, const Mesh_data& mesh) {
  Number_writer w(os);
  w << "solid meshfit\n";
  for (const auto& t : mesh.triangles) {
    const Point_3 &a = mesh.points[t[0]], &b = mesh.points[t[1]], &c = mesh.points[t[2]];
    Vector_3 n = CGAL::cross_product(b - a, c - a);
    const double len = std::sqrt(n.squared_length());
    if (len > 0 && std::isfinite(len)) n = n / len;
    else n = Vector_3(0, 0, 0);
    w << "facet normal " << n.x() << ' ' << n.y() << ' ' << n.z() << "\nouter loop\n";
    for (const Point_3* p : {&a, &b, &c}) w << "vertex " << p->x() << ' ' << p->y() << ' ' << p->z() << '\n';
    w << "endloop\nendfacet\n";
  }
  w << "endsolid meshfit\n";
}

}  // namespace

void write_mesh_data(std::ostream& out, Mesh_format format, const Mesh_data& mesh,
                     Ply_encoding ply_encoding) {
  check_indices(mesh);
  switch (format) {
    case Mesh_format::off: write_off(out, mesh); break;
    case Mesh_format::obj: write_obj(out, mesh); break;
    case Mesh_format::ply: write_ply(out, mesh, ply_encoding); break;
    case Mesh_format::stl: write_stl(out, mesh); break;
  }
}

void write_mesh_data(const std::string& path, const Mesh_data& mesh, const Write_options& options) {
  const Mesh_format format = mesh_format_of(path);
  check_output_path(path, options.protected_paths);
  check_indices(mesh);
  internal::write_file_atomically(path, [&](std::ostream& os) {
    write_mesh_data(os, format, mesh, options.ply_encoding);
  });
}

}  // namespace meshfit
