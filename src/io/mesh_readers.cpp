// Strict parsers for OFF/COFF, OBJ, PLY (ASCII and binary) and STL (ASCII and binary).
// They never size an allocation from a count in the file: elements are appended as they are read,
// and a count larger than the data is reported when the data runs out.
#include "polygon_soup.h"
#include "text_parser.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

namespace meshfit {
namespace internal {

namespace {

// ---- OFF ----------------------------------------------------------------------------------------

Polygon_soup parse_off_impl(std::string_view text, const std::string& name) {
  Polygon_soup soup;
  soup.file = name;
  Line_reader in(text, name);
  if (!in.next())
    throw Invalid_input(Input_location{name, 0, Input_location::no_offset},
                        "empty file: expected an OFF header");

  std::string_view head = in.tokens()[0];
  if (head.size() < 3 || head.substr(head.size() - 3) != "OFF")
    in.fail("expected an OFF header (OFF, COFF, NOFF, STOFF, …), found " + quote(head));
  std::string_view prefix = head.substr(0, head.size() - 3);
  const bool plain = prefix.empty();
  if (prefix.substr(0, 2) == "ST") {
    prefix.remove_prefix(2);
    soup.drop("texture coordinates (STOFF)");
  }
  if (!prefix.empty() && prefix.front() == 'C') {
    prefix.remove_prefix(1);
    soup.drop("vertex colours (COFF)");
  }
  if (!prefix.empty() && prefix.front() == 'N') {
    prefix.remove_prefix(1);
    soup.drop("vertex normals (NOFF)");
  }
  if (!prefix.empty() && (prefix.front() == '4' || prefix.front() == 'n'))
    in.fail("OFF files of dimension other than 3 (" + quote(head) + ") are not supported");
  if (!prefix.empty()) in.fail("unknown OFF header " + quote(head));

  std::vector<std::string_view> counts(in.tokens().begin() + 1, in.tokens().end());
  if (!counts.empty() && counts[0] == "BINARY") in.fail("binary OFF is not supported");
  if (counts.empty()) {
    if (!in.next()) in.fail("file ends after the header: expected the vertex and face counts");
    counts = in.tokens();
  }
  if (counts.size() < 2 || counts.size() > 3)
    in.fail("expected 'vertices faces [edges]' counts, found " + std::to_string(counts.size()) +
            " values");
  const std::uint64_t nv = in.to_unsigned(counts[0], "vertex count");
  const std::uint64_t nf = in.to_unsigned(counts[1], "face count");
  if (counts.size() == 3) in.to_unsigned(counts[2], "edge count");
  const std::size_t count_line = in.line_number();

  for (std::uint64_t i = 0; i < nv; ++i) {
    if (!in.next())
      throw Invalid_input(Input_location::at_line(name, count_line),
                          "the header declares " + std::to_string(nv) +
                              " vertices but the file ends after " + std::to_string(i));
    const auto& t = in.tokens();
    if (t.size() < 3)
      in.fail("vertex " + std::to_string(i) + " has " + std::to_string(t.size()) +
              " values; expected x y z");
    soup.points.emplace_back(in.to_double(t[0], "x coordinate"),
                             in.to_double(t[1], "y coordinate"),
                             in.to_double(t[2], "z coordinate"));
    for (std::size_t k = 3; k < t.size(); ++k) in.to_double(t[k], "vertex attribute");
    if (plain && t.size() > 3) soup.drop("vertex values after x y z (colours)");
  }
  for (std::uint64_t f = 0; f < nf; ++f) {
    if (!in.next())
      throw Invalid_input(Input_location::at_line(name, count_line),
                          "the header declares " + std::to_string(nf) +
                              " faces but the file ends after " + std::to_string(f));
    const auto& t = in.tokens();
    const std::uint64_t n = in.to_unsigned(t[0], "face size");
    if (n > t.size() - 1)
      in.fail("face " + std::to_string(f) + " declares " + std::to_string(n) +
              " vertices but the line has " + std::to_string(t.size() - 1) + " indices");
    if (t.size() - 1 - n > 4)
      in.fail("face " + std::to_string(f) + " declares " + std::to_string(n) +
              " vertices but the line has " + std::to_string(t.size() - 1) + " values");
    for (std::size_t k = 1; k <= n; ++k) soup.corners.push_back(in.to_unsigned(t[k], "vertex index"));
    for (std::size_t k = n + 1; k < t.size(); ++k) in.to_double(t[k], "face colour");
    if (t.size() > n + 1) soup.drop("face colours (values after the indices)");
    soup.end_polygon(in.line_number());
  }
  if (in.next())
    in.fail("unexpected data after the " + std::to_string(nf) + " declared faces");
  return soup;
}

// ---- OBJ ----------------------------------------------------------------------------------------

bool obj_statement_ignored(std::string_view k) {
  static const char* const ignored[] = {
      "vt", "vn", "vp", "o", "s", "mg", "usemtl", "mtllib", "usemap", "maplib", "p",
      "cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm", "trim", "hole",
      "scrv", "sp", "end", "con", "lod", "bevel", "c_interp", "d_interp", "shadow_obj",
      "trace_obj", "ctech", "stech", "call", "csh"};
  for (const char* s : ignored)
    if (k == s) return true;
  return false;
}

using Tokens = std::vector<std::string_view>;

// Reads an OBJ file statement by statement into a soup. Positive indices may refer to vertices
// defined later; they are range-checked by the mesh check once all vertices are known, with the
// line of the face that used them. Texture coordinates and normals are indexed per corner;
// meshfit keeps them per vertex when every corner of each vertex that uses one names the same
// (`vt`/`vn` index, or equal values).
class Obj_reader {
 public:
  Obj_reader(std::string_view text, const std::string& name) : m_name(name), m_in(text, name) {
    m_soup.file = name;
    m_soup.one_based = true;
  }

