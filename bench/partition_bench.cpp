// Benchmark of stage 2: partition a sphere of about 2 × <points> faces by <circles> parallel
// circles of <samples> segments each. The mesh is the convex hull of random points and the circles'
// samples, so every network vertex is a mesh vertex and the segments are (mostly) not edges.
//   partition_bench <points> <circles> <samples> [repeats] [order]
// order: "hilbert" (default: the points, hence the mesh's vertices and faces, in Hilbert-curve
// order, as meshes from modelling tools and scanners usually come) or "random" (the order of
// random generation: every step of a walk is a cache miss on a 1e6-face mesh).
// Prints key=value pairs: the counts of the report and the time per segment and per face crossed
// (the fastest of `repeats` runs, each on a fresh copy of the mesh).
#include <meshfit/partition.h>

#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <CGAL/Spatial_sort_traits_adapter_3.h>
#include <CGAL/hilbert_sort.h>
#include <meshfit/io.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

int main(int argc, char** argv) {
  if (argc < 4 || argc > 6) {
    std::fprintf(stderr, "usage: partition_bench <points> <circles> <samples> [repeats] [hilbert|random]\n");
    return 2;
  }
  const std::size_t n = std::stoul(argv[1]), circles = std::stoul(argv[2]), samples = std::stoul(argv[3]);
  const std::size_t repeats = argc >= 5 ? std::stoul(argv[4]) : 1;
  const std::string order = argc >= 6 ? argv[5] : "hilbert";
  using Mesh = CGAL::Surface_mesh<meshfit::Point_3>;
  std::mt19937_64 rng(4);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(0, 2 * CGAL_PI);
  std::vector<meshfit::Point_3> points;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = g(rng), y = g(rng), z = g(rng), l = std::sqrt(x * x + y * y + z * z);
    points.emplace_back(x / l, y / l, z / l);
  }
  std::vector<meshfit::Curve_network::Polyline> polylines;
  for (std::size_t c = 0; c < circles; ++c) {
    const double lat = -1.4 + 2.8 * (c + 0.5) / circles, phase = u(rng);
    meshfit::Curve_network::Polyline pl;
    for (std::size_t k = 0; k < samples; ++k) {
      const double t = phase + 2 * CGAL_PI * k / samples;
      pl.emplace_back(std::cos(lat) * std::cos(t), std::cos(lat) * std::sin(t), std::sin(lat));
    }
    points.insert(points.end(), pl.begin(), pl.end());
    pl.push_back(pl.front());
    polylines.push_back(pl);
  }
  auto t0 = std::chrono::steady_clock::now();
  Mesh tm;
  CGAL::convex_hull_3(points.begin(), points.end(), tm);
  const double hull_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (order == "hilbert") {
    // Renumber the vertices along a Hilbert curve and the faces by their first vertex.
    meshfit::Mesh_data d = meshfit::to_mesh_data(tm);
    std::vector<std::ptrdiff_t> by_curve(d.points.size());
    std::vector<std::size_t> new_index(d.points.size());
    for (std::size_t i = 0; i < by_curve.size(); ++i) by_curve[i] = static_cast<std::ptrdiff_t>(i);
    using Traits = CGAL::Spatial_sort_traits_adapter_3<meshfit::Kernel, const meshfit::Point_3*>;
    CGAL::hilbert_sort(by_curve.begin(), by_curve.end(), Traits(d.points.data()));
    meshfit::Mesh_data sorted;
    for (std::size_t k = 0; k < by_curve.size(); ++k) {
      new_index[static_cast<std::size_t>(by_curve[k])] = k;
      sorted.points.push_back(d.points[static_cast<std::size_t>(by_curve[k])]);
    }
    for (auto t : d.triangles) sorted.triangles.push_back({new_index[t[0]], new_index[t[1]], new_index[t[2]]});
    std::sort(sorted.triangles.begin(), sorted.triangles.end(), [](const auto& x, const auto& y) {
      return std::min({x[0], x[1], x[2]}) < std::min({y[0], y[1], y[2]});
    });
    meshfit::build_triangle_mesh(sorted, tm);
  }
  const meshfit::Curve_network network(polylines);

  meshfit::Partition_report r;
  for (std::size_t run = 0; run < repeats; ++run) {
    Mesh copy = tm;
    auto curve = copy.add_property_map<Mesh::Edge_index, bool>("e:curve", false).first;
    auto region = copy.add_property_map<Mesh::Face_index, int>("f:region", 0).first;
    const meshfit::Partition_report ri = meshfit::partition_mesh(
        copy, network, CGAL::parameters::edge_is_constrained_map(curve).face_patch_map(region));
    if (run == 0 || ri.seconds < r.seconds) r = ri;
  }
  const std::size_t inserted = r.by_walk + r.by_fallback;
  std::printf(
      "faces=%zu segments=%zu existing=%zu walk=%zu fallback=%zu not_embedded=%zu regions=%zu faces_crossed=%zu "
      "flips=%zu hull_s=%.3f match_s=%.3f walk_s=%.3f fallback_s=%.3f region_s=%.3f total_s=%.3f "
      "segments_per_s=%.0f ns_per_face_crossed=%.0f\n",
      static_cast<std::size_t>(tm.number_of_faces()), r.segments, r.existing_edges, r.by_walk, r.by_fallback,
      r.not_embedded.size(), r.regions, r.faces_crossed, r.edge_flips, hull_s, r.matching_seconds, r.walk_seconds,
      r.fallback_seconds, r.region_seconds, r.seconds, inserted / (r.walk_seconds + r.fallback_seconds),
      1e9 * r.walk_seconds / std::max<std::size_t>(1, r.faces_crossed));
  return r.not_embedded.empty() ? 0 : 3;
}
