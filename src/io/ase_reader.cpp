// Strict reader of 3ds Max ASCII Scene Export (ASE) templates, the format the thesis's system read.
// Only the triangle meshes are taken: every *MESH block directly inside a *GEOMOBJECT, merged in
// file order. The structure is line-based: a line ending in '{' opens a block named by its first
// token, a line '}' closes one; every other line is '*KEY values…'.
#include "polygon_soup.h"
#include "text_parser.h"

#include <algorithm>

namespace meshfit {
namespace internal {

namespace {

enum class Ase_role { other, geomobject, mesh, vertex_list, face_list };

struct Ase_block {
  std::string key;
  std::size_t line = 0;
  Ase_role role = Ase_role::other;
};

// One *MESH being read.
struct Ase_mesh {
  std::size_t open_line = 0;
  std::size_t base = 0;  ///< vertices of the objects before this one
  bool has_vertex_count = false, has_face_count = false;
  std::uint64_t vertex_count = 0, face_count = 0;
  std::size_t vertex_count_line = 0, face_count_line = 0;
  bool has_vertex_list = false, has_face_list = false;
  std::uint64_t vertices_read = 0, faces_read = 0;
};

// The reader's state and one method per kind of line; run() reads the whole file.
class Ase_reader {
 public:
  Ase_reader(std::string_view text, const std::string& name) : name(name), in(text, name, '\0') { soup.file = name; }

  Polygon_soup run() {
    read_header();
    while (in.next()) {
      const auto& t = in.tokens();
      const std::string_view key = t[0];
      if (key == "}") {
        close_block();
        continue;
      }
      if (key.front() != '*') in.fail("unexpected " + quote(key) + ": an ASE line starts with '*' or is '}'");
      const Ase_role parent = open.empty() ? Ase_role::other : open.back().role;
      if (t.size() >= 2 && t.back() == "{")
        open_block(key, parent);
      else if (parent == Ase_role::mesh && (key == "*MESH_NUMVERTEX" || key == "*MESH_NUMFACES"))
        read_count(key);
      else if (parent == Ase_role::vertex_list)
        read_vertex(key);
      else if (parent == Ase_role::face_list)
        read_face(key);
      // Any other line (scene, materials, node transforms, mapping channels, …) is not geometry.
    }
    finish();
    return std::move(soup);
  }

 private:
  void read_header() {
    if (!in.next())
      throw Invalid_input(Input_location{name, 0, Input_location::no_offset},
                          "empty file: expected an ASE header (*3DSMAX_ASCIIEXPORT)");
    if (in.tokens()[0] != "*3DSMAX_ASCIIEXPORT")
      in.fail("expected the ASE header *3DSMAX_ASCIIEXPORT, found " + quote(in.tokens()[0]));
  }

  // '}': the block it closes must hold what it declared.
  void close_block() {
    if (in.tokens().size() != 1) in.fail("unexpected values after '}'");
    if (open.empty()) in.fail("'}' closes no block");
    const Ase_block block = open.back();
    open.pop_back();
    const std::string opened = " (opened at line " + std::to_string(block.line) + ")";
    if (block.role == Ase_role::vertex_list && mesh.vertices_read != mesh.vertex_count)
      in.fail("the *MESH_VERTEX_LIST" + opened + " has " + std::to_string(mesh.vertices_read) +
              " vertices but *MESH_NUMVERTEX (line " + std::to_string(mesh.vertex_count_line) + ") declares " +
              std::to_string(mesh.vertex_count));
    if (block.role == Ase_role::face_list && mesh.faces_read != mesh.face_count)
      in.fail("the *MESH_FACE_LIST" + opened + " has " + std::to_string(mesh.faces_read) +
              " faces but *MESH_NUMFACES (line " + std::to_string(mesh.face_count_line) + ") declares " +
              std::to_string(mesh.face_count));
    if (block.role == Ase_role::mesh) {
      if (!mesh.has_vertex_count) in.fail("the *MESH" + opened + " has no *MESH_NUMVERTEX");
      if (!mesh.has_face_count) in.fail("the *MESH" + opened + " has no *MESH_NUMFACES");
      if (!mesh.has_vertex_list && mesh.vertex_count > 0)
        in.fail("the *MESH" + opened + " has no *MESH_VERTEX_LIST (it declares " + std::to_string(mesh.vertex_count) +
                " vertices)");
      if (!mesh.has_face_list && mesh.face_count > 0)
        in.fail("the *MESH" + opened + " has no *MESH_FACE_LIST (it declares " + std::to_string(mesh.face_count) +
                " faces)");
      ++meshes;
    }
  }

  // '*KEY … {': a block, whose role depends on where it opens.
  void open_block(std::string_view key, Ase_role parent) {
    Ase_block block{std::string(key), in.line_number(), Ase_role::other};
    if (key == "*GEOMOBJECT" && open.empty()) {
      block.role = Ase_role::geomobject;
    } else if (key == "*MESH" && parent == Ase_role::geomobject) {
      block.role = Ase_role::mesh;
      mesh = Ase_mesh();
      mesh.open_line = in.line_number();
      mesh.base = soup.points.size();
    } else if (key == "*MESH_VERTEX_LIST" && parent == Ase_role::mesh) {
      if (!mesh.has_vertex_count) in.fail("*MESH_VERTEX_LIST before *MESH_NUMVERTEX");
      if (mesh.has_vertex_list) in.fail("a second *MESH_VERTEX_LIST in the *MESH of line " + std::to_string(mesh.open_line));
      mesh.has_vertex_list = true;
      block.role = Ase_role::vertex_list;
    } else if (key == "*MESH_FACE_LIST" && parent == Ase_role::mesh) {
      if (!mesh.has_face_count) in.fail("*MESH_FACE_LIST before *MESH_NUMFACES");
      if (!mesh.has_vertex_count) in.fail("*MESH_FACE_LIST before *MESH_NUMVERTEX");
      if (mesh.has_face_list) in.fail("a second *MESH_FACE_LIST in the *MESH of line " + std::to_string(mesh.open_line));
      mesh.has_face_list = true;
      block.role = Ase_role::face_list;
    } else if (parent == Ase_role::mesh) {
      if (key == "*MESH_TVERTLIST") soup.drop("texture coordinates (*MESH_TVERTLIST)");
      if (key == "*MESH_CVERTLIST") soup.drop("vertex colours (*MESH_CVERTLIST)");
      if (key == "*MESH_NORMALS") soup.drop("normals (*MESH_NORMALS)");
    }
    open.push_back(std::move(block));
  }