  Polygon_soup read() {
    while (m_in.next()) statement(m_in.tokens());
    if (!m_has_regions) m_soup.polygon_patch.clear();
    take_colours();
    per_vertex(m_texcoords, [](const Corner_refs& c) { return c.vt; }, m_soup.vertex_uvs, "texture coordinate");
    per_vertex(m_normals, [](const Corner_refs& c) { return c.vn; }, m_soup.vertex_normals, "normal");
    return std::move(m_soup);
  }

 private:
  struct Corner_refs {
    std::size_t vertex;
    std::int64_t vt, vn;  // 0: none; negative: relative, resolved when read
    std::size_t line;
  };

  void statement(const Tokens& t) {
    const std::string_view key = t[0];
    if (key == "v") vertex(t);
    else if (key == "vt") texture_coordinate(t);
    else if (key == "vn") normal(t);
    else if (key == "f") face(t);
    else if (key == "l") line(t);
    else if (key == "g") group(t);
    else if (!obj_statement_ignored(key)) m_in.fail("unknown OBJ statement " + quote(key));
  }

  void vertex(const Tokens& t) {
    if (t.size() < 4) m_in.fail("vertex has " + std::to_string(t.size() - 1) + " values; expected x y z");
    if (t.size() > 7) m_in.fail("vertex has " + std::to_string(t.size() - 1) + " values; expected at most 6");
    m_soup.points.emplace_back(m_in.to_double(t[1], "x coordinate"),
                               m_in.to_double(t[2], "y coordinate"),
                               m_in.to_double(t[3], "z coordinate"));
    double extra[3] = {0, 0, 0};
    for (std::size_t k = 4; k < t.size(); ++k) extra[k - 4] = m_in.to_double(t[k], "vertex attribute");
    if (t.size() == 5) m_soup.drop("vertex weights (v x y z w)");
    if (t.size() == 7) {
      m_colours.resize(m_soup.points.size());
      m_colours.back() = {extra[0], extra[1], extra[2], 1.0};
      ++m_coloured;
    }
  }

