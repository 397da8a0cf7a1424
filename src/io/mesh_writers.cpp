// Mesh writers (OFF, OBJ with regions, PLY with patch_id, VTK PolyData (XML and legacy) with region
// and curve cell data, STL; curve edges in OBJ/PLY on request, else in a polyline file of their own)
// and the dispatch of mesh reading by format. Files are written under a temporary name and renamed.
#include "polygon_soup.h"
#include "text_parser.h"
#include "write_file.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>

#include <unistd.h>

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
  if (ext == "vtp") return Mesh_format::vtp;
  if (ext == "vtk") return Mesh_format::vtk;
  if (ext == "ase") return Mesh_format::ase;
  throw Invalid_input(Input_location{path, 0, Input_location::no_offset},
                      "unknown mesh format " + internal::quote(ext) +
                          "; expected .off, .obj, .ply or .stl (or, for outputs, .vtp or .vtk; for "
                          "templates, .ase)");
}

const char* to_string(Mesh_format format) {
  switch (format) {
    case Mesh_format::off: return "OFF";
    case Mesh_format::obj: return "OBJ";
    case Mesh_format::ply: return "PLY";
    case Mesh_format::stl: return "STL";
    case Mesh_format::vtp: return "VTP";
    case Mesh_format::vtk: return "VTK";
    case Mesh_format::ase: return "ASE";
  }
  return "?";
}

const char* extension_of(Mesh_format format) {
  switch (format) {
    case Mesh_format::off: return "off";
    case Mesh_format::obj: return "obj";
    case Mesh_format::ply: return "ply";
    case Mesh_format::stl: return "stl";
    case Mesh_format::vtp: return "vtp";
    case Mesh_format::vtk: return "vtk";
    case Mesh_format::ase: return "ase";
  }
  return "";
}

Mesh_data parse_mesh_data(const std::string& content, Mesh_format format, const std::string& name,
                          Mesh_read_report* report) {
  internal::Polygon_soup soup;
  switch (format) {
    case Mesh_format::off: soup = internal::parse_off(content, name); break;
    case Mesh_format::obj: soup = internal::parse_obj(content, name); break;
    case Mesh_format::ply: soup = internal::parse_ply(content, name); break;
    case Mesh_format::stl: soup = internal::parse_stl(content, name); break;
    case Mesh_format::ase: soup = internal::parse_ase(content, name); break;
    case Mesh_format::vtp:
    case Mesh_format::vtk:
      throw Invalid_input(Input_location{name, 0, Input_location::no_offset},
                          std::string(to_string(format)) +
                              " is an output format only: read meshes from .off, .obj, .ply, .stl or .ase");
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
  auto check_attribute = [&](const auto& values, const char* what) {
    if (values.empty()) return;
    if (values.size() != n)
      throw Invalid_input(std::string(what) + " has " + std::to_string(values.size()) + " entries for " +
                          std::to_string(n) + " vertices");
    for (const auto& a : values)
      for (double c : a)
        if (!std::isfinite(c)) throw Invalid_input(std::string("the mesh has a non-finite value in ") + what);
  };
  check_attribute(mesh.vertex_uvs, "vertex_uvs");
  check_attribute(mesh.vertex_normals, "vertex_normals");
  check_attribute(mesh.vertex_colors, "vertex_colors");
}

// A colour channel in [0, 1] as a byte (PLY `uchar red`, …).
std::uint8_t colour_byte(double c) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(c, 0.0, 1.0) * 255));
}


// One line per vertex: its attribute's components, colours as bytes (colour_byte).
template <typename Values>
void write_attribute_rows(Number_writer& w, const Values& values, bool bytes) {
  for (const auto& a : values) {
    for (std::size_t k = 0; k < a.size(); ++k) {
      if (k) w << ' ';
      if (bytes) w << int(colour_byte(a[k]));
      else w << a[k];
    }
    w << '\n';
  }
}

}  // namespace

