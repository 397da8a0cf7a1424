// Writes the inputs of the end-to-end benchmark into a directory:
//   - a template of at least <faces> faces: an icosphere (20 × 4^k faces) laid on a slightly
//     larger copy of the ellipsoid below (the benchmark measures the cost of the stages, so the
//     template starts near the curves);
//   - a network of about <network_vertices> vertices on the ellipsoid x²/4 + y²/0.64 + z²/0.49 = 1:
//     8 parallels and 16 meridian arcs between them, sharing their crossings;
//   - pairs: every crossing with its nearest template vertex.
//   fit_bench_data <faces> <network_vertices> <output_dir>
#include <meshfit/curve_network.h>
#include <meshfit/io.h>

#include <CGAL/Surface_mesh.h>

#include <array>
#include <cmath>
#include <map>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: fit_bench_data <faces> <network_vertices> <output_dir>\n");
    return 2;
  }
  const std::size_t faces = std::stoul(argv[1]), wanted = std::stoul(argv[2]);
  const std::string dir = argv[3];
  using Point = meshfit::Point_3;

  // Template: an icosphere (an icosahedron subdivided until it has at least `faces` faces, so
  // 20 × 4^k), projected onto the ellipsoid slightly enlarged.
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<std::array<double, 3>> v{{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                       {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<std::size_t, 3>> f{{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9},
                                            {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2},
                                            {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10},
                                            {8, 6, 7}, {9, 8, 1}};
  while (f.size() < faces) {
    std::map<std::pair<std::size_t, std::size_t>, std::size_t> mid;
    auto middle = [&](std::size_t a, std::size_t b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back({(v[a][0] + v[b][0]) / 2, (v[a][1] + v[b][1]) / 2, (v[a][2] + v[b][2]) / 2});
      return mid[key] = v.size() - 1;
    };
    std::vector<std::array<std::size_t, 3>> g;
    for (const auto& c : f) {
      const std::size_t ab = middle(c[0], c[1]), bc = middle(c[1], c[2]), ca = middle(c[2], c[0]);
      g.push_back({c[0], ab, ca});
      g.push_back({c[1], bc, ab});
      g.push_back({c[2], ca, bc});
      g.push_back({ab, bc, ca});
    }
    f.swap(g);
  }
  meshfit::Mesh_data sphere;
  for (const auto& p : v) {
    const double l = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    sphere.points.emplace_back(2.02 * p[0] / l, 0.81 * p[1] / l, 0.71 * p[2] / l);
  }
  sphere.triangles = f;
  CGAL::Surface_mesh<Point> tm;
  meshfit::build_triangle_mesh(sphere, tm);
  meshfit::write_triangle_mesh(dir + "/template.off", tm);

  // Network: a (theta, phi) grid of curves on the band |phi| <= 3pi/8 (the poles, where
  // meridians would crowd, are left out): 8 parallels (closed) and 16 meridian arcs from the lowest
  // parallel to the highest, sharing the crossings. S samples along a parallel, T along an arc.
  // (Spread over many curves, the network is nowhere much denser than the template.)
  const int parallels = 8, meridians = 16;
  auto multiple = [](double x, int m) { return std::max(m, static_cast<int>(std::lround(x / m)) * m); };
  const int S = multiple(wanted / 2.0 / parallels, meridians);
  const int T = multiple(wanted / 2.0 / meridians, parallels - 1);
  auto at = [](double theta, double phi) {
    return Point(2 * std::cos(phi) * std::cos(theta), 0.8 * std::cos(phi) * std::sin(theta), 0.7 * std::sin(phi));
  };
  const double pi = std::acos(-1.0);
  auto phi_of = [&](int k) { return -3 * pi / 8 + 3 * pi / 4 * k / T; };  // k = 0..T
  std::vector<std::vector<Point>> lines;
  for (int p = 0; p < parallels; ++p) {
    const int k = T * p / (parallels - 1);
    std::vector<Point> line;
    for (int j = 0; j <= S; ++j) line.push_back(at(2 * pi * (j % S) / S, phi_of(k)));
    lines.push_back(line);
  }
  for (int m = 0; m < meridians; ++m) {
    const int j = S * m / meridians;
    std::vector<Point> line;
    for (int k = 0; k <= T; ++k) line.push_back(at(2 * pi * j / S, phi_of(k)));
    lines.push_back(line);
  }
  {
    std::ofstream out(dir + "/curves.polylines.txt");
    out.precision(17);
    for (const auto& l : lines) {
      out << l.size();
      for (const Point& p : l) out << ' ' << p.x() << ' ' << p.y() << ' ' << p.z();
      out << '\n';
    }
  }
  const meshfit::Curve_network network = meshfit::read_curve_network(dir + "/curves.polylines.txt");
  // Pairs: every feature point with its nearest template vertex.
  std::ofstream pairs(dir + "/pairs.txt");
  pairs.precision(17);
  std::vector<std::size_t> used;
  for (std::size_t n : network.feature_points()) {
    const Point& p = network.point(n);
    std::size_t best = 0;
    double d2 = 1e300;
    for (auto u : tm.vertices())
      if (CGAL::squared_distance(tm.point(u), p) < d2) d2 = CGAL::squared_distance(tm.point(u), p), best = u.idx();
    if (std::find(used.begin(), used.end(), best) != used.end()) continue;
    used.push_back(best);
    pairs << best << ' ' << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  }
  std::printf("template_faces=%zu template_vertices=%zu network_vertices=%zu segments=%zu pairs=%zu\n",
              static_cast<std::size_t>(tm.number_of_faces()), static_cast<std::size_t>(tm.number_of_vertices()),
              network.number_of_vertices(), network.number_of_segments(), used.size());
  return 0;
}
