// Runs a fuzz target over files and directories of inputs (corpus, reproducers), so that every
// build re-checks them as an ordinary test:  meshfit_fuzz_replay <target> <file or dir>...
#include "fuzz_common.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 3 || !meshfit_fuzz::registry().count(argv[1])) {
    std::cerr << "usage: meshfit_fuzz_replay <target> <file or directory>...\ntargets:";
    for (const auto& kv : meshfit_fuzz::registry()) std::cerr << " " << kv.first;
    std::cerr << "\n";
    return 2;
  }
  const meshfit_fuzz::Target target = meshfit_fuzz::registry().at(argv[1]);
  std::vector<std::filesystem::path> files;
  for (int i = 2; i < argc; ++i) {
    const std::filesystem::path p(argv[i]);
    if (std::filesystem::is_directory(p)) {
      for (const auto& e : std::filesystem::directory_iterator(p))
        if (e.is_regular_file() && e.path().filename().string()[0] != '.') files.push_back(e.path());
    } else if (std::filesystem::exists(p)) {
      files.push_back(p);
    }
  }
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    std::ifstream in(f, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    target(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  }
  std::cout << argv[1] << ": " << files.size() << " inputs replayed\n";
  return files.empty() ? 1 : 0;
}