std::array<std::uint8_t, 3> region_colour(int region) {
  if (region < 0) return {128, 128, 128};
  // HSL to RGB (as THREE.Color.setHSL in the viewer).
  const double h = std::fmod(region * 0.381966, 1.0), s = 0.65, l = 0.58;
  const double q = l < 0.5 ? l * (1 + s) : l + s - l * s, p = 2 * l - q;
  auto channel = [&](double t) {
    t = t < 0 ? t + 1 : t > 1 ? t - 1 : t;
    const double c = t < 1.0 / 6 ? p + (q - p) * 6 * t : t < 0.5 ? q : t < 2.0 / 3 ? p + (q - p) * (2.0 / 3 - t) * 6 : p;
    return colour_byte(c);
  };
  return {channel(h + 1.0 / 3), channel(h), channel(h - 1.0 / 3)};
}

namespace {

void write_off(std::ostream& os, const Mesh_data& mesh) {
  Number_writer w(os);
  w << "OFF\n" << mesh.points.size() << ' ' << mesh.triangles.size() << " 0\n";
  for (const Point_3& p : mesh.points) w << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (const auto& t : mesh.triangles) w << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
}

// The material of region `k` in a material library (write_material_library).
std::string material_name(int k) { return k >= 0 ? "region_" + std::to_string(k) : std::string("unassigned"); }

void write_obj(std::ostream& os, const Mesh_data& mesh, bool curves_in_mesh, const std::string& material_library) {
  Number_writer w(os);
  w << (curves_in_mesh ? "# written by meshfit: faces grouped by region (g region_<k>), curve edges as l\n"
                       : "# written by meshfit: faces grouped by region (g region_<k>)\n");
  const bool materials = !material_library.empty() && !mesh.face_patch.empty();
  if (materials) w << "mtllib " << material_library.c_str() << '\n';
  // Vertex colours as `v x y z r g b` (the common extension); texture coordinates and normals one
  // per vertex, `vt`/`vn` k being vertex k's, so that every corner is `v/v/v`.
  const bool uvs = !mesh.vertex_uvs.empty(), normals = !mesh.vertex_normals.empty(),
             colours = !mesh.vertex_colors.empty();
  for (std::size_t i = 0; i < mesh.points.size(); ++i) {
    const Point_3& p = mesh.points[i];
    w << "v " << p.x() << ' ' << p.y() << ' ' << p.z();
    if (colours) w << ' ' << mesh.vertex_colors[i][0] << ' ' << mesh.vertex_colors[i][1] << ' ' << mesh.vertex_colors[i][2];
    w << '\n';
  }
  if (uvs)
    for (const auto& t : mesh.vertex_uvs) w << "vt " << t[0] << ' ' << t[1] << '\n';
  if (normals)
    for (const auto& n : mesh.vertex_normals) w << "vn " << n[0] << ' ' << n[1] << ' ' << n[2] << '\n';
  auto corner = [&](std::size_t v) {
    w << v + 1;
    if (uvs || normals) w << '/';
    if (uvs) w << v + 1;
    if (normals) w << '/' << v + 1;
  };
  // One group per region, in increasing region order (faces of a region keep their order), as
  // doc/design.md fixes; so the faces of an OBJ come back grouped, not in the mesh's face order.
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
      if (materials) w << "usemtl " << material_name(current).c_str() << '\n';
    }
    first = false;
    const auto& t = mesh.triangles[f];
    w << "f ";
    corner(t[0]);
    w << ' ';
    corner(t[1]);
    w << ' ';
    corner(t[2]);
    w << '\n';
  }
  if (curves_in_mesh)
    for (const auto& e : mesh.curve_edges) w << "l " << e[0] + 1 << ' ' << e[1] + 1 << '\n';
}

template <typename T>
void put_le(std::ostream& os, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  os.write(b, sizeof(T));
}

