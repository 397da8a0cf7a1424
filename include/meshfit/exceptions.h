// meshfit: typed exceptions. Every error meshfit reports on bad input is an Invalid_input that
// names where the problem is (file and line, byte offset, or element) and what it is.
#ifndef MESHFIT_EXCEPTIONS_H
#define MESHFIT_EXCEPTIONS_H

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>
#include <utility>

namespace meshfit {

/// Where in the input a problem was found. Any part may be unknown (empty file, zero line,
/// `no_offset`); `what()` of the exception shows only the known parts, compiler-style:
/// `file:line: problem`, `file: byte 1234: problem` or `file: problem`.
struct Input_location {
  /// The value of `byte_offset` when the offset is unknown.
  static constexpr std::size_t no_offset = static_cast<std::size_t>(-1);
  std::string file;                  ///< file name as given by the caller, may be empty
  std::size_t line = 0;              ///< 1-based line, 0 when unknown or not a text format
  std::size_t byte_offset = no_offset;  ///< 0-based byte offset in a binary file

  /// Line `line` (1-based) of text file `file`.
  static Input_location at_line(std::string file, std::size_t line) {
    Input_location l;
    l.file = std::move(file);
    l.line = line;
    return l;
  }
  /// Byte `offset` (0-based) of binary file `file`.
  static Input_location at_byte(std::string file, std::size_t offset) {
    Input_location l;
    l.file = std::move(file);
    l.byte_offset = offset;
    return l;
  }
  /// "file:line", "file: byte N" or "file" (empty when nothing is known).
  std::string to_string() const;
};

/// Thrown for every kind of bad input, in every build type. Derives from std::invalid_argument.
class Invalid_input : public std::invalid_argument {
 public:
  /// `problem` found at `where`; what() is `where.to_string()` followed by `": "` and `problem`.
  Invalid_input(Input_location where, const std::string& problem);
  /// `problem`, at no known place (the message names the element).
  explicit Invalid_input(const std::string& problem) : Invalid_input(Input_location{}, problem) {}

  /// Where the problem is (any part may be unknown).
  const Input_location& where() const noexcept { return m_where; }
  /// what() without the location.
  const std::string& problem() const noexcept { return m_problem; }

 private:
  Input_location m_where;
  std::string m_problem;
};

/// Thrown when a numerical step (a linear solve, say) fails or produces a non-finite value.
class Numerical_error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A number behind an Algorithm_failure, by name ("network_vertices", "estimated_bytes", …):
/// what the reason says in words, for a caller (and the command line's report) to read without
/// parsing the message.
struct Failure_figure {
  std::string name;  ///< snake_case, as in the command line's report
  double value = 0;  ///< the number (counts are exact up to 2^53)
};

/// Thrown when an algorithm cannot complete on valid input (a stage gives up); names the stage
/// and carries the figures that decided it.
class Algorithm_failure : public std::runtime_error {
 public:
  /// what() is `stage + ": " + reason`.
  Algorithm_failure(std::string stage, const std::string& reason, std::vector<Failure_figure> figures = {})
      : std::runtime_error(stage + ": " + reason), m_stage(std::move(stage)), m_reason(reason),
        m_figures(std::move(figures)) {}
  /// The stage that gave up: "deform", "partition", "smooth", "fit", ….
  const std::string& stage() const noexcept { return m_stage; }
  /// what() without the stage.
  const std::string& reason() const noexcept { return m_reason; }
  /// The numbers the reason is made of (empty for a cancel).
  const std::vector<Failure_figure>& figures() const noexcept { return m_figures; }

 private:
  std::string m_stage, m_reason;
  std::vector<Failure_figure> m_figures;
};

/// Thrown when the `progress` callback returns `false`: the caller cancelled the stage. An
/// Algorithm_failure (reason "cancelled by the progress callback"), so that code catching those
/// sees it; the stages never take it for a failure of their own to recover from.
class Cancelled : public Algorithm_failure {
 public:
  /// what() is `stage + ": cancelled by the progress callback"`.
  explicit Cancelled(std::string stage) : Algorithm_failure(std::move(stage), "cancelled by the progress callback") {}
};

}  // namespace meshfit

#endif  // MESHFIT_EXCEPTIONS_H
