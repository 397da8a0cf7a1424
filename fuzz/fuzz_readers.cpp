// Fuzz targets of the mesh readers: any input either reads into a mesh that keeps the reader's
// promises (and survives a write and a read back), or gives a one-line Invalid_input naming it.
#include "fuzz_common.h"

#include <algorithm>
#include <array>
#include <sstream>
#include <utility>
#include <vector>

namespace {

// The faces with their regions (-1 without), sorted by region when `grouped` (stable).
std::vector<std::pair<int, std::array<std::size_t, 3>>> faces_in_order(const meshfit::Mesh_data& d, bool grouped) {
  std::vector<std::pair<int, std::array<std::size_t, 3>>> f;
  for (std::size_t i = 0; i < d.triangles.size(); ++i)
    f.emplace_back(d.face_patch.empty() ? -1 : d.face_patch[i], d.triangles[i]);
  if (grouped) std::stable_sort(f.begin(), f.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return f;
}

int read_mesh(const std::uint8_t* data, std::size_t size, meshfit::Mesh_format format) {
  const std::string name = "fuzz-input";
  const std::string text(reinterpret_cast<const char*>(data), size);
  meshfit::Mesh_data m;
  try {
    meshfit::Mesh_read_report report;
    m = meshfit::parse_mesh_data(text, format, name, &report);
    MESHFIT_FUZZ_REQUIRE(report.polygons_read <= m.triangles.size());
  } catch (const meshfit::Invalid_input& e) {
    meshfit_fuzz::check_error(e, name);
    return 0;
  }
  meshfit_fuzz::check_mesh(m);
  // What was read writes and reads back to the same mesh (OFF keeps geometry only).
  for (meshfit::Mesh_format out : {meshfit::Mesh_format::obj, meshfit::Mesh_format::ply}) {
    std::ostringstream os;
    meshfit::write_mesh_data(os, out, m);
    const meshfit::Mesh_data back = meshfit::parse_mesh_data(os.str(), out, "round-trip");
    MESHFIT_FUZZ_REQUIRE(back.points.size() == m.points.size());
    // OBJ writes the faces grouped by region: compare in that order.
    const bool grouped = out == meshfit::Mesh_format::obj && !m.face_patch.empty();
    MESHFIT_FUZZ_REQUIRE(faces_in_order(back, grouped) == faces_in_order(m, grouped));
    for (std::size_t i = 0; i < m.points.size(); ++i) MESHFIT_FUZZ_REQUIRE(back.points[i] == m.points[i]);
  }
  return 0;
}

}  // namespace

MESHFIT_FUZZ_TARGET(off) { return read_mesh(data, size, meshfit::Mesh_format::off); }
MESHFIT_FUZZ_TARGET(obj) { return read_mesh(data, size, meshfit::Mesh_format::obj); }
MESHFIT_FUZZ_TARGET(ply) { return read_mesh(data, size, meshfit::Mesh_format::ply); }
MESHFIT_FUZZ_TARGET(stl) { return read_mesh(data, size, meshfit::Mesh_format::stl); }