void write_ply(std::ostream& os, const Mesh_data& mesh, Ply_encoding encoding, bool curves_in_mesh) {
  if (mesh.points.size() > static_cast<std::size_t>(INT32_MAX))
    throw Invalid_input("PLY output is limited to 2^31-1 vertices");
  const bool patches = !mesh.face_patch.empty();
  Number_writer w(os);
  w << "ply\nformat " << (encoding == Ply_encoding::ascii ? "ascii" : "binary_little_endian")
    << " 1.0\ncomment written by meshfit\n"
    << "element vertex " << mesh.points.size()
    << "\nproperty double x\nproperty double y\nproperty double z\n";
  const bool uvs = !mesh.vertex_uvs.empty(), normals = !mesh.vertex_normals.empty(),
             colours = !mesh.vertex_colors.empty();
  if (uvs) w << "property double u\nproperty double v\n";
  if (normals) w << "property double nx\nproperty double ny\nproperty double nz\n";
  if (colours) w << "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n";
  w << "element face " << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\n";
  // The regions' colours beside their numbers: viewers that show no `patch_id` (f3d) show them.
  if (patches) w << "property int patch_id\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n";
  // No empty element (meshio refuses `element edge 0`); the flag tells curve edges from a list of
  // every edge, which is what CGAL's write_PLY writes.
  const bool edges = curves_in_mesh && !mesh.curve_edges.empty();
  if (edges)
    w << "element edge " << mesh.curve_edges.size()
      << "\nproperty int vertex1\nproperty int vertex2\nproperty int curve\n";
  w << "end_header\n";
  if (encoding == Ply_encoding::ascii) {
    for (std::size_t i = 0; i < mesh.points.size(); ++i) {
      const Point_3& p = mesh.points[i];
      w << p.x() << ' ' << p.y() << ' ' << p.z();
      if (uvs) w << ' ' << mesh.vertex_uvs[i][0] << ' ' << mesh.vertex_uvs[i][1];
      if (normals) w << ' ' << mesh.vertex_normals[i][0] << ' ' << mesh.vertex_normals[i][1] << ' ' << mesh.vertex_normals[i][2];
      if (colours)
        for (double c : mesh.vertex_colors[i]) w << ' ' << int(colour_byte(c));
      w << '\n';
    }
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
      const auto& t = mesh.triangles[f];
      w << "3 " << t[0] << ' ' << t[1] << ' ' << t[2];
      if (patches) {
        const auto c = region_colour(mesh.face_patch[f]);
        w << ' ' << mesh.face_patch[f] << ' ' << int(c[0]) << ' ' << int(c[1]) << ' ' << int(c[2]);
      }
      w << '\n';
    }
    if (edges)
      for (const auto& e : mesh.curve_edges) w << e[0] << ' ' << e[1] << " 1\n";
    return;
  }
  for (std::size_t i = 0; i < mesh.points.size(); ++i) {
    const Point_3& p = mesh.points[i];
    put_le<double>(os, p.x());
    put_le<double>(os, p.y());
    put_le<double>(os, p.z());
    if (uvs)
      for (double c : mesh.vertex_uvs[i]) put_le<double>(os, c);
    if (normals)
      for (double c : mesh.vertex_normals[i]) put_le<double>(os, c);
    if (colours)
      for (double c : mesh.vertex_colors[i]) put_le<std::uint8_t>(os, colour_byte(c));
  }
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    put_le<std::uint8_t>(os, 3);
    for (std::size_t v : mesh.triangles[f]) put_le<std::int32_t>(os, static_cast<std::int32_t>(v));
    if (patches) {
      put_le<std::int32_t>(os, mesh.face_patch[f]);
      for (std::uint8_t c : region_colour(mesh.face_patch[f])) put_le<std::uint8_t>(os, c);
    }
  }
  if (edges)
    for (const auto& e : mesh.curve_edges) {
      put_le<std::int32_t>(os, static_cast<std::int32_t>(e[0]));
      put_le<std::int32_t>(os, static_cast<std::int32_t>(e[1]));
      put_le<std::int32_t>(os, 1);
    }
}

