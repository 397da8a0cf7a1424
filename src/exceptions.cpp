#include <meshfit/exceptions.h>

namespace meshfit {

std::string Input_location::to_string() const {
  std::string s = file;
  if (line != 0) {
    s += (s.empty() ? "line " : ":") + std::to_string(line);
  } else if (byte_offset != no_offset) {
    s += (s.empty() ? "byte " : ": byte ") + std::to_string(byte_offset);
  }
  return s;
}

namespace {
std::string compose(const Input_location& where, const std::string& problem) {
  const std::string w = where.to_string();
  return w.empty() ? problem : w + ": " + problem;
}
}  // namespace

Invalid_input::Invalid_input(Input_location where, const std::string& problem)
    : std::invalid_argument(compose(where, problem)),
      m_where(std::move(where)),
      m_problem(problem) {}

}  // namespace meshfit