  void texture_coordinate(const Tokens& t) {
    if (t.size() < 2 || t.size() > 4) m_in.fail("expected 'vt u [v [w]]'");
    m_texcoords.push_back({m_in.to_double(t[1], "texture coordinate u"),
                           t.size() > 2 ? m_in.to_double(t[2], "texture coordinate v") : 0.0});
    if (t.size() > 3) m_in.to_double(t[3], "texture coordinate w");
  }

  void normal(const Tokens& t) {
    if (t.size() != 4) m_in.fail("expected 'vn x y z'");
    m_normals.push_back(
        {m_in.to_double(t[1], "normal x"), m_in.to_double(t[2], "normal y"), m_in.to_double(t[3], "normal z")});
  }

  void face(const Tokens& t) {
    for (std::size_t k = 1; k < t.size(); ++k) {
      m_soup.corners.push_back(resolve(t[k], "vertex index"));
      // v, v/vt, v//vn or v/vt/vn
      const std::string_view tok = t[k];
      const std::size_t s1 = tok.find('/');
      std::string_view vt, vn;
      if (s1 != std::string_view::npos) {
        const std::size_t s2 = tok.find('/', s1 + 1);
        vt = tok.substr(s1 + 1, s2 == std::string_view::npos ? std::string_view::npos : s2 - s1 - 1);
        if (s2 != std::string_view::npos) vn = tok.substr(s2 + 1);
      }
      m_corner_refs.push_back({m_soup.corners.back(),
                               attribute_index(vt, m_texcoords.size(), "texture coordinate index"),
                               attribute_index(vn, m_normals.size(), "normal index"), m_in.line_number()});
    }
    m_soup.end_polygon(m_in.line_number());
    m_soup.polygon_patch.push_back(m_region);
  }

  void line(const Tokens& t) {
    if (t.size() < 3) m_in.fail("a line element needs at least two vertices");
    std::size_t prev = resolve(t[1], "vertex index");
    for (std::size_t k = 2; k < t.size(); ++k) {
      const std::size_t cur = resolve(t[k], "vertex index");
      m_soup.edges.push_back({prev, cur});
      m_soup.edge_where.push_back(m_in.line_number());
      prev = cur;
    }
  }

  void group(const Tokens& t) {
    m_region = -1;
    if (t.size() == 2 && t[1].substr(0, 7) == "region_") {
      std::uint64_t k = 0;
      if (parse_unsigned(t[1].substr(7), k) == Number_status::ok && k <= INT32_MAX) {
        m_region = static_cast<int>(k);
        m_has_regions = true;
      }
    }
  }

  // A `vt` or `vn` index of a corner, relative ones resolved against the `count` read so far.
  std::int64_t attribute_index(std::string_view index, std::size_t count, const char* what) const {
    if (index.empty()) return 0;
    const std::int64_t i = m_in.to_signed(index, what);
    if (i == 0) m_in.fail(std::string(what) + " 0: OBJ indices start at 1");
    if (i < 0) {
      const std::uint64_t back = static_cast<std::uint64_t>(-(i + 1)) + 1;
      if (back > count) m_in.fail(std::string(what) + " " + quote(index) + " refers before the first one");
      return static_cast<std::int64_t>(count - back) + 1;
    }
    return i;
  }

  // The vertex a corner or line token names, from 0.
  std::size_t resolve(std::string_view token, const char* what) const {
    const std::string_view index = token.substr(0, token.find('/'));
    const std::int64_t i = m_in.to_signed(index, what);
    if (i == 0) m_in.fail(std::string(what) + " 0: OBJ indices start at 1");
    if (i < 0) {
      const std::uint64_t back = static_cast<std::uint64_t>(-(i + 1)) + 1;
      if (back > m_soup.points.size())
        m_in.fail(std::string(what) + " " + quote(token) + " refers before the first vertex (" +
                  std::to_string(m_soup.points.size()) + " vertices so far)");
      return m_soup.points.size() - back;
    }
    return static_cast<std::size_t>(i - 1);
  }

