// Helpers shared by the example-data generators (standard library only): 3-vectors, number
// formatting that round-trips, atomic file writing, the mesh they build.
#ifndef MESHFIT_EXAMPLE_DATA_COMMON_H
#define MESHFIT_EXAMPLE_DATA_COMMON_H

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace example_data {

using Vec = std::array<double, 3>;

inline Vec operator+(const Vec& p, const Vec& q) { return {p[0] + q[0], p[1] + q[1], p[2] + q[2]}; }
inline Vec operator-(const Vec& p, const Vec& q) { return {p[0] - q[0], p[1] - q[1], p[2] - q[2]}; }
inline Vec operator*(double s, const Vec& p) { return {s * p[0], s * p[1], s * p[2]}; }
inline double dot(const Vec& p, const Vec& q) { return p[0] * q[0] + p[1] * q[1] + p[2] * q[2]; }
inline double norm(const Vec& p) { return std::sqrt(dot(p, p)); }
inline Vec normalized(const Vec& p) { return (1.0 / norm(p)) * p; }

constexpr double kPi = 3.14159265358979323846;

inline void require(bool ok, const std::string& what) {
  if (!ok) throw std::runtime_error(what);
}

// %.17g round-trips every double; -0 is printed as 0 so equal points always print equally.
inline std::string fmt(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v == 0.0 ? 0.0 : v);
  require(std::strtod(buf, nullptr) == v, "coordinate does not round-trip through text");
  return buf;
}
inline std::string fmt(const Vec& p) { return fmt(p[0]) + " " + fmt(p[1]) + " " + fmt(p[2]); }

// Writing through a temporary file means an interrupted run never leaves a half-written file.
inline void write_file(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    require(static_cast<bool>(out), "cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, path);
}

struct Mesh {
  std::vector<Vec> vertices;
  std::vector<std::array<int, 3>> faces;
};

}  // namespace example_data

#endif  // MESHFIT_EXAMPLE_DATA_COMMON_H
