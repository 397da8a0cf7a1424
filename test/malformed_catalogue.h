// The catalogue of malformed inputs shared by the reader tests and the command-line tests: each
// case names the line (or byte offset) its error must name.
#ifndef MESHFIT_TEST_MALFORMED_CATALOGUE_H
#define MESHFIT_TEST_MALFORMED_CATALOGUE_H

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace meshfit_test {

enum class Input_kind { template_mesh, curves, correspondences };

struct Malformed_case {
  std::string name;
  Input_kind kind;
  std::string extension;  ///< of the malformed file (".off", ".polylines.txt", …)
  std::string content;
  std::size_t line;         ///< line the error must name; 0 when it names a byte or nothing
  std::size_t byte_offset;  ///< byte the error must name (binary files), or SIZE_MAX
  std::string fragment;     ///< text the message must contain
};

// Valid companions for the cases that break one input only.
inline const char* valid_template_off() {
  return "OFF\n6 8 0\n1 0 0\n-1 0 0\n0 1 0\n0 -1 0\n0 0 1\n0 0 -1\n"
         "3 0 2 4\n3 2 1 4\n3 1 3 4\n3 3 0 4\n3 2 0 5\n3 1 2 5\n3 3 1 5\n3 0 3 5\n";
}
inline const char* valid_curves() {
  return "# a triangle and a spoke\n4 0 0 0 1 0 0 0 1 0 0 0 0\n2 0 0 0 0 0 1\n";
}
inline const char* valid_pairs() { return "0 0 0 0\n1 1 0 0\n2 0 1 0\n4 0 0 1\n"; }

template <typename T>
void append_le(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s.append(b, sizeof(T));
}

inline std::string binary_ply_tetra(bool drop_last_byte, bool extra_bytes) {
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
      "property float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\n"
      "end_header\n";
  const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (const auto& q : p)
    for (float c : q) append_le(s, c);
  const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  for (const auto& t : f) {
    append_le<std::uint8_t>(s, 3);
    for (int i : t) append_le<std::int32_t>(s, i);
  }
  if (drop_last_byte) s.pop_back();
  if (extra_bytes) s += "xyz";
  return s;
}

inline std::size_t header_size(const std::string& s) { return s.find("end_header\n") + 11; }

inline std::vector<Malformed_case> malformed_catalogue() {
  const std::size_t none = SIZE_MAX;
  using K = Input_kind;
  std::vector<Malformed_case> c = {
      // ---- OFF
      {"empty OFF", K::template_mesh, ".off", "", 0, none, "empty file"},
      {"OFF of blanks and comments only", K::template_mesh, ".off", "# nothing\n\n  \n", 0, none, "empty file"},
      {"missing OFF header", K::template_mesh, ".off", "3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 1, none, "expected an OFF header"},
      {"4OFF unsupported", K::template_mesh, ".off", "4OFF\n1 0 0\n0 0 0 0\n", 1, none, "dimension"},
      {"OFF counts missing", K::template_mesh, ".off", "OFF\n", 1, none, "file ends after the header"},
      {"OFF counts not numbers", K::template_mesh, ".off", "OFF\nfour 1 0\n", 2, none, "vertex count"},
      {"OFF truncated vertices", K::template_mesh, ".off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n", 2, none, "declares 4 vertices but the file ends after 3"},
      {"OFF more faces declared than given", K::template_mesh, ".off", "OFF\n3 10 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 2, none, "declares 10 faces"},
      {"OFF absurd vertex count", K::template_mesh, ".off", "OFF\n2000000000 1 0\n0 0 0\n", 2, none, "declares 2000000000 vertices"},
      {"OFF count beyond 64 bits", K::template_mesh, ".off", "OFF\n99999999999999999999999 1 0\n", 2, none, "too large"},
      {"OFF NaN coordinate", K::template_mesh, ".off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", 4, none, "not a finite number"},
      {"OFF infinite coordinate", K::template_mesh, ".off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 -inf 0\n3 0 1 2\n", 5, none, "not a finite number"},
      {"OFF 1e400 coordinate", K::template_mesh, ".off", "OFF\n3 1 0\n0 0 1e400\n1 0 0\n0 1 0\n3 0 1 2\n", 3, none, "out of the range"},
      {"OFF garbage coordinate", K::template_mesh, ".off", "OFF\n3 1 0\n0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n", 4, none, "expected a number"},
      {"COFF truncated vertex line", K::template_mesh, ".off", "COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0\n", 4, none, "vertex 1 has 2 values"},
      {"OFF index out of range", K::template_mesh, ".off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", 6, none, "refers to vertex 7"},
      {"OFF negative index", K::template_mesh, ".off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", 6, none, "negative"},
      {"OFF face with two vertices", K::template_mesh, ".off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", 6, none, "has 2 vertices"},
      {"OFF face with no vertex", K::template_mesh, ".off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n0\n", 6, none, "has 0 vertices"},
      {"OFF face size larger than its line", K::template_mesh, ".off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n5 0 1 2\n", 6, none, "declares 5 vertices"},
      {"OFF absurd face size", K::template_mesh, ".off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4000000000 0 1 2\n", 6, none, "declares 4000000000 vertices"},
      {"OFF face size of 2^64-1", K::template_mesh, ".off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n18446744073709551615 0 1 2\n", 6, none, "declares 18446744073709551615 vertices"},
      {"OFF coordinate with two signs", K::template_mesh, ".off", "OFF\n3 1 0\n0 0 0\n+-1 0 0\n0 1 0\n3 0 1 2\n", 4, none, "expected a number"},
      {"OFF repeated vertex in a face", K::template_mesh, ".off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n", 6, none, "appears more than once"},
      {"OFF edge shared by three faces", K::template_mesh, ".off",
       "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n", 10, none, "shared by 3 faces"},
      {"OFF inconsistent orientation", K::template_mesh, ".off",
       "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 2 3\n", 8, none, "not consistently oriented"},
      {"OFF two fans at one vertex", K::template_mesh, ".off",
       "OFF\n5 2 0\n0 0 0\n1 0 0\n0 1 0\n-1 0 0\n0 -1 0\n3 0 1 2\n3 0 3 4\n", 9, none, "meet only at vertex 0"},
      {"OFF faces past the declared count", K::template_mesh, ".off",
       "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n", 7, none, "after the 1 declared faces"},
      {"binary OFF", K::template_mesh, ".off", "OFF BINARY\n", 1, none, "binary OFF"},
      // ---- OBJ
      {"OBJ zero index", K::template_mesh, ".obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, none, "OBJ indices start at 1"},
      {"OBJ negative index before the first vertex", K::template_mesh, ".obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", 4, none, "refers before the first vertex"},
      {"OBJ index out of range", K::template_mesh, ".obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 9\n", 5, none, "refers to vertex 9, but there are only 3 vertices"},
      {"OBJ vertex with two coordinates", K::template_mesh, ".obj", "v 0 0 0\nv 1 0\n", 2, none, "expected x y z"},
      {"OBJ face with two vertices", K::template_mesh, ".obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", 3, none, "has 2 vertices"},
      {"OBJ unknown statement", K::template_mesh, ".obj", "v 0 0 0\nvertex 1 0 0\n", 2, none, "unknown OBJ statement 'vertex'"},
      {"OBJ malformed index", K::template_mesh, ".obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x/1\n", 4, none, "expected an integer"},
      // ---- PLY
      {"PLY property before element", K::template_mesh, ".ply",
       "ply\nformat ascii 1.0\nproperty float x\nelement vertex 0\nend_header\n", 3, none, "'property' before any 'element'"},
      {"PLY without end_header", K::template_mesh, ".ply", "ply\nformat ascii 1.0\nelement vertex 0\n", 3, none, "no 'end_header'"},
      {"PLY unknown encoding", K::template_mesh, ".ply", "ply\nformat utf16 1.0\nend_header\n", 2, none, "unknown PLY encoding"},
      {"PLY not a PLY", K::template_mesh, ".ply", "OFF\n0 0 0\n", 1, none, "expected 'ply'"},
      {"PLY ASCII fewer vertices than declared", K::template_mesh, ".ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "end_header\n0 0 0\n1 0 0\n", 3, none, "declares 3 vertex elements but the file ends after 2"},
      {"PLY ASCII list longer than its line", K::template_mesh, ".ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n200 0 1 2\n",
       13, none, "declares 200 items"},
      {"PLY ASCII uchar out of range", K::template_mesh, ".ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n",
       13, none, "does not fit"},
      {"PLY vertex without z", K::template_mesh, ".ply",
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n", 3, none, "needs properties x, y and z"},
      {"binary PLY one byte short", K::template_mesh, ".ply", binary_ply_tetra(true, false), 0,
       header_size(binary_ply_tetra(true, false)) + 48 + 3 * 13 + 1, "element 'face' 3: list 'vertex_indices' declares 3 items but only 2 values are left"},
      {"binary PLY cut inside a vertex", K::template_mesh, ".ply", binary_ply_tetra(false, false).substr(0, header_size(binary_ply_tetra(false, false)) + 22),
       0, header_size(binary_ply_tetra(false, false)) + 20, "file ends inside element 'vertex' 1 (property 'z')"},
      {"binary PLY with trailing bytes", K::template_mesh, ".ply", binary_ply_tetra(false, true), 0,
       header_size(binary_ply_tetra(false, true)) + 48 + 4 * 13, "3 unexpected bytes"},
      {"PLY element without properties and an absurd count", K::template_mesh, ".ply",
       "ply\nformat binary_little_endian 1.0\nelement junk 18446744073709551615\nend_header\n", 3, none, "has no properties"},
      // ---- STL
      {"binary STL of wrong length", K::template_mesh, ".stl", std::string(80, ' ') + std::string("\x05\0\0\0", 4) + std::string(60, '\0'),
       0, 80, "declares 5 triangles"},
      {"ASCII STL truncated facet", K::template_mesh, ".stl",
       "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n", 5, none, "file ends inside a facet"},
      {"ASCII STL NaN vertex", K::template_mesh, ".stl",
       "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex NaN 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n", 5, none, "not a finite number"},
      {"too short for STL", K::template_mesh, ".stl", "hello", 0, 0, "not an STL file"},
      // ---- polylines
      {"polyline with a wrong count", K::curves, ".polylines.txt", "# c\n3 0 0 0 1 0 0 0 1 0 0 0 1\n\n4 0 0 0 1 1 1 2 2 2\n", 2, none, "declares 3 points"},
      {"polyline of one point", K::curves, ".polylines.txt", "2 0 0 0 1 0 0\n1 0 0 0\n", 2, none, "at least 2 points"},
      {"polyline with NaN", K::curves, ".polylines.txt", "2 0 0 0 1 0 0\n2 0 0 0 nan 1 1\n", 2, none, "not a finite number"},
      {"polyline with a zero-length segment", K::curves, ".polylines.txt", "2 0 0 0 1 0 0\n3 0 0 0 1 1 1 1 1 1\n", 2, none, "zero length"},
      {"polyline count not a number", K::curves, ".polylines.txt", "2.0 0 0 0 1 0 0\n", 1, none, "point count"},
      {"empty curve file", K::curves, ".polylines.txt", "# only a comment\n", 0, none, "no polyline"},
      // ---- correspondences
      {"pair with missing fields", K::correspondences, ".txt", "0 0 0 0\n1 1 0\n", 2, none, "expected 'template_vertex x y z'"},
      {"pair index out of range", K::correspondences, ".txt", "0 0 0 0\n1 1 0 0\n2 0 1 0\n# c\n60 0 0 1\n", 5, none, "out of range: the template has 6 vertices"},
      {"pair with negative index", K::correspondences, ".txt", "-1 0 0 0\n", 1, none, "negative"},
      {"pair point not a network vertex", K::correspondences, ".txt", "0 0 0 0\n1 0.5 0 0\n", 2, none, "not a vertex of the curve network"},
      {"pair repeating a template vertex", K::correspondences, ".txt", "0 0 0 0\n0 1 0 0\n", 2, none, "already paired on line 1"},
      {"pair with infinite coordinate", K::correspondences, ".txt", "0 0 0 inf\n", 1, none, "not a finite number"},
  };
  return c;
}

}  // namespace meshfit_test

#endif  // MESHFIT_TEST_MALFORMED_CATALOGUE_H
