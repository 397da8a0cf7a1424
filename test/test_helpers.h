// Shared helpers of the meshfit tests.
#ifndef MESHFIT_TEST_HELPERS_H
#define MESHFIT_TEST_HELPERS_H

#include <meshfit/exceptions.h>
#include <meshfit/io.h>

#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

namespace meshfit_test {

/// A fresh directory under the system temporary directory, removed at the end of the scope.
class Temp_dir {
 public:
  Temp_dir() {
    std::string tmpl = (std::filesystem::temp_directory_path() / "meshfit-test-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    m_path = tmpl;
  }
  ~Temp_dir() {
    std::error_code ec;
    std::filesystem::remove_all(m_path, ec);
  }
  std::string file(const std::string& name) const { return (m_path / name).string(); }
  std::string write(const std::string& name, const std::string& content) const {
    const std::string p = file(name);
    std::ofstream(p, std::ios::binary) << content;
    return p;
  }

 private:
  std::filesystem::path m_path;
};

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// Runs `f`, which must throw meshfit::Invalid_input whose location has `line` (0: no line) and
/// whose message contains `fragment`.
/// What the meshfit command did: its exit status (128 + the signal when killed), stdout, stderr.
struct Run_result {
  int status = -1;
  std::string out, err;
};

/// `s` in single quotes, for a shell command line.
inline std::string q(const std::string& s) { return "'" + s + "'"; }

#ifdef MESHFIT_CLI
/// Runs `meshfit <args>` from the shell in `dir` (its working directory), stdin from /dev/null.
inline Run_result run(const Temp_dir& dir, const std::string& args) {
  const std::string out = dir.file("stdout.txt"), err = dir.file("stderr.txt");
  const std::string cmd =
      "cd " + q(dir.file("")) + " && " + q(MESHFIT_CLI) + " " + args + " > " + q(out) + " 2> " + q(err) + " < /dev/null";
  const int raw = std::system(cmd.c_str());
  Run_result r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  r.out = read_text(out);
  r.err = read_text(err);
  return r;
}
#endif

inline void require_invalid(const std::function<void()>& f, std::size_t line,
                            const std::string& fragment) {
  try {
    f();
  } catch (const meshfit::Invalid_input& e) {
    INFO("message: " << e.what());
    CHECK(e.where().line == line);
    CHECK(std::string(e.what()).find(fragment) != std::string::npos);
    return;
  }
  FAIL("no meshfit::Invalid_input was thrown (expected line " << line << ", '" << fragment << "')");
}

/// A closed octahedron: 6 vertices, 8 outward-oriented triangles.
inline meshfit::Mesh_data octahedron() {
  meshfit::Mesh_data m;
  m.points = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                 {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  return m;
}

/// An n×n grid of unit squares in the plane z = 0, two triangles each: an open disc.
inline meshfit::Mesh_data grid(std::size_t n) {
  meshfit::Mesh_data m;
  for (std::size_t j = 0; j <= n; ++j)
    for (std::size_t i = 0; i <= n; ++i) m.points.emplace_back(double(i), double(j), 0.0);
  auto id = [n](std::size_t i, std::size_t j) { return j * (n + 1) + i; };
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t i = 0; i < n; ++i) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

}  // namespace meshfit_test

#endif  // MESHFIT_TEST_HELPERS_H