// Cells in VTK PolyData order (lines before polygons): the curve edges, then the triangles.
// Cell data `region` (-1 on lines) and `curve` (1 on lines) let f3d and ParaView colour either.
void write_vtp(std::ostream& os, const Mesh_data& mesh) {
  if (mesh.points.size() > static_cast<std::size_t>(INT32_MAX))
    throw Invalid_input("VTK output is limited to 2^31-1 vertices");
  Number_writer w(os);
  const std::size_t nl = mesh.curve_edges.size(), nt = mesh.triangles.size();
  w << "<?xml version=\"1.0\"?>\n<!-- written by meshfit -->\n"
    << "<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n<PolyData>\n"
    << "<Piece NumberOfPoints=\"" << mesh.points.size() << "\" NumberOfVerts=\"0\" NumberOfLines=\"" << nl
    << "\" NumberOfStrips=\"0\" NumberOfPolys=\"" << nt << "\">\n"
    << "<Points>\n<DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const Point_3& p : mesh.points) w << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  w << "</DataArray>\n</Points>\n";
  // The vertex attributes as point data: texture coordinates and normals as VTK's active TCoords
  // and Normals, colours as bytes (RGBA; f3d and ParaView show them with --scalars=Colors).
  const bool uvs = !mesh.vertex_uvs.empty(), normals = !mesh.vertex_normals.empty(),
             colours = !mesh.vertex_colors.empty();
  if (uvs || normals || colours) {
    w << "<PointData" << (uvs ? " TCoords=\"TCoords\"" : "") << (normals ? " Normals=\"Normals\"" : "") << ">\n";
    auto array = [&](const char* type, const char* name, const auto& values, bool bytes) {
      w << "<DataArray type=\"" << type << "\" Name=\"" << name << "\" NumberOfComponents=\""
        << values.front().size() << "\" format=\"ascii\">\n";
      write_attribute_rows(w, values, bytes);
      w << "</DataArray>\n";
    };
    if (uvs) array("Float64", "TCoords", mesh.vertex_uvs, false);
    if (normals) array("Float64", "Normals", mesh.vertex_normals, false);
    if (colours) array("UInt8", "Colors", mesh.vertex_colors, true);
    w << "</PointData>\n";
  }
  w << "<CellData Scalars=\"region\">\n"
    << "<DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n";
  for (std::size_t e = 0; e < nl; ++e) w << "-1\n";
  for (std::size_t f = 0; f < nt; ++f) w << (mesh.face_patch.empty() ? 0 : mesh.face_patch[f]) << '\n';
  w << "</DataArray>\n<DataArray type=\"Int32\" Name=\"curve\" format=\"ascii\">\n";
  for (std::size_t e = 0; e < nl; ++e) w << "1\n";
  for (std::size_t f = 0; f < nt; ++f) w << "0\n";
  w << "</DataArray>\n</CellData>\n";
  auto cells = [&](const char* section, auto&& range, std::size_t corners) {
    w << '<' << section << ">\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (const auto& c : range) {
      for (std::size_t k = 0; k < corners; ++k) w << (k ? " " : "") << c[k];
      w << '\n';
    }
    w << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (std::size_t i = 1; i <= range.size(); ++i) w << i * corners << '\n';
    w << "</DataArray>\n</" << section << ">\n";
  };
  cells("Lines", mesh.curve_edges, 2);
  cells("Polys", mesh.triangles, 3);
  w << "</Piece>\n</PolyData>\n</VTKFile>\n";
}

// Legacy VTK as an unstructured grid (meshio reads no legacy POLYDATA; f3d and ParaView read both):
// the same cells and cell data as write_vtp, lines (VTK_LINE, 3) before triangles (VTK_TRIANGLE, 5).
void write_vtk(std::ostream& os, const Mesh_data& mesh) {
  if (mesh.points.size() > static_cast<std::size_t>(INT32_MAX))
    throw Invalid_input("VTK output is limited to 2^31-1 vertices");
  Number_writer w(os);
  const std::size_t nl = mesh.curve_edges.size(), nt = mesh.triangles.size();
  w << "# vtk DataFile Version 4.2\nwritten by meshfit: cell data region and curve\nASCII\n"
    << "DATASET UNSTRUCTURED_GRID\nPOINTS " << mesh.points.size() << " double\n";
  for (const Point_3& p : mesh.points) w << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  w << "CELLS " << nl + nt << ' ' << 3 * nl + 4 * nt << '\n';
  for (const auto& e : mesh.curve_edges) w << "2 " << e[0] << ' ' << e[1] << '\n';
  for (const auto& t : mesh.triangles) w << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  w << "CELL_TYPES " << nl + nt << '\n';
  for (std::size_t e = 0; e < nl; ++e) w << "3\n";
  for (std::size_t f = 0; f < nt; ++f) w << "5\n";
  w << "CELL_DATA " << nl + nt << "\nSCALARS region int 1\nLOOKUP_TABLE default\n";
  for (std::size_t e = 0; e < nl; ++e) w << "-1\n";
  for (std::size_t f = 0; f < nt; ++f) w << (mesh.face_patch.empty() ? 0 : mesh.face_patch[f]) << '\n';
  w << "SCALARS curve int 1\nLOOKUP_TABLE default\n";
  for (std::size_t e = 0; e < nl; ++e) w << "1\n";
  for (std::size_t f = 0; f < nt; ++f) w << "0\n";
  // The vertex attributes as point data arrays of a FIELD (meshio's legacy reader knows no
  // TEXTURE_COORDINATES or NORMALS section): TCoords, Normals, Colors (RGBA bytes), as in write_vtp.
  const std::size_t n = mesh.points.size();
  const int arrays = int(!mesh.vertex_uvs.empty()) + int(!mesh.vertex_normals.empty()) + int(!mesh.vertex_colors.empty());
  if (arrays == 0) return;
  w << "POINT_DATA " << n << "\nFIELD attributes " << arrays << '\n';
  auto array = [&](const char* name, const auto& values, bool bytes) {
    if (values.empty()) return;
    w << name << ' ' << values.front().size() << ' ' << n << (bytes ? " unsigned_char\n" : " double\n");
    write_attribute_rows(w, values, bytes);
  };
  array("TCoords", mesh.vertex_uvs, false);
  array("Normals", mesh.vertex_normals, false);
  array("Colors", mesh.vertex_colors, true);
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
                     const Write_options& options) {
  check_indices(mesh);
  switch (format) {
    case Mesh_format::off: write_off(out, mesh); break;
    case Mesh_format::obj: write_obj(out, mesh, options.curves_in_mesh, options.material_library); break;
    case Mesh_format::ply: write_ply(out, mesh, options.ply_encoding, options.curves_in_mesh); break;
    case Mesh_format::stl: write_stl(out, mesh); break;
    case Mesh_format::vtp: write_vtp(out, mesh); break;
    case Mesh_format::vtk: write_vtk(out, mesh); break;
    case Mesh_format::ase:
      throw Invalid_input("ASE is an input format only: write meshes as .off, .obj, .ply, .stl, .vtp or .vtk");
  }
}

