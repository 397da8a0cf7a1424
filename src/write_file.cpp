#include "write_file.h"

#include <meshfit/exceptions.h>
#include <meshfit/io.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sys/stat.h>
#include <unistd.h>

namespace meshfit {

void check_output_path(const std::string& output, const std::vector<std::string>& inputs) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path out = fs::weakly_canonical(fs::path(output), ec);
  for (const std::string& input : inputs) {
    std::error_code ec1, ec2;
    bool same = fs::exists(output, ec1) && fs::exists(input, ec2) && fs::equivalent(output, input, ec1);
    if (!same && !ec) {
      std::error_code ec3;
      const fs::path in = fs::weakly_canonical(fs::path(input), ec3);
      same = !ec3 && in == out;
    }
    if (same)
      throw Invalid_input(Input_location{output, 0, Input_location::no_offset},
                          "the output is the input file '" + input + "'; refusing to overwrite an input");
  }
}

namespace internal {

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const Input_location where{path, 0, Input_location::no_offset};
  std::string tmp = path + ".tmp-XXXXXX";
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) throw Invalid_input(where, std::string("cannot create the output file: ") + std::strerror(errno));
  // mkstemp creates the file private to its owner; give the output the usual permissions.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd, 0666 & ~mask);
  ::close(fd);
  try {
    {
      std::ofstream os(tmp, std::ios::binary | std::ios::trunc);
      if (!os) throw Invalid_input(where, "cannot open a temporary file for writing");
      write(os);
      os.close();
      if (!os) throw Invalid_input(where, "write error (disk full?)");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0)
      throw Invalid_input(where, std::string("cannot rename the temporary file into place: ") +
                                     std::strerror(errno));
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
}

}  // namespace internal
}  // namespace meshfit
