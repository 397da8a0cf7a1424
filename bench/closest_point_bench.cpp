// Benchmark of the closest-point correspondences (k-d tree) against brute force.
//   closest_point_bench <network vertices n> <template vertices m>
#include <meshfit/correspondence.h>

#include <chrono>
#include <cstdio>
#include <random>
#include <string>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: closest_point_bench <n> <m>\n");
    return 2;
  }
  const std::size_t n = std::stoul(argv[1]), m = std::stoul(argv[2]);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g;
  auto on_sphere = [&](double jitter) {
    double x = g(rng), y = g(rng), z = g(rng);
    const double s = (1 + jitter * g(rng)) / std::sqrt(x * x + y * y + z * z);
    return meshfit::Point_3(x * s, y * s, z * s);
  };
  std::vector<meshfit::Point_3> tpl(m);
  for (auto& p : tpl) p = on_sphere(0.0);
  // The network: one polyline wandering over the sphere, slightly off it.
  meshfit::Curve_network::Polyline line(n);
  for (auto& p : line) p = on_sphere(0.01);
  const meshfit::Curve_network net({line});

  auto t0 = std::chrono::steady_clock::now();
  const auto a = meshfit::closest_point_correspondences(tpl, net);
  const double tree_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  t0 = std::chrono::steady_clock::now();
  std::vector<std::size_t> brute(net.number_of_vertices());
#pragma omp parallel for schedule(dynamic, 16)
  for (std::ptrdiff_t v = 0; v < static_cast<std::ptrdiff_t>(brute.size()); ++v) {
    const meshfit::Point_3& q = net.point(static_cast<std::size_t>(v));
    std::size_t best = 0;
    double bd = 1e300;
    for (std::size_t t = 0; t < m; ++t) {
      const double d = CGAL::squared_distance(q, tpl[t]);
      if (d < bd) { bd = d; best = t; }
    }
    brute[static_cast<std::size_t>(v)] = best;
  }
  const double brute_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::size_t agree = 0, compared = 0;
  for (std::size_t v = 0; v < brute.size(); ++v) {
    if (a.template_of[v] == meshfit::Closest_point_assignment::unassigned) continue;  // lost a conflict
    ++compared;
    agree += a.template_of[v] == brute[v];
  }
  std::printf("closest n=%zu m=%zu tree_s=%.3f brute_s=%.3f agree=%zu/%zu losers=%zu\n", n, m, tree_s, brute_s,
              agree, compared, a.losers.size());
  return agree == compared ? 0 : 1;
}
