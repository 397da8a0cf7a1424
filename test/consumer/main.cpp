// A downstream program built against the installed meshfit (find_package(meshfit)): it fits the
// example template to the example curves on CGAL::Surface_mesh and on CGAL::Polyhedron_3 with a
// chain of named parameters, a map of its own on the vertices (a tag) and a UV map, and checks that
// none of its data is lost and that the outputs it asked for are filled in.
//   consumer <examples/data>
#include <meshfit/correspondence.h>
#include <meshfit/curve_network.h>
#include <meshfit/fit.h>
#include <meshfit/io.h>
#include <meshfit/parameters.h>
#include <meshfit/threads.h>
#include <meshfit/version.h>

#include <CGAL/Polyhedron_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/graph_traits_Polyhedron_3.h>
#include <CGAL/boost/graph/properties_Polyhedron_3.h>

#include <algorithm>
#include <array>
#include <iostream>
#include <set>
#include <string>
#include <unordered_set>
#include <vector>

namespace {

int failures = 0;
void expect(bool ok, const std::string& what) {
  if (!ok) {
    std::cerr << "FAILED: " << what << "\n";
    ++failures;
  }
}

// Fits `tm` and checks the caller's data; returns the result's points, sorted.
template <typename Mesh>
std::vector<std::array<double, 3>> fit_and_check(const std::string& name, const std::string& data) {
  using GT = boost::graph_traits<Mesh>;
  Mesh tm;
  meshfit::read_triangle_mesh(data + "/template.off", tm);
  const auto network = meshfit::read_curve_network(data + "/curves.polylines.txt");
  const auto pairs = meshfit::read_correspondences(data + "/pairs.txt", network);

  // The caller's own maps: a tag on every template vertex, a UV in [0.25, 0.75]^2, and the outputs.
  auto tag = get(CGAL::dynamic_vertex_property_t<int>(), tm);
  auto uv = get(CGAL::dynamic_vertex_property_t<meshfit::Kernel::Point_2>(), tm);
  auto region = get(CGAL::dynamic_face_property_t<int>(), tm);
  auto curve = get(CGAL::dynamic_edge_property_t<bool>(), tm);
  const std::vector<typename GT::vertex_descriptor> template_vertices(vertices(tm).begin(), vertices(tm).end());
  const std::size_t nt = template_vertices.size();
  for (std::size_t k = 0; k < nt; ++k) {
    put(tag, template_vertices[k], int(k));
    const double s = double(k) / double(nt);
    put(uv, template_vertices[k], meshfit::Kernel::Point_2(0.25 + 0.5 * s, 0.75 - 0.5 * s));
  }

  std::set<std::string> stages;
  std::set<int> threads_seen;
  std::size_t calls = 0;
  const int threads_before = meshfit::number_of_threads();
  const meshfit::Fit_report r = meshfit::fit_template_to_curves(
      tm, network, pairs,
      meshfit::parameters::progress([&](const meshfit::Progress_step& s) {
        stages.insert(s.stage);
        threads_seen.insert(meshfit::number_of_threads());
        ++calls;
      })
          .number_of_threads(1)
          .rbf_kernel(meshfit::Rbf_kernel::linear)
          .number_of_iterations(60)
          .step_size(0.9)
          .vertex_texture_map(uv)
          .face_patch_map(region)
          .edge_is_constrained_map(curve));

  const std::string at = name + ": ";
  expect(r.verification.passed(), at + "the verification passed");
  expect(calls > 0 && stages.count("deform") && stages.count("partition") && stages.count("smooth"),
         at + "the progress callback saw deform, partition and smooth");
  expect(threads_seen == std::set<int>{1} && meshfit::number_of_threads() == threads_before,
         at + "number_of_threads(1) held during the call only");
  expect(r.smoothing.iterations == 60, at + "number_of_iterations(60) reached the smoothing (" +
                                           std::to_string(r.smoothing.iterations) + ")");
  expect(num_vertices(tm) == r.vertices && r.vertices > nt, at + "the mesh holds the result, with vertices added");
  // Nothing of the caller's lost: each template vertex (by the descriptor taken before the fit)
  // keeps its tag and its UV.
  std::size_t kept = 0;
  for (std::size_t k = 0; k < nt; ++k) {
    const double s = double(k) / double(nt);
    const auto p = get(uv, template_vertices[k]);
    if (get(tag, template_vertices[k]) == int(k) && p.x() == 0.25 + 0.5 * s && p.y() == 0.75 - 0.5 * s) ++kept;
  }
  expect(kept == nt, at + std::to_string(kept) + " of " + std::to_string(nt) + " template vertices keep tag and UV");
  // The added vertices get a UV in the template's range (the tag map, not carried, is left alone).
  std::size_t added = 0, in_range = 0;
  std::unordered_set<typename GT::vertex_descriptor> template_set(template_vertices.begin(), template_vertices.end());
  for (auto v : vertices(tm)) {
    if (template_set.count(v)) continue;
    ++added;
    const auto p = get(uv, v);
    if (p.x() >= 0.25 && p.x() <= 0.75 && p.y() >= 0.25 && p.y() <= 0.75) ++in_range;
  }
  expect(added == r.vertices - nt && in_range == added,
         at + std::to_string(in_range) + " of " + std::to_string(added) + " added vertices have a UV in range");
  // Every face has a region; as many regions as the report and the network's Euler count say.
  std::set<int> regions;
  bool all_labelled = true;
  for (auto f : faces(tm)) {
    const int k = get(region, f);
    all_labelled = all_labelled && k >= 0 && std::size_t(k) < r.partition.regions;
    regions.insert(k);
  }
  expect(all_labelled && regions.size() == r.partition.regions && r.verification.expected_regions_known &&
             regions.size() == r.verification.expected_regions,
         at + std::to_string(regions.size()) + " regions in the face map");
  // Each network vertex is a mesh vertex at its position, on a curve edge.
  std::size_t curve_edges = 0;
  std::unordered_set<typename GT::vertex_descriptor> on_curves;
  for (auto e : edges(tm))
    if (get(curve, e)) {
      ++curve_edges;
      on_curves.insert(source(e, tm));
      on_curves.insert(target(e, tm));
    }
  std::size_t found = 0;
  for (std::size_t i = 0; i < network.number_of_vertices(); ++i)
    for (auto v : on_curves)
      if (get(CGAL::vertex_point, tm, v) == network.point(i)) {
        ++found;
        break;
      }
  expect(curve_edges >= network.number_of_segments() && found == network.number_of_vertices(),
         at + std::to_string(found) + " of " + std::to_string(network.number_of_vertices()) +
             " network vertices on the curve edges (" + std::to_string(curve_edges) + " edges)");

  std::vector<std::array<double, 3>> points;
  for (auto v : vertices(tm)) {
    const auto p = get(CGAL::vertex_point, tm, v);
    points.push_back({p.x(), p.y(), p.z()});
  }
  std::sort(points.begin(), points.end());
  std::cout << name << ": " << r.vertices << " vertices (" << added << " added), " << regions.size() << " regions, "
            << curve_edges << " curve edges, " << kept << " tags and UVs kept\n";
  return points;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  std::cout << "meshfit " << MESHFIT_VERSION_STRING << "\n";
  const auto a = fit_and_check<CGAL::Surface_mesh<meshfit::Point_3>>("Surface_mesh", argv[1]);
  const auto b = fit_and_check<CGAL::Polyhedron_3<meshfit::Kernel>>("Polyhedron_3", argv[1]);
  expect(a == b, "Surface_mesh and Polyhedron_3 give the same points");
  return failures == 0 ? 0 : 1;
}
