// Private: writing a file under a temporary name in its directory, renamed into place on success.
#ifndef MESHFIT_SRC_WRITE_FILE_H
#define MESHFIT_SRC_WRITE_FILE_H

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>

namespace meshfit {
namespace internal {

/// The file that writing to `path` replaces: `path`, or the end of its chain of symbolic links.
std::filesystem::path write_target(const std::string& path);

/// \throws Invalid_input naming `path` when it cannot be written as a regular file: it (or the
///         target of its symbolic link) exists and is not a regular file (directory, FIFO,
///         device, socket), its directory does not exist or is not writable, or its name is too long.
void check_writable(const std::string& path);

/// Calls `write` on a stream to a temporary file next to `path` (next to its target when `path`
/// is a symbolic link), then renames it onto `path` (the target: the link stays). On any failure
/// (an exception from `write`, a stream error) the temporary file is removed and the destination
/// is left as it was. \throws Invalid_input naming `path` when it cannot be written (check_writable).
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_SRC_WRITE_FILE_H