void write_mesh_data(std::ostream& out, Mesh_format format, const Mesh_data& mesh,
                     Ply_encoding ply_encoding) {
  Write_options options;
  options.ply_encoding = ply_encoding;
  write_mesh_data(out, format, mesh, options);
}

void write_mesh_data(const std::string& path, const Mesh_data& mesh, const Write_options& options) {
  const Mesh_format format = mesh_format_of(path);
  if (format == Mesh_format::ase)
    throw Invalid_input(Input_location{path, 0, Input_location::no_offset},
                        "ASE is an input format only: write meshes as .off, .obj, .ply, .stl, .vtp or .vtk");
  check_output_path(path, options.protected_paths);
  check_indices(mesh);
  internal::write_file_atomically(path, [&](std::ostream& os) {
    write_mesh_data(os, format, mesh, options);
  });
}

std::vector<std::vector<std::size_t>> curve_edge_chains(const Mesh_data& mesh) {
  // Adjacency by vertex, edges numbered in input order; a walk starts at every vertex whose
  // curve degree is not 2, then the loops left over start at their lowest-numbered edge.
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> around;  // vertex -> (edge, other end)
  std::size_t n = 0;
  for (const auto& e : mesh.curve_edges) n = std::max({n, e[0] + 1, e[1] + 1});
  around.resize(n);
  for (std::size_t k = 0; k < mesh.curve_edges.size(); ++k) {
    const auto& e = mesh.curve_edges[k];
    around[e[0]].push_back({k, e[1]});
    around[e[1]].push_back({k, e[0]});
  }
  std::vector<bool> used(mesh.curve_edges.size(), false);
  std::vector<std::vector<std::size_t>> chains;
  auto walk = [&](std::size_t v, std::size_t first_edge) {
    std::vector<std::size_t> chain{v};
    std::size_t edge = first_edge;
    while (true) {
      used[edge] = true;
      const auto& ce = mesh.curve_edges[edge];
      v = ce[0] == v ? ce[1] : ce[0];
      chain.push_back(v);
      if (around[v].size() != 2) break;
      const auto& next = around[v][0].first == edge ? around[v][1] : around[v][0];
      if (used[next.first]) break;
      edge = next.first;
    }
    chains.push_back(std::move(chain));
  };
  for (std::size_t v = 0; v < n; ++v)
    if (around[v].size() != 2)
      for (const auto& a : around[v])
        if (!used[a.first]) walk(v, a.first);
  for (std::size_t k = 0; k < used.size(); ++k)
    if (!used[k]) walk(mesh.curve_edges[k][0], k);
  return chains;
}

