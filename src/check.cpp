#include <meshfit/check.h>
#include <meshfit/internal/smallest_angle.h>
#include <boost/pending/disjoint_sets.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace meshfit {

Mesh_summary summarize_mesh(const Mesh_data& mesh) {
  Mesh_summary s;
  s.vertices = mesh.points.size();
  s.faces = mesh.triangles.size();
  const std::size_t n = mesh.points.size();

  // Undirected edges, and boundary half-edges (edges with one face, oriented as the boundary
  // runs: opposite to their face).
  std::vector<std::pair<std::size_t, std::size_t>> directed;
  directed.reserve(3 * s.faces);
  for (const auto& t : mesh.triangles)
    for (int j = 0; j < 3; ++j) directed.emplace_back(t[j], t[(j + 1) % 3]);
  std::vector<std::pair<std::size_t, std::size_t>> undirected;
  undirected.reserve(directed.size());
  for (const auto& d : directed) undirected.emplace_back(std::min(d.first, d.second), std::max(d.first, d.second));
  std::sort(undirected.begin(), undirected.end());
  std::sort(directed.begin(), directed.end());
  std::vector<std::size_t> boundary_next(n, SIZE_MAX);
  for (std::size_t i = 0; i < undirected.size();) {
    std::size_t j = i + 1;
    while (j < undirected.size() && undirected[j] == undirected[i]) ++j;
    ++s.edges;
    if (j - i == 1) {
      const auto [a, b] = undirected[i];
      // The face has a->b or b->a; the boundary runs the other way.
      if (std::binary_search(directed.begin(), directed.end(), std::make_pair(a, b))) boundary_next[b] = a;
      else boundary_next[a] = b;
    }
    i = j;
  }

  // Components over faces; Euler characteristic per component gives its genus.
  boost::disjoint_sets_with_storage<> sets(n);
  auto root = [&](std::size_t i) { return sets.find_set(i); };
  std::vector<bool> used(n, false);
  for (const auto& t : mesh.triangles) {
    for (std::size_t v : t) used[v] = true;
    for (int j = 1; j < 3; ++j) sets.union_set(t[0], t[j]);
  }
  std::vector<long long> chi(n, 0), boundaries(n, 0);
  for (std::size_t v = 0; v < n; ++v) {
    if (!used[v]) { ++s.isolated_vertices; continue; }
    ++chi[root(v)];
  }
  for (const auto& t : mesh.triangles) ++chi[root(t[0])];
  for (std::size_t i = 0; i < undirected.size();) {
    std::size_t j = i + 1;
    while (j < undirected.size() && undirected[j] == undirected[i]) ++j;
    --chi[root(undirected[i].first)];
    i = j;
  }
  std::vector<bool> seen(n, false);
  for (std::size_t v = 0; v < n; ++v) {
    if (boundary_next[v] == SIZE_MAX || seen[v]) continue;
    ++s.boundaries;
    ++boundaries[root(v)];
    for (std::size_t w = v; w != SIZE_MAX && !seen[w]; w = boundary_next[w]) seen[w] = true;
  }
  for (std::size_t v = 0; v < n; ++v) {
    if (!used[v] || root(v) != v) continue;
    ++s.components;
    const long long g2 = 2 - chi[v] - boundaries[v];
    if (g2 > 0) s.genus += static_cast<std::size_t>(g2 / 2);
  }
  return s;
}

double minimum_angle_degrees(const Mesh_data& m) {
  double best = CGAL_PI;
  for (const auto& t : m.triangles)
    best = std::min(best, internal::smallest_angle(m.points[t[0]], m.points[t[1]], m.points[t[2]]));
  return best * 180 / CGAL_PI;
}

Check_summary check_inputs(const std::string& template_path, const std::string& curves_path,
                           const std::string& correspondences_path, double relative_merge_tolerance) {
  Check_summary s;
  const Mesh_data mesh = read_mesh_data(template_path, &s.mesh_report);
  if (mesh.triangles.empty())
    throw Invalid_input(Input_location{template_path, 0, Input_location::no_offset},
                        "the template has no face");
  s.mesh = summarize_mesh(mesh);
  const Curve_network network = read_curve_network(curves_path, relative_merge_tolerance);
  const auto pairs = read_correspondences(correspondences_path, network);
  // As deform and fit: coplanar template vertices are fine (the RBF adds auxiliary pairs).
  validate_correspondences(pairs, mesh.points, network, true);

  s.network_vertices = network.number_of_vertices();
  s.network_segments = network.number_of_segments();
  s.feature_points = network.feature_points().size();
  s.endpoints = network.endpoints().size();
  s.closed_polylines = network.number_of_closed_polylines();
  s.curves = network.curves().size();
  s.independent_cycles = network.number_of_independent_cycles();
  s.network_components = network.number_of_components();
  s.correspondences = pairs.size();

  auto list = [](const std::vector<std::size_t>& v) {
    std::string out;
    for (std::size_t i = 0; i < v.size() && i < 5; ++i) out += (i ? ", " : "") + std::to_string(v[i]);
    if (v.size() > 5) out += ", …";
    return out;
  };
  const auto& r = s.mesh_report;
  if (!r.degenerate_faces.empty())
    s.problems.push_back(std::to_string(r.degenerate_faces.size()) +
                         " degenerate (zero-area) template faces: " + list(r.degenerate_faces));
  if (!r.isolated_vertices.empty())
    s.problems.push_back(std::to_string(r.isolated_vertices.size()) +
                         " template vertices used by no face: " + list(r.isolated_vertices));
  if (network.number_of_repeated_segments() > 0)
    s.problems.push_back(std::to_string(network.number_of_repeated_segments()) +
                         " curve segments given more than once (kept once)");
  if (s.network_vertices > s.mesh.vertices)
    s.problems.push_back("the network has more vertices (" + std::to_string(s.network_vertices) +
                         ") than the template (" + std::to_string(s.mesh.vertices) +
                         "): the template will be refined where curves are dense");
  return s;
}

}  // namespace meshfit
