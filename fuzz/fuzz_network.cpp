// Fuzz targets of the curve network and correspondence readers, and of `meshfit check`'s
// validation of the three inputs against each other.
#include "fuzz_common.h"

#include <meshfit/check.h>
#include <meshfit/correspondence.h>
#include <meshfit/curve_network.h>

namespace {

const char* const fixed_curves = "4 0 0 0 1 0 0 0 1 0 0 0 0\n2 0 0 0 0 0 1\n3 1 0 0 1 1 1 0 0 1\n";

void check_network(const meshfit::Curve_network& net) {
  const std::size_t n = net.number_of_vertices();
  std::size_t degree_sum = 0;
  for (std::size_t v = 0; v < n; ++v) {
    MESHFIT_FUZZ_REQUIRE(meshfit_fuzz::finite(net.point(v)));
    MESHFIT_FUZZ_REQUIRE(net.component(v) < net.number_of_components());
    degree_sum += net.degree(v);
  }
  MESHFIT_FUZZ_REQUIRE(degree_sum == 2 * net.number_of_segments());
  for (const auto& s : net.segments()) MESHFIT_FUZZ_REQUIRE(s[0] < n && s[1] < n && s[0] != s[1]);
  std::size_t covered = 0;
  for (const auto& c : net.curves()) {
    MESHFIT_FUZZ_REQUIRE(c.vertices.size() >= 2);
    covered += c.vertices.size() - 1;
  }
  MESHFIT_FUZZ_REQUIRE(covered == net.number_of_segments());
  for (std::size_t v = 0; v < n; ++v) {
    const auto found = net.find_vertex(net.point(v));
    MESHFIT_FUZZ_REQUIRE(found.has_value());
  }
}

}  // namespace

MESHFIT_FUZZ_TARGET(polylines) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    check_network(meshfit::parse_curve_network(text, "fuzz-input"));
  } catch (const meshfit::Invalid_input& e) {
    meshfit_fuzz::check_error(e, "fuzz-input");
  }
  return 0;
}

MESHFIT_FUZZ_TARGET(correspondences) {
  static const meshfit::Curve_network net = meshfit::parse_curve_network(fixed_curves, "curves");
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto pairs = meshfit::parse_correspondences(text, "fuzz-input", net);
    for (const auto& c : pairs) MESHFIT_FUZZ_REQUIRE(c.network_vertex < net.number_of_vertices());
    const std::vector<meshfit::Point_3> tpl = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    meshfit::validate_correspondences(pairs, tpl, net);
    MESHFIT_FUZZ_REQUIRE(pairs.size() >= 4);
  } catch (const meshfit::Invalid_input& e) {
    meshfit_fuzz::check_error(e, "");
  }
  return 0;
}

// The input holds the three files of a `meshfit check` run, separated by lines "@@".
MESHFIT_FUZZ_TARGET(check) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::string part[3];
  std::size_t k = 0, pos = 0;
  while (k < 2) {
    const std::size_t sep = text.find("\n@@\n", pos);
    if (sep == std::string::npos) break;
    part[k++] = text.substr(pos, sep - pos + 1);
    pos = sep + 4;
  }
  part[k] = text.substr(std::min(pos, text.size()));
  try {
    const meshfit::Mesh_data mesh = meshfit::parse_mesh_data(part[0], meshfit::Mesh_format::off, "template");
    meshfit_fuzz::check_mesh(mesh);
    const meshfit::Mesh_summary s = meshfit::summarize_mesh(mesh);
    MESHFIT_FUZZ_REQUIRE(s.vertices == mesh.points.size() && s.faces == mesh.triangles.size());
    MESHFIT_FUZZ_REQUIRE(s.isolated_vertices <= s.vertices);
    const meshfit::Curve_network net = meshfit::parse_curve_network(part[1], "curves");
    check_network(net);
    const auto pairs = meshfit::parse_correspondences(part[2], "pairs", net);
    meshfit::validate_correspondences(pairs, mesh.points, net);
  } catch (const meshfit::Invalid_input& e) {
    meshfit_fuzz::check_error(e, "");
  }
  return 0;
}