  // *MESH_NUMVERTEX n or *MESH_NUMFACES n, once each per *MESH.
  void read_count(std::string_view key) {
    const auto& t = in.tokens();
    const bool vertices = key == "*MESH_NUMVERTEX";
    if (t.size() != 2) in.fail("expected '" + std::string(key) + " n'");
    if (vertices ? mesh.has_vertex_count : mesh.has_face_count) in.fail("a second " + std::string(key));
    const std::uint64_t n = in.to_unsigned(t[1], vertices ? "vertex count" : "face count");
    (vertices ? mesh.vertex_count : mesh.face_count) = n;
    (vertices ? mesh.has_vertex_count : mesh.has_face_count) = true;
    (vertices ? mesh.vertex_count_line : mesh.face_count_line) = in.line_number();
  }

  // *MESH_VERTEX i x y z, in order.
  void read_vertex(std::string_view key) {
    const auto& t = in.tokens();
    if (key != "*MESH_VERTEX") in.fail("expected *MESH_VERTEX in the *MESH_VERTEX_LIST, found " + quote(key));
    if (t.size() != 5) in.fail("expected '*MESH_VERTEX i x y z', found " + std::to_string(t.size() - 1) + " values");
    const std::uint64_t i = in.to_unsigned(t[1], "vertex index");
    if (i >= mesh.vertex_count)
      in.fail("vertex index " + std::to_string(i) + " is out of range: the *MESH declares " +
              std::to_string(mesh.vertex_count) + " vertices" + numvertex_at + std::to_string(mesh.vertex_count_line) +
              ")");
    if (i != mesh.vertices_read)
      in.fail("expected vertex " + std::to_string(mesh.vertices_read) + ", found vertex " + std::to_string(i) +
              " (vertices are listed in order)");
    soup.points.emplace_back(in.to_double(t[2], "x coordinate"), in.to_double(t[3], "y coordinate"),
                             in.to_double(t[4], "z coordinate"));
    ++mesh.vertices_read;
  }

  // *MESH_FACE i: A: a B: b C: c …, in order.
  void read_face(std::string_view key) {
    if (key != "*MESH_FACE") in.fail("expected *MESH_FACE in the *MESH_FACE_LIST, found " + quote(key));
    // "*MESH_FACE 0: A: 0 B: 1 C: 2 AB: 1 …": the colons are separators (some writers omit the
    // blank after them).
    std::string line(in.line());
    std::replace(line.begin(), line.end(), ':', ' ');
    std::vector<std::string_view> f;
    split_tokens(line, f, 8);
    if (f.size() < 8 || f[2] != "A" || f[4] != "B" || f[6] != "C") in.fail("expected '*MESH_FACE i: A: a B: b C: c'");
    const std::uint64_t i = in.to_unsigned(f[1], "face index");
    if (i >= mesh.face_count)
      in.fail("face index " + std::to_string(i) + " is out of range: the *MESH declares " +
              std::to_string(mesh.face_count) + " faces (*MESH_NUMFACES, line " + std::to_string(mesh.face_count_line) +
              ")");
    if (i != mesh.faces_read)
      in.fail("expected face " + std::to_string(mesh.faces_read) + ", found face " + std::to_string(i) +
              " (faces are listed in order)");
    for (int k = 0; k < 3; ++k) {
      const std::string corner(f[2 + 2 * k]);
      const std::uint64_t v = in.to_unsigned(f[3 + 2 * k], "vertex index");
      if (v >= mesh.vertex_count)
        in.fail("corner " + corner + " of face " + std::to_string(i) + ": vertex " + std::to_string(v) +
                " is out of range: the *MESH declares " + std::to_string(mesh.vertex_count) + " vertices" +
                numvertex_at + std::to_string(mesh.vertex_count_line) + ")");
      soup.corners.push_back(mesh.base + static_cast<std::size_t>(v));
    }
    soup.end_polygon(in.line_number());
    ++mesh.faces_read;
  }

  // Every block closed, and a mesh read.
  void finish() const {
    if (!open.empty())
      throw Invalid_input(Input_location::at_line(name, open.back().line),
                          "the block " + quote(open.back().key) + " opened here is not closed (the file ends at line " +
                              std::to_string(in.line_number()) + ")");
    if (meshes == 0)
      throw Invalid_input(Input_location::at_line(name, in.line_number()),
                          "no *GEOMOBJECT with a *MESH: the file holds no triangle mesh");
  }

  const std::string& name;
  Line_reader in;
  Polygon_soup soup;
  std::vector<Ase_block> open;
  Ase_mesh mesh;
  std::size_t meshes = 0;
  const std::string numvertex_at = " (*MESH_NUMVERTEX, line ";
};

}  // namespace

Polygon_soup parse_ase(std::string_view text, const std::string& name) { return Ase_reader(text, name).run(); }

}  // namespace internal
}  // namespace meshfit