  void take_colours() {
    if (m_coloured > 0 && m_coloured == m_soup.points.size())
      m_soup.vertex_colors = std::move(m_colours);
    else if (m_coloured > 0)
      m_soup.drop("vertex colours (v x y z r g b), not on every vertex");
  }

  // Per vertex when every corner of a vertex names the same values (a seam gives a vertex two).
  template <typename Value, typename Index_of>
  void per_vertex(const std::vector<Value>& values, Index_of index_of, std::vector<Value>& out, const char* what) {
    if (values.empty()) return;
    std::vector<Value> v(m_soup.points.size());
    std::vector<char> seen(m_soup.points.size(), 0);
    bool ok = true;
    for (const Corner_refs& c : m_corner_refs) {
      const std::int64_t i = index_of(c);
      if (i > static_cast<std::int64_t>(values.size()))
        throw Invalid_input(Input_location::at_line(m_name, c.line),
                            std::string(what) + " index " + std::to_string(i) + " refers past the last one (" +
                                std::to_string(values.size()) + ")");
      if (i == 0 || c.vertex >= v.size()) {
        ok = false;
        continue;
      }
      const Value& value = values[static_cast<std::size_t>(i - 1)];
      if (seen[c.vertex] && v[c.vertex] != value) ok = false;
      v[c.vertex] = value;
      seen[c.vertex] = 1;
    }
    if (ok) out = std::move(v);
    else m_soup.drop(std::string(what) + "s (" + (what[0] == 't' ? "vt" : "vn") + "), not one per vertex");
  }