std::string curve_edges_path(const std::string& output) { return output + ".curves.polylines.txt"; }

std::string material_library_path(const std::string& output) { return output + ".mtl"; }

void write_material_library(const std::string& path, const Mesh_data& mesh, const Write_options& options) {
  check_output_path(path, options.protected_paths);
  check_indices(mesh);
  if (mesh.face_patch.empty()) return;
  std::vector<int> regions = mesh.face_patch;
  std::sort(regions.begin(), regions.end());
  regions.erase(std::unique(regions.begin(), regions.end()), regions.end());
  internal::write_file_atomically(path, [&](std::ostream& os) {
    Number_writer w(os);
    w << "# written by meshfit: one material per region, its colour as in the .ply output\n";
    for (int k : regions) {
      const auto c = region_colour(k);
      w << "newmtl " << material_name(k).c_str() << "\nKd " << c[0] / 255.0 << ' ' << c[1] / 255.0 << ' '
        << c[2] / 255.0 << '\n';
    }
  });
}

void write_curve_edges(const std::string& path, const Mesh_data& mesh, const Write_options& options) {
  check_output_path(path, options.protected_paths);
  check_indices(mesh);
  const auto chains = curve_edge_chains(mesh);
  internal::write_file_atomically(path, [&](std::ostream& os) {
    Number_writer w(os);
    w << "# curve edges written by meshfit: one chain of mesh edges per line, N x1 y1 z1 ... xN yN zN\n";
    for (const auto& chain : chains) {
      w << chain.size();
      for (std::size_t v : chain) {
        const Point_3& p = mesh.points[v];
        w << ' ' << p.x() << ' ' << p.y() << ' ' << p.z();
      }
      w << '\n';
    }
  });
}

// ---- one mesh per region ------------------------------------------------------------------------

std::vector<Region_mesh> split_by_region(const Mesh_data& mesh) {
  const std::size_t n = mesh.points.size(), nt = mesh.triangles.size();
  if (!mesh.face_patch.empty() && mesh.face_patch.size() != nt)
    throw Invalid_input("face_patch has " + std::to_string(mesh.face_patch.size()) + " entries for " +
                        std::to_string(nt) + " triangles");
  for (std::size_t t = 0; t < nt; ++t)
    for (std::size_t v : mesh.triangles[t])
      if (v >= n) throw Invalid_input("triangle " + std::to_string(t) + " refers to vertex " +
                                      std::to_string(v) + " of " + std::to_string(n));
  auto region_of = [&](std::size_t t) { return mesh.face_patch.empty() ? 0 : mesh.face_patch[t]; };
  std::vector<int> ids;
  for (std::size_t t = 0; t < nt; ++t) ids.push_back(region_of(t));
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());

  std::vector<Region_mesh> regions(ids.size());
  std::vector<std::size_t> slot(nt);
  for (std::size_t r = 0; r < ids.size(); ++r) regions[r].region = ids[r];
  for (std::size_t t = 0; t < nt; ++t) {
    slot[t] = static_cast<std::size_t>(std::lower_bound(ids.begin(), ids.end(), region_of(t)) - ids.begin());
    regions[slot[t]].face_in_full.push_back(t);
  }
  // Local vertices in increasing order of their full index, so a region file lists its vertices
  // in the order of the full output.
  constexpr std::size_t none = static_cast<std::size_t>(-1);
  std::vector<std::size_t> local(n, none);
  for (Region_mesh& r : regions) {
    for (std::size_t t : r.face_in_full)
      for (std::size_t v : mesh.triangles[t]) r.vertex_in_full.push_back(v);
    std::sort(r.vertex_in_full.begin(), r.vertex_in_full.end());
    r.vertex_in_full.erase(std::unique(r.vertex_in_full.begin(), r.vertex_in_full.end()), r.vertex_in_full.end());
    r.mesh.points.reserve(r.vertex_in_full.size());
    for (std::size_t i = 0; i < r.vertex_in_full.size(); ++i) {
      local[r.vertex_in_full[i]] = i;
      r.mesh.points.push_back(mesh.points[r.vertex_in_full[i]]);
    }
    // The vertices' texture coordinates, normals and colours go with them.
    auto carry = [&](const auto& full, auto& part) {
      if (full.size() != n) return;
      for (std::size_t v : r.vertex_in_full) part.push_back(full[v]);
    };
    carry(mesh.vertex_uvs, r.mesh.vertex_uvs);
    carry(mesh.vertex_normals, r.mesh.vertex_normals);
    carry(mesh.vertex_colors, r.mesh.vertex_colors);
    r.mesh.triangles.reserve(r.face_in_full.size());
    for (std::size_t t : r.face_in_full) {
      const auto& tri = mesh.triangles[t];
      r.mesh.triangles.push_back({local[tri[0]], local[tri[1]], local[tri[2]]});
    }
    r.mesh.face_patch.assign(r.face_in_full.size(), r.region);
    for (std::size_t v : r.vertex_in_full) local[v] = none;
  }
  return regions;
}

