// Strict PLY parser (ASCII, binary little- and big-endian). The header is validated completely
// before the body is read; every element instance is bounds-checked against the data left, so a
// count larger than the data gives an error at the place the data runs out.
#include <meshfit/internal/format_number.h>

#include "polygon_soup.h"
#include "text_parser.h"

#include <cmath>
#include <algorithm>
#include <cstring>
#include <set>

namespace meshfit {
namespace internal {

namespace {

enum class Ply_type { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

bool ply_type_from_name(std::string_view s, Ply_type& t) {
  struct Entry { const char* name; Ply_type type; };
  static const Entry table[] = {
      {"char", Ply_type::int8},     {"int8", Ply_type::int8},       {"uchar", Ply_type::uint8},
      {"uint8", Ply_type::uint8},   {"short", Ply_type::int16},     {"int16", Ply_type::int16},
      {"ushort", Ply_type::uint16}, {"uint16", Ply_type::uint16},   {"int", Ply_type::int32},
      {"int32", Ply_type::int32},   {"uint", Ply_type::uint32},     {"uint32", Ply_type::uint32},
      {"float", Ply_type::float32}, {"float32", Ply_type::float32}, {"double", Ply_type::float64},
      {"float64", Ply_type::float64}};
  for (const Entry& e : table)
    if (s == e.name) { t = e.type; return true; }
  return false;
}

std::size_t size_of(Ply_type t) {
  switch (t) {
    case Ply_type::int8: case Ply_type::uint8: return 1;
    case Ply_type::int16: case Ply_type::uint16: return 2;
    case Ply_type::int32: case Ply_type::uint32: case Ply_type::float32: return 4;
    case Ply_type::float64: return 8;
  }
  return 0;
}

bool is_integral(Ply_type t) { return t != Ply_type::float32 && t != Ply_type::float64; }

struct Ply_property {
  std::string name;
  bool is_list = false;
  Ply_type count_type = Ply_type::uint8;
  Ply_type type = Ply_type::float32;
};

// What a property means to meshfit.
enum class Role { none, x, y, z, face_indices, patch_id, edge_v1, edge_v2, curve_flag,
                  u, v, nx, ny, nz, red, green, blue, alpha,
                  face_red, face_green, face_blue };


struct Ply_element {
  std::string name;
  std::uint64_t count = 0;
  std::size_t line = 0;
  std::vector<Ply_property> properties;
  std::vector<Role> roles;
};

// The vertex attributes meshfit keeps (Mesh_data::vertex_uvs, …): a complete set only (both
// texture coordinates of one naming, the three normal components, red green blue), else they
// stay Role::none and are reported as dropped.
void assign_attribute_roles(Ply_element& e) {
  auto find = [&](const char* name) -> std::size_t {
    for (std::size_t k = 0; k < e.properties.size(); ++k)
      if (!e.properties[k].is_list && e.roles[k] == Role::none && e.properties[k].name == name) return k;
    return e.properties.size();
  };
  auto assign = [&](std::initializer_list<std::pair<const char*, Role>> set) {
    std::vector<std::size_t> at;
    for (const auto& [name, role] : set) at.push_back(find(name));
    for (std::size_t k : at)
      if (k == e.properties.size()) return false;
    std::size_t i = 0;
    for (const auto& [name, role] : set) e.roles[at[i++]] = role;
    return true;
  };
  (void)(assign({{"u", Role::u}, {"v", Role::v}}) || assign({{"s", Role::u}, {"t", Role::v}}) ||
         assign({{"texture_u", Role::u}, {"texture_v", Role::v}}) ||
         assign({{"texture_s", Role::u}, {"texture_t", Role::v}}));
  (void)(assign({{"nx", Role::nx}, {"ny", Role::ny}, {"nz", Role::nz}}) ||
         assign({{"normal_x", Role::nx}, {"normal_y", Role::ny}, {"normal_z", Role::nz}}));
  if (assign({{"red", Role::red}, {"green", Role::green}, {"blue", Role::blue}}) ||
      assign({{"diffuse_red", Role::red}, {"diffuse_green", Role::green}, {"diffuse_blue", Role::blue}}))
    (void)(assign({{"alpha", Role::alpha}}) || assign({{"diffuse_alpha", Role::alpha}}));
}

enum class Encoding { ascii, binary_le, binary_be };

struct Ply_header {
  Encoding encoding = Encoding::ascii;
  std::vector<Ply_element> elements;
  std::size_t body_offset = 0;
  std::size_t end_line = 0;
};

using Tokens = std::vector<std::string_view>;

// A `format` line: the encoding and the version.
void header_format(const Tokens& t, const Line_reader& in, Ply_header& h, bool& has_format) {
  if (has_format) in.fail("second 'format' line");
  if (t.size() != 3) in.fail("expected 'format <encoding> 1.0'");
  if (t[1] == "ascii") h.encoding = Encoding::ascii;
  else if (t[1] == "binary_little_endian") h.encoding = Encoding::binary_le;
  else if (t[1] == "binary_big_endian") h.encoding = Encoding::binary_be;
  else in.fail("unknown PLY encoding " + quote(t[1]));
  if (t[2] != "1.0") in.fail("unsupported PLY version " + quote(t[2]) + " (expected 1.0)");
  has_format = true;
}

// An `element` line; `names`: the elements declared so far.
void header_element(const Tokens& t, const Line_reader& in, bool has_format, std::set<std::string>& names,
                    Ply_header& h) {
  if (!has_format) in.fail("'element' before the 'format' line");
  if (t.size() != 3) in.fail("expected 'element <name> <count>'");
  Ply_element e;
  e.name = std::string(t[1]);
  if (!names.insert(e.name).second) in.fail("element " + quote(t[1]) + " is declared twice");
  e.count = in.to_unsigned(t[2], "element count");
  e.line = in.line_number();
  h.elements.push_back(std::move(e));
}

// A `property` line's type(s) and name.
Ply_property header_property(const Tokens& t, const Line_reader& in) {
  Ply_property p;
  if (t.size() == 5 && t[1] == "list") {
    p.is_list = true;
    if (!ply_type_from_name(t[2], p.count_type)) in.fail("unknown PLY type " + quote(t[2]));
    if (!is_integral(p.count_type)) in.fail("a list count must have an integer type");
    if (!ply_type_from_name(t[3], p.type)) in.fail("unknown PLY type " + quote(t[3]));
    p.name = std::string(t[4]);
  } else if (t.size() == 3) {
    if (!ply_type_from_name(t[1], p.type)) in.fail("unknown PLY type " + quote(t[1]));
    p.name = std::string(t[2]);
  } else {
    in.fail("expected 'property <type> <name>' or 'property list <type> <type> <name>'");
  }
  return p;
}

// What meshfit reads from property `p` of element `e` (the position, face corners, patch ids,
// curve edges), checking its type; other roles are assigned after the header
// (assign_attribute_roles).
Role property_role(const Ply_element& e, const Ply_property& p, const Line_reader& in) {
  Role role = Role::none;
  if (e.name == "vertex" && !p.is_list) {
    if (p.name == "x") role = Role::x;
    if (p.name == "y") role = Role::y;
    if (p.name == "z") role = Role::z;
  } else if (e.name == "face") {
    if (p.name == "vertex_indices" || p.name == "vertex_index") {
      if (!p.is_list) in.fail("face property " + quote(p.name) + " must be a list");
      if (!is_integral(p.type)) in.fail("vertex indices must have an integer type");
      for (Role r : e.roles)
        if (r == Role::face_indices) in.fail("a second list of face vertex indices");
      role = Role::face_indices;
    } else if (p.name == "patch_id" && !p.is_list) {
      if (!is_integral(p.type)) in.fail("patch_id must have an integer type");
      role = Role::patch_id;
    }
  } else if (e.name == "edge" && !p.is_list) {
    if (p.name == "vertex1") role = Role::edge_v1;
    if (p.name == "vertex2") role = Role::edge_v2;
    if (role != Role::none && !is_integral(p.type)) in.fail("edge vertices must have an integer type");
    if (p.name == "curve") {
      if (!is_integral(p.type)) in.fail("the edge property curve (the curve flag) must have an integer type");
      role = Role::curve_flag;
    }
  }
  return role;
}

// A `property` line: a property of the last element declared.
void header_property_line(const Tokens& t, const Line_reader& in, Ply_header& h) {
  if (h.elements.empty()) in.fail("'property' before any 'element'");
  Ply_property p = header_property(t, in);
  Ply_element& e = h.elements.back();
  for (const auto& q : e.properties)
    if (q.name == p.name) in.fail("property " + quote(p.name) + " is declared twice");
  const Role role = property_role(e, p, in);
  e.properties.push_back(std::move(p));
  e.roles.push_back(role);
}

// Face colours beside patch_id: meshfit writes region_colour(patch_id) there, and writes them
// again from the patch ids; checked against them when read (other colours are reported dropped).
void assign_face_colour_roles(Ply_element& e) {
  if (e.name != "face" || std::find(e.roles.begin(), e.roles.end(), Role::patch_id) == e.roles.end()) return;
  std::array<std::size_t, 3> at{};
  std::size_t found = 0;
  const char* channels[3] = {"red", "green", "blue"};
  for (std::size_t c = 0; c < 3; ++c)
    for (std::size_t k = 0; k < e.properties.size(); ++k)
      if (!e.properties[k].is_list && e.roles[k] == Role::none && e.properties[k].name == channels[c] &&
          is_integral(e.properties[k].type)) {
        at[c] = k;
        ++found;
        break;
      }
  if (found == 3)
    for (std::size_t c = 0; c < 3; ++c) e.roles[at[c]] = c == 0 ? Role::face_red : c == 1 ? Role::face_green : Role::face_blue;
}

// The properties meshfit needs of the elements it reads.
void check_required_properties(const Ply_element& e, const Line_reader& in) {
  auto has = [&](Role r) {
    for (Role q : e.roles) if (q == r) return true;
    return false;
  };
  const Input_location at = Input_location::at_line(in.file_name(), e.line);
  // An instance with no property occupies no byte: an absurd count would loop for ever.
  if (e.properties.empty() && e.count > 0)
    throw Invalid_input(at, "element " + quote(e.name) + " has no properties");
  if (e.name == "vertex" && !(has(Role::x) && has(Role::y) && has(Role::z)))
    throw Invalid_input(at, "the vertex element needs properties x, y and z");
  if (e.name == "face" && !has(Role::face_indices))
    throw Invalid_input(at, "the face element needs a list property vertex_indices");
  // (An edge element without the curve flag lists no curve edge and is skipped, whatever it holds.)
  if (e.name == "edge" && has(Role::curve_flag) && !(has(Role::edge_v1) && has(Role::edge_v2)))
    throw Invalid_input(at, "the edge element has a curve flag and needs properties vertex1 and vertex2");
}

// Reads one line of the header; false when it is `end_header`.
bool header_line(Line_reader& in, Ply_header& h, bool& has_format, std::set<std::string>& names) {
  if (!in.next_raw()) in.fail("the header has no 'end_header' line");
  const auto& t = in.tokens();
  if (t.empty()) in.fail("blank line in the PLY header");
  const std::string_view key = t[0];
  if (key == "end_header") {
    if (t.size() != 1) in.fail("unexpected values after 'end_header'");
    return false;
  }
  if (key == "comment" || key == "obj_info") return true;
  if (key == "format") header_format(t, in, h, has_format);
  else if (key == "element") header_element(t, in, has_format, names, h);
  else if (key == "property") header_property_line(t, in, h);
  else in.fail("unknown PLY header line " + quote(key));
  return true;
}

Ply_header parse_header(Line_reader& in) {
  Ply_header h;
  if (!in.next_raw() || in.tokens().size() != 1 || in.tokens()[0] != "ply")
    in.fail("expected 'ply' on the first line");
  bool has_format = false;
  std::set<std::string> names;
  while (header_line(in, h, has_format, names)) continue;
  if (!has_format) in.fail("the header has no 'format' line");
  h.end_line = in.line_number();
  h.body_offset = in.offset();
  for (Ply_element& e : h.elements) {
    if (e.name == "vertex") assign_attribute_roles(e);
    assign_face_colour_roles(e);
  }
  for (const Ply_element& e : h.elements) check_required_properties(e, in);
  return h;
}

// Reads values from the body, ASCII or binary, with locations for errors.
class Body_reader {
 public:
  Body_reader(std::string_view text, const Ply_header& h, const std::string& file, Line_reader& lines)
      : m_text(text), m_encoding(h.encoding), m_pos(h.body_offset), m_file(file), m_lines(lines) {}

