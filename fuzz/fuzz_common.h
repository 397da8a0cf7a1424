// Shared by the fuzz targets. Each target is a function registered under a name:
// libfuzzer_main.cpp makes one of them libFuzzer's entry point (clang, MESHFIT_FUZZ=ON), and
// replay_main.cpp runs any of them over corpus and reproducer files with any compiler, as an
// ordinary test.
#ifndef MESHFIT_FUZZ_COMMON_H
#define MESHFIT_FUZZ_COMMON_H

#include <meshfit/exceptions.h>
#include <meshfit/io.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

namespace meshfit_fuzz {

using Target = int (*)(const std::uint8_t*, std::size_t);

inline std::map<std::string, Target>& registry() {
  static std::map<std::string, Target> r;
  return r;
}

struct Registrar {
  Registrar(const char* name, Target t) { registry()[name] = t; }
};

/// A guarantee the code under test broke: print it and abort, so that libFuzzer records the
/// input and the replay test fails.
[[noreturn]] inline void broken(const char* what, const char* file, int line) {
  std::fprintf(stderr, "meshfit fuzz: guarantee broken at %s:%d: %s\n", file, line, what);
  std::abort();
}

/// An Invalid_input must be one line that names the input.
inline void check_error(const meshfit::Invalid_input& e, const std::string& name) {
  const std::string w = e.what();
  if (w.empty() || w.find('\n') != std::string::npos) broken("error message is empty or several lines", __FILE__, __LINE__);
  if (!name.empty() && w.find(name) == std::string::npos) broken("error message does not name the input", __FILE__, __LINE__);
}

inline bool finite(const meshfit::Point_3& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
}

/// What read_mesh_data promises of what it returns.
inline void check_mesh(const meshfit::Mesh_data& m) {
  for (const auto& p : m.points)
    if (!finite(p)) broken("non-finite coordinate accepted", __FILE__, __LINE__);
  for (const auto& t : m.triangles) {
    for (std::size_t v : t)
      if (v >= m.points.size()) broken("triangle index out of range", __FILE__, __LINE__);
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) broken("triangle with a repeated vertex", __FILE__, __LINE__);
  }
  if (!m.face_patch.empty() && m.face_patch.size() != m.triangles.size())
    broken("face_patch size differs from the triangle count", __FILE__, __LINE__);
  for (const auto& e : m.curve_edges)
    if (e[0] >= m.points.size() || e[1] >= m.points.size() || e[0] == e[1])
      broken("bad curve edge accepted", __FILE__, __LINE__);
}

}  // namespace meshfit_fuzz

#define MESHFIT_FUZZ_REQUIRE(cond) \
  do {                             \
    if (!(cond)) ::meshfit_fuzz::broken(#cond, __FILE__, __LINE__); \
  } while (0)

#define MESHFIT_FUZZ_TARGET(NAME)                                                          \
  int meshfit_fuzz_##NAME(const std::uint8_t* data, std::size_t size);                     \
  static const ::meshfit_fuzz::Registrar meshfit_fuzz_registrar_##NAME(#NAME, meshfit_fuzz_##NAME); \
  int meshfit_fuzz_##NAME(const std::uint8_t* data, std::size_t size)

#endif  // MESHFIT_FUZZ_COMMON_H
