// Private: writing a file under a temporary name in its directory, renamed into place on success.
#ifndef MESHFIT_SRC_WRITE_FILE_H
#define MESHFIT_SRC_WRITE_FILE_H

#include <functional>
#include <iosfwd>
#include <string>

namespace meshfit {
namespace internal {

/// Calls `write` on a stream to a temporary file next to `path`, then renames it to `path`.
/// On any failure (an exception from `write`, a stream error) the temporary file is removed and
/// the destination is left as it was. \throws Invalid_input naming `path` when it cannot be written.
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_SRC_WRITE_FILE_H