  const std::string& m_name;
  Line_reader m_in;
  Polygon_soup m_soup;
  bool m_has_regions = false;
  int m_region = -1;
  std::vector<std::array<double, 2>> m_texcoords;
  std::vector<std::array<double, 3>> m_normals;
  std::vector<std::array<double, 4>> m_colours;  // of the vertices (`v x y z r g b`)
  std::size_t m_coloured = 0;
  std::vector<Corner_refs> m_corner_refs;
};

Polygon_soup parse_obj_impl(std::string_view text, const std::string& name) { return Obj_reader(text, name).read(); }

// ---- STL ----------------------------------------------------------------------------------------

struct Point_less {
  bool operator()(const Point_3& a, const Point_3& b) const {
    return std::make_tuple(a.x(), a.y(), a.z()) < std::make_tuple(b.x(), b.y(), b.z());
  }
};

// STL stores every triangle with its own corners: equal coordinates are one vertex, numbered in
// order of first appearance.
struct Stl_welder {
  Polygon_soup& soup;
  std::map<Point_3, std::size_t, Point_less> index;
  void add(const Point_3& p) {
    const auto it = index.emplace(p, soup.points.size());
    if (it.second) soup.points.push_back(p);
    soup.corners.push_back(it.first->second);
  }
};

template <typename T>
T load_le(const char* p) {
  // Binary formats here are little-endian, as is every platform meshfit is built on.
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

Polygon_soup parse_stl_binary(std::string_view data, const std::string& name) {
  Polygon_soup soup;
  soup.file = name;
  soup.binary = true;
  Stl_welder weld{soup, {}};
  const std::size_t n = load_le<std::uint32_t>(data.data() + 80);
  for (std::size_t f = 0; f < n; ++f) {
    const std::size_t at = 84 + 50 * f;
    for (int c = 0; c < 3; ++c) {
      double xyz[3];
      for (int k = 0; k < 3; ++k) {
        const std::size_t off = at + 12 + 12 * c + 4 * k;
        const float v = load_le<float>(data.data() + off);
        if (!std::isfinite(v))
          throw Invalid_input(Input_location::at_byte(name, off),
                              "triangle " + std::to_string(f) + " has a non-finite coordinate");
        xyz[k] = v;
      }
      weld.add(Point_3(xyz[0], xyz[1], xyz[2]));
    }
    soup.end_polygon(at);
  }
  return soup;
}

Polygon_soup parse_stl_ascii(std::string_view text, const std::string& name) {
  Polygon_soup soup;
  soup.file = name;
  Stl_welder weld{soup, {}};
  Line_reader in(text, name, '\0');
  auto expect = [&](const char* what) {
    if (!in.next()) in.fail(std::string("file ends where '") + what + "' was expected");
    if (in.tokens()[0] != what)
      in.fail(std::string("expected '") + what + "', found " + quote(in.tokens()[0]));
  };
  if (!in.next() || in.tokens()[0] != "solid") in.fail("expected 'solid' to start an ASCII STL file");
  while (true) {
    if (!in.next()) in.fail("file ends inside a solid: expected 'facet' or 'endsolid'");
    const std::string_view key = in.tokens()[0];
    if (key == "endsolid") {
      if (!in.next()) break;
      if (in.tokens()[0] != "solid")
        in.fail("expected 'solid' or the end of the file, found " + quote(in.tokens()[0]));
      continue;
    }
    if (key != "facet") in.fail("expected 'facet' or 'endsolid', found " + quote(key));
    const std::size_t facet_line = in.line_number();
    const auto& t = in.tokens();
    if (t.size() != 5 || t[1] != "normal") in.fail("expected 'facet normal nx ny nz'");
    for (int k = 2; k < 5; ++k) in.to_double(t[k], "normal component");
    expect("outer");
    if (in.tokens().size() != 2 || in.tokens()[1] != "loop") in.fail("expected 'outer loop'");
    std::size_t corners = 0;
    while (true) {
      if (!in.next()) in.fail("file ends inside a facet: expected 'vertex' or 'endloop'");
      const auto& v = in.tokens();
      if (v[0] == "endloop") break;
      if (v[0] != "vertex") in.fail("expected 'vertex x y z' or 'endloop', found " + quote(v[0]));
      if (v.size() != 4) in.fail("expected 'vertex x y z'");
      weld.add(Point_3(in.to_double(v[1], "x coordinate"), in.to_double(v[2], "y coordinate"),
                       in.to_double(v[3], "z coordinate")));
      ++corners;
    }
    if (in.tokens().size() != 1) in.fail("unexpected values after 'endloop'");
    expect("endfacet");
    (void)corners;  // fewer than three corners is reported by the mesh check, with this line
    soup.end_polygon(facet_line);
  }
  return soup;
}

Polygon_soup parse_stl_impl(std::string_view data, const std::string& name) {
  if (data.size() >= 84) {
    const std::uint64_t n = load_le<std::uint32_t>(data.data() + 80);
    if (84 + 50 * n == data.size()) return parse_stl_binary(data, name);
  }
  Line_reader probe(data, name, '\0');
  if (probe.next() && probe.tokens()[0] == "solid") return parse_stl_ascii(data, name);
  if (data.size() < 84)
    throw Invalid_input(Input_location::at_byte(name, 0),
                        "not an STL file: too short for binary STL (" + std::to_string(data.size()) +
                            " bytes) and no 'solid' keyword");
  const std::uint64_t n = load_le<std::uint32_t>(data.data() + 80);
  throw Invalid_input(Input_location::at_byte(name, 80),
                      "binary STL declares " + std::to_string(n) + " triangles, which need " +
                          std::to_string(84 + 50 * n) + " bytes, but the file has " +
                          std::to_string(data.size()) + " bytes");
}

}  // namespace

Polygon_soup parse_off(std::string_view text, const std::string& name) {
  return parse_off_impl(text, name);
}
Polygon_soup parse_obj(std::string_view text, const std::string& name) {
  return parse_obj_impl(text, name);
}
Polygon_soup parse_stl(std::string_view text, const std::string& name) {
  return parse_stl_impl(text, name);
}

}  // namespace internal
}  // namespace meshfit