  // Starts an element instance; returns its location (line or byte offset).
  std::size_t begin_instance(const Ply_element& e, std::uint64_t i) {
    if (m_encoding != Encoding::ascii) {
      m_element = &e.name;
      m_index = i;
      return m_pos;
    }
    if (!m_lines.next())
      throw Invalid_input(Input_location::at_line(m_file, e.line),
                          "the header declares " + std::to_string(e.count) + " " + e.name +
                              " elements but the file ends after " + std::to_string(i));
    m_token = 0;
    return m_lines.line_number();
  }
  void end_instance(const Ply_element& e) {
    if (m_encoding == Encoding::ascii && m_token != m_lines.tokens().size())
      m_lines.fail("element '" + e.name + "' has " +
                   std::to_string(m_lines.tokens().size() - m_token) + " values too many");
  }
  // The number of items a list of `count_type` may hold, checked against the data left.
  std::uint64_t list_count(Ply_type count_type, Ply_type item_type, const std::string& prop) {
    const double c = value(count_type, prop);
    if (c < 0) fail_here("list " + quote(prop) + " has a negative length");
    const std::uint64_t n = static_cast<std::uint64_t>(c);
    const std::uint64_t left = m_encoding == Encoding::ascii
                                   ? m_lines.tokens().size() - m_token
                                   : (m_text.size() - m_pos) / size_of(item_type);
    if (n > left)
      fail_here("list " + quote(prop) + " declares " + std::to_string(n) + " items but only " +
                std::to_string(left) + " values are left");
    return n;
  }
  double value(Ply_type t, const std::string& prop) {
    if (m_encoding == Encoding::ascii) {
      if (m_token >= m_lines.tokens().size()) m_lines.fail("missing value for property " + quote(prop));
      const std::string_view tok = m_lines.tokens()[m_token++];
      if (is_integral(t)) {
        const std::int64_t v = m_lines.to_signed(tok, prop.c_str());
        if (!fits(t, static_cast<double>(v)))
          m_lines.fail("value " + quote(tok) + " does not fit the type of property " + quote(prop));
        return static_cast<double>(v);
      }
      return m_lines.to_double(tok, prop.c_str());
    }
    const std::size_t n = size_of(t);
    if (m_text.size() - m_pos < n)
      throw Invalid_input(Input_location::at_byte(m_file, m_pos),
                          "file ends inside " + instance() + " (property " + quote(prop) + ")");
    unsigned char b[8];
    std::memcpy(b, m_text.data() + m_pos, n);
    if (m_encoding == Encoding::binary_be)
      for (std::size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    const std::size_t at = m_pos;
    m_pos += n;
    double v = 0;
    switch (t) {
      case Ply_type::int8: { std::int8_t x; std::memcpy(&x, b, 1); v = x; break; }
      case Ply_type::uint8: { std::uint8_t x; std::memcpy(&x, b, 1); v = x; break; }
      case Ply_type::int16: { std::int16_t x; std::memcpy(&x, b, 2); v = x; break; }
      case Ply_type::uint16: { std::uint16_t x; std::memcpy(&x, b, 2); v = x; break; }
      case Ply_type::int32: { std::int32_t x; std::memcpy(&x, b, 4); v = x; break; }
      case Ply_type::uint32: { std::uint32_t x; std::memcpy(&x, b, 4); v = x; break; }
      case Ply_type::float32: { float x; std::memcpy(&x, b, 4); v = x; break; }
      case Ply_type::float64: { std::memcpy(&v, b, 8); break; }
    }
    if (!std::isfinite(v))
      throw Invalid_input(Input_location::at_byte(m_file, at),
                          "property " + quote(prop) + " of " + instance() + " is not finite");
    return v;
  }
  void finish(const Ply_header& h) {
    if (m_encoding == Encoding::ascii) {
      if (m_lines.next()) m_lines.fail("unexpected data after the last declared element");
      return;
    }
    if (m_pos != m_text.size())
      throw Invalid_input(Input_location::at_byte(m_file, m_pos),
                          std::to_string(m_text.size() - m_pos) +
                              " unexpected bytes after the last declared element");
    (void)h;
  }
  [[noreturn]] void fail_here(const std::string& problem) {
    if (m_encoding == Encoding::ascii) m_lines.fail(problem);
    throw Invalid_input(Input_location::at_byte(m_file, m_pos), instance() + ": " + problem);
  }

 private:
  static bool fits(Ply_type t, double v) {
    switch (t) {
      case Ply_type::int8: return v >= -128 && v <= 127;
      case Ply_type::uint8: return v >= 0 && v <= 255;
      case Ply_type::int16: return v >= -32768 && v <= 32767;
      case Ply_type::uint16: return v >= 0 && v <= 65535;
      case Ply_type::int32: return v >= -2147483648.0 && v <= 2147483647.0;
      case Ply_type::uint32: return v >= 0 && v <= 4294967295.0;
      default: return true;
    }
  }

  std::string_view m_text;
  Encoding m_encoding;
  std::size_t m_pos;
  std::string m_file;
  Line_reader& m_lines;
  std::size_t m_token = 0;
  const std::string* m_element = nullptr;
  std::uint64_t m_index = 0;

  std::string instance() const {
    return "element '" + (m_element ? *m_element : std::string()) + "' " + std::to_string(m_index);
  }
};

// Vertex and face properties meshfit reads past without keeping, grouped as people name them:
// "vertex normals (nx ny nz)", "texture coordinates (s t)", "other face properties (flags)".
void note_dropped_attributes(const Ply_header& h, Polygon_soup& soup) {
  auto one_of = [](const std::string& n, std::initializer_list<const char*> names) {
    for (const char* c : names)
      if (n == c) return true;
    return false;
  };
  for (const Ply_element& e : h.elements) {
    if (e.name != "vertex" && e.name != "face") continue;
    std::string normals, colours, uvs, others;
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      if (e.roles[k] != Role::none) continue;
      const std::string& n = e.properties[k].name;
      std::string* group = &others;
      if (one_of(n, {"nx", "ny", "nz", "normal_x", "normal_y", "normal_z"})) group = &normals;
      else if (one_of(n, {"red", "green", "blue", "alpha", "r", "g", "b", "a", "diffuse_red", "diffuse_green",
                          "diffuse_blue", "diffuse_alpha"}))
        group = &colours;
      else if (one_of(n, {"u", "v", "s", "t", "texture_u", "texture_v", "texture_s", "texture_t", "texcoord"}))
        group = &uvs;
      *group += (group->empty() ? "" : " ") + n;
    }
    const std::string which = e.name == "vertex" ? "vertex " : "face ";
    if (!normals.empty()) soup.drop(which + "normals (" + normals + ")");
    if (!colours.empty()) soup.drop(which + "colours (" + colours + ")");
    if (!uvs.empty()) soup.drop((e.name == "vertex" ? "texture coordinates (" : "face texture coordinates (") + uvs + ")");
    if (!others.empty()) soup.drop("other " + which + "properties (" + others + ")");
  }
}

// What an element's instances carry that meshfit keeps.
struct Element_layout {
  bool keeps_uv, keeps_normal, keeps_colour, has_alpha;
  // Integer colour channels are bytes (0-255, as CGAL and most tools write them); floats are in [0, 1].
  double colour_divisor = 1;
  bool has_patch, has_face_colour;
  // Only flagged edges are curve edges: CGAL's write_PLY lists every edge of the mesh, and
  // taking such a list as curves would fix every vertex.
  bool has_curve_flag;
};

Element_layout element_layout(const Ply_element& e) {
  auto has = [&](Role r) { return std::find(e.roles.begin(), e.roles.end(), r) != e.roles.end(); };
  Element_layout l;
  l.keeps_uv = e.name == "vertex" && has(Role::u);
  l.keeps_normal = e.name == "vertex" && has(Role::nx);
  l.keeps_colour = e.name == "vertex" && has(Role::red);
  l.has_alpha = has(Role::alpha);
  for (std::size_t k = 0; k < e.properties.size(); ++k)
    if (e.roles[k] == Role::red && is_integral(e.properties[k].type)) l.colour_divisor = 255;
  l.has_patch = e.name == "face" && has(Role::patch_id);
  l.has_face_colour = has(Role::face_red);
  l.has_curve_flag = e.name == "edge" && has(Role::curve_flag);
  return l;
}

// The values one instance of an element gives meshfit.
struct Instance {
  double xyz[3] = {0, 0, 0}, uv[2] = {0, 0}, normal[3] = {0, 0, 0}, rgba[4] = {0, 0, 0, 1};
  std::array<std::size_t, 2> edge{};
  int patch = -1;
  bool flagged = false;
  double face_rgb[3] = {0, 0, 0};
};

std::size_t to_index(Body_reader& body, double v, const std::string& what) {
  if (v < 0) body.fail_here(what + " " + std::to_string(static_cast<long long>(v)) + " is negative");
  return static_cast<std::size_t>(v);
}

// Puts value `v` of a property with role `role` where it belongs in `x`.
void take_value(Role role, double v, double colour_divisor, Body_reader& body, Instance& x) {
  switch (role) {
    case Role::x: x.xyz[0] = v; break;
    case Role::y: x.xyz[1] = v; break;
    case Role::z: x.xyz[2] = v; break;
    case Role::patch_id:
      // -1 is a face in no region (what the writers write as such); other negative ids
      // would not read back as written.
      if (v < -1 || v > INT32_MAX)
        body.fail_here("patch_id " + internal::format_number(v) +
                       ": a region index is 0 or more, or -1 for a face in no region");
      x.patch = static_cast<int>(v);
      break;
    case Role::edge_v1: x.edge[0] = to_index(body, v, "edge vertex"); break;
    case Role::edge_v2: x.edge[1] = to_index(body, v, "edge vertex"); break;
    case Role::curve_flag: x.flagged = v != 0; break;
    case Role::u: x.uv[0] = v; break;
    case Role::v: x.uv[1] = v; break;
    case Role::nx: x.normal[0] = v; break;
    case Role::ny: x.normal[1] = v; break;
    case Role::nz: x.normal[2] = v; break;
    case Role::red: x.rgba[0] = v / colour_divisor; break;
    case Role::green: x.rgba[1] = v / colour_divisor; break;
    case Role::blue: x.rgba[2] = v / colour_divisor; break;
    case Role::alpha: x.rgba[3] = v / colour_divisor; break;
    case Role::face_red: x.face_rgb[0] = v; break;
    case Role::face_green: x.face_rgb[1] = v; break;
    case Role::face_blue: x.face_rgb[2] = v; break;
    default: break;
  }
}

// Reads the properties of one instance of `e`; a face's corners go straight to the soup.
Instance read_instance(const Ply_element& e, const Element_layout& layout, Body_reader& body, Polygon_soup& soup) {
  Instance x;
  for (std::size_t k = 0; k < e.properties.size(); ++k) {
    const Ply_property& p = e.properties[k];
    if (p.is_list) {
      const std::uint64_t n = body.list_count(p.count_type, p.type, p.name);
      for (std::uint64_t j = 0; j < n; ++j) {
        const double v = body.value(p.type, p.name);
        if (e.roles[k] == Role::face_indices) soup.corners.push_back(to_index(body, v, "vertex index"));
      }
      continue;
    }
    take_value(e.roles[k], body.value(p.type, p.name), layout.colour_divisor, body, x);
  }
  return x;
}

// Adds instance `x` of `e`, read at `where`, to the soup. `other_face_colours`: set when a face's
// colour is not region_colour(patch_id).
void add_instance(const Ply_element& e, const Element_layout& layout, const Instance& x, std::size_t where,
                  Polygon_soup& soup, bool& other_face_colours) {
  if (e.name == "vertex") {
    soup.points.emplace_back(x.xyz[0], x.xyz[1], x.xyz[2]);
    if (layout.keeps_uv) soup.vertex_uvs.push_back({x.uv[0], x.uv[1]});
    if (layout.keeps_normal) soup.vertex_normals.push_back({x.normal[0], x.normal[1], x.normal[2]});
    if (layout.keeps_colour)
      soup.vertex_colors.push_back({x.rgba[0], x.rgba[1], x.rgba[2], layout.has_alpha ? x.rgba[3] : 1.0});
  }
  if (e.name == "face") {
    soup.end_polygon(where);
    if (layout.has_patch) soup.polygon_patch.push_back(x.patch);
    if (layout.has_face_colour && !other_face_colours) {
      const auto c = region_colour(x.patch);
      other_face_colours = x.face_rgb[0] != c[0] || x.face_rgb[1] != c[1] || x.face_rgb[2] != c[2];
    }
  }
  if (e.name == "edge") {
    if (layout.has_curve_flag && x.flagged) {
      soup.edges.push_back(x.edge);
      soup.edge_where.push_back(where);
    } else {
      ++soup.ignored_edges;
    }
  }
}

}  // namespace

Polygon_soup parse_ply(std::string_view text, const std::string& name) {
  Line_reader lines(text, name, '\0');
  const Ply_header h = parse_header(lines);
  Polygon_soup soup;
  soup.file = name;
  soup.binary = h.encoding != Encoding::ascii;
  note_dropped_attributes(h, soup);
  Body_reader body(text, h, name, lines);
  bool other_face_colours = false;  // face colours that are not region_colour(patch_id)
  for (const Ply_element& e : h.elements) {
    const Element_layout layout = element_layout(e);
    for (std::uint64_t i = 0; i < e.count; ++i) {
      const std::size_t where = body.begin_instance(e, i);
      const Instance x = read_instance(e, layout, body, soup);
      body.end_instance(e);
      add_instance(e, layout, x, where, soup, other_face_colours);
    }
  }
  body.finish(h);
  if (other_face_colours) soup.drop("face colours (red green blue) other than meshfit's region colours");
  return soup;
}

}  // namespace internal
}  // namespace meshfit