std::string region_file_name(int region, Mesh_format format) {
  return "region_" + std::to_string(region) + "." + extension_of(format);
}

namespace {

namespace fs = std::filesystem;

// Whether `name` is a file write_region_meshes may write: region_<k>.<ext> or regions.json.
bool is_region_file_name(const std::string& name, Mesh_format format) {
  if (name == "regions.json") return true;
  const std::string prefix = "region_", suffix = std::string(".") + extension_of(format);
  if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return false;
  std::string k = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  if (!k.empty() && k.front() == '-') k.erase(0, 1);
  return !k.empty() && std::all_of(k.begin(), k.end(), [](unsigned char c) { return c >= '0' && c <= '9'; });
}

}  // namespace

void check_region_directory(const std::string& dir, Mesh_format format,
                            const std::vector<std::string>& protected_paths) {
  const Input_location where{dir, 0, Input_location::no_offset};
  if (dir.empty()) throw Invalid_input("the directory for the region meshes is empty");
  if (format == Mesh_format::ase)
    throw Invalid_input(where, "ASE is an input format only: region meshes are written as the output is");
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (fs::exists(st)) {
    if (!fs::is_directory(st))
      throw Invalid_input(where, "exists and is not a directory; the region meshes need a directory (remove it "
                                 "or choose another name)");
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
      throw Invalid_input(where, std::string("cannot write in the directory: ") + std::strerror(errno));
  } else {
    // Created when writing, but not its parents: a mistyped parent is an error, not a new tree.
    fs::path parent = fs::path(dir).lexically_normal();
    if (!parent.has_filename()) parent = parent.parent_path();  // "out/" -> "out"
    parent = parent.has_parent_path() ? parent.parent_path() : fs::path(".");
    const fs::file_status pst = fs::status(parent, ec);
    if (!fs::exists(pst))
      throw Invalid_input(where, "the directory does not exist and neither does its parent '" + parent.string() +
                                     "' (only the last level is created)");
    if (!fs::is_directory(pst)) throw Invalid_input(where, "'" + parent.string() + "' is not a directory");
    if (::access(parent.c_str(), W_OK | X_OK) != 0)
      throw Invalid_input(where, "cannot create the directory in '" + parent.string() + "': " + std::strerror(errno));
  }
  // Never over an input or another output: refuse a protected file that a region file would replace.
  const fs::path d = fs::weakly_canonical(fs::path(dir), ec);
  for (const std::string& p : protected_paths) {
    std::error_code ec2;
    const fs::path pp = fs::weakly_canonical(fs::path(p), ec2);
    if (ec || ec2 || pp.parent_path() != d) continue;
    if (is_region_file_name(pp.filename().string(), format))
      throw Invalid_input(where, "'" + p + "' is in the directory and has the name of a region file or of "
                                 "regions.json; refusing to overwrite it");
  }
}

std::vector<Region_mesh> write_region_meshes(const std::string& dir, const Mesh_data& mesh, Mesh_format format,
                                             const Write_options& options) {
  check_region_directory(dir, format, options.protected_paths);
  std::vector<Region_mesh> regions = split_by_region(mesh);
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    fs::create_directory(dir, ec);
    if (ec)
      throw Invalid_input(Input_location{dir, 0, Input_location::no_offset},
                          "cannot create the directory: " + ec.message());
  }
  for (const Region_mesh& r : regions)
    write_mesh_data((fs::path(dir) / region_file_name(r.region, format)).string(), r.mesh, options);
  return regions;
}

}  // namespace meshfit
