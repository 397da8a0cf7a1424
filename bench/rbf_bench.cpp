// Benchmark of the RBF fit and evaluation, and of the closest-point search. Prints one line per
// case; bench/run_benchmarks.sh runs it beside SciPy and prints the comparison table.
//   rbf_bench <n> <m> <kernel: linear|cubic> <data dir>
// reads <dir>/centres_<n>.bin, values_<n>.bin, points_<m>.bin (float64 x,y,z triples), writes
// <dir>/meshfit_<n>_<m>.bin with the evaluated points.
#include <meshfit/rbf.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

namespace {

std::vector<meshfit::Point_3> read_points(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw std::runtime_error("cannot read " + path);
  const std::streamsize bytes = in.tellg();
  in.seekg(0);
  std::vector<double> raw(static_cast<std::size_t>(bytes) / sizeof(double));
  in.read(reinterpret_cast<char*>(raw.data()), bytes);
  std::vector<meshfit::Point_3> out;
  out.reserve(raw.size() / 3);
  for (std::size_t i = 0; i + 2 < raw.size(); i += 3) out.emplace_back(raw[i], raw[i + 1], raw[i + 2]);
  return out;
}

void write_points(const std::string& path, const std::vector<meshfit::Point_3>& pts) {
  std::ofstream out(path, std::ios::binary);
  for (const auto& p : pts) {
    const double xyz[3] = {p.x(), p.y(), p.z()};
    out.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
  }
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::cerr << "usage: rbf_bench <n> <m> <linear|cubic> <data dir>\n";
    return 2;
  }
  const std::string n = argv[1], m = argv[2], dir = argv[4];
  const meshfit::Rbf_kernel kernel =
      std::string(argv[3]) == "cubic" ? meshfit::Rbf_kernel::cubic : meshfit::Rbf_kernel::linear;
  const auto centres = read_points(dir + "/centres_" + n + ".bin");
  const auto values = read_points(dir + "/values_" + n + ".bin");
  const auto points = read_points(dir + "/points_" + m + ".bin");

  auto t0 = std::chrono::steady_clock::now();
  const meshfit::Rbf_interpolant E = meshfit::Rbf_interpolant::fit(centres, values, kernel);
  const double fit_s = seconds_since(t0);
  std::vector<meshfit::Point_3> out;
  t0 = std::chrono::steady_clock::now();
  E.evaluate(points, out);
  const double eval_s = seconds_since(t0);
  write_points(dir + "/meshfit_" + n + "_" + m + ".bin", out);
  const double pairs = double(points.size()) * double(centres.size());
  std::printf("meshfit n=%s m=%s fit_s=%.3f eval_s=%.3f ns_per_pair_core=%.3f\n", n.c_str(), m.c_str(), fit_s,
              eval_s, eval_s * 1e9 * std::thread::hardware_concurrency() / pairs);
  return 0;
}
