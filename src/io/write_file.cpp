#include "write_file.h"

#include <meshfit/exceptions.h>
#include <meshfit/io.h>

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sys/stat.h>
#include <unistd.h>

namespace meshfit {

namespace fs = std::filesystem;

namespace {

Input_location file_location(const std::string& path) { return Input_location{path, 0, Input_location::no_offset}; }

const char* kind_of(fs::file_type t) {
  switch (t) {
    case fs::file_type::directory: return "a directory";
    case fs::file_type::fifo: return "a FIFO";
    case fs::file_type::character: return "a character device";
    case fs::file_type::block: return "a block device";
    case fs::file_type::socket: return "a socket";
    default: return "not a regular file";
  }
}

/// The mkstemp pattern of the temporary file written beside `target` and renamed onto it.
std::string temporary_name(const fs::path& target) {
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  // The temporary name does not grow with the output's, which may be as long as the system allows.
  return (dir / ("." + target.filename().string().substr(0, 64) + ".tmp-XXXXXX")).string();
}

}  // namespace

namespace internal {

fs::path write_target(const std::string& path) {
  fs::path p(path);
  for (int hops = 0; hops < 40; ++hops) {
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(p, ec))) return p;
    const fs::path link = fs::read_symlink(p, ec);
    if (ec) return p;
    p = link.is_absolute() ? link : p.parent_path() / link;
  }
  throw Invalid_input(file_location(path), "too many levels of symbolic links");
}

void check_writable(const std::string& path) {
  const Input_location where = file_location(path);
  if (path.empty()) throw Invalid_input("the output path is empty");
  const fs::path target = write_target(path);
  std::error_code ec;
  const fs::file_status st = fs::status(target, ec);
  if (fs::exists(st) && !fs::is_regular_file(st))
    throw Invalid_input(where, std::string("exists and is ") + kind_of(st.type()) +
                                   "; meshfit writes only regular files (remove it or choose another name)");
  const std::string name = target.filename().string();
  if (name.empty() || name == "." || name == "..")
    throw Invalid_input(where, "names a directory, not a file");
  // Before the directory is looked at: a path over PATH_MAX makes every look-up fail as if the
  // directory did not exist.
  if (target.string().size() >= PATH_MAX)
    throw Invalid_input(where, "the path is " + std::to_string(target.string().size()) + " bytes long; at most " +
                                   std::to_string(PATH_MAX - 1));
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const fs::file_status dst = fs::status(dir, ec);
  if (!fs::exists(dst)) throw Invalid_input(where, "the directory '" + dir.string() + "' does not exist");
  if (!fs::is_directory(dst)) throw Invalid_input(where, "'" + dir.string() + "' is not a directory");
  long name_max = ::pathconf(dir.c_str(), _PC_NAME_MAX);
  if (name_max <= 0) name_max = 255;
  if (name.size() > static_cast<std::size_t>(name_max))
    throw Invalid_input(where, "the file name is " + std::to_string(name.size()) + " bytes long; at most " +
                                   std::to_string(name_max) + " here");
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw Invalid_input(where, "cannot write in the directory '" + dir.string() + "': " + std::strerror(errno));
  // Some directories pass access() and still refuse new files (/proc): create the temporary file
  // the write would, now, before any work.
  std::string tmp = temporary_name(target);
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) throw Invalid_input(where, std::string("cannot create the output file: ") + std::strerror(errno));
  ::close(fd);
  std::remove(tmp.c_str());
}

}  // namespace internal

void check_output_path(const std::string& output, const std::vector<std::string>& inputs) {
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
      throw Invalid_input(file_location(output),
                          "the output is the input file '" + input + "'; refusing to overwrite an input");
  }
  internal::check_writable(output);
}

namespace internal {

void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const Input_location where = file_location(path);
  check_writable(path);
  // A symbolic link is followed: its target is replaced (atomically), the link stays.
  const fs::path target = write_target(path);
  std::string tmp = temporary_name(target);
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) throw Invalid_input(where, std::string("cannot create the output file: ") + std::strerror(errno));
  // mkstemp creates the file private to its owner: give it the replaced file's permissions, or
  // the usual ones.
  struct stat old {};
  if (::stat(target.c_str(), &old) == 0) {
    ::fchmod(fd, old.st_mode & 07777);
  } else {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    ::fchmod(fd, 0666 & ~mask);
  }
  ::close(fd);
  try {
    {
      std::ofstream os(tmp, std::ios::binary | std::ios::trunc);
      if (!os) throw Invalid_input(where, "cannot open a temporary file for writing");
      write(os);
      os.close();
      if (!os) throw Invalid_input(where, "write error (disk full?)");
    }
    if (std::rename(tmp.c_str(), target.c_str()) != 0)
      throw Invalid_input(where, std::string("cannot rename the temporary file into place: ") +
                                     std::strerror(errno));
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
}

}  // namespace internal
}  // namespace meshfit
