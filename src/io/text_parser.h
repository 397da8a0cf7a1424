// Private helpers shared by the text readers: a whole-file buffer cut into significant lines and
// whitespace-separated tokens, and strict number parsing that names the line on failure.
#ifndef MESHFIT_SRC_TEXT_PARSER_H
#define MESHFIT_SRC_TEXT_PARSER_H

#include <meshfit/exceptions.h>

#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>
#include <string_view>
#include <vector>

namespace meshfit {
namespace internal {

/// Reads a whole stream into memory. A UTF-8 byte-order mark is kept (Line_reader skips it).
std::string read_all(std::istream& in, const std::string& file_name);
/// Reads a whole file; Invalid_input naming the file when it cannot be opened or read.
std::string read_file(const std::string& path);

/// Splits a buffer into lines (LF, CRLF or CR) and lines into tokens separated by blanks (space,
/// tab, CR, vertical tab, form feed). Lines that are blank, or whose first token starts with the
/// comment character, are skipped by next().
class Line_reader {
 public:
  /// `max_tokens` bounds how many tokens of a line tokens() holds (a reader of very long lines
  /// walks the rest with next_token, so that no line costs a token array of its own).
  Line_reader(std::string_view text, std::string file_name, char comment = '#',
              std::size_t max_tokens = static_cast<std::size_t>(-1));

  /// Advances to the next significant line; false at the end of the text.
  bool next();
  /// Advances to the next line even if blank (for formats where blank lines matter); false at end.
  bool next_raw();
  std::size_t line_number() const { return m_line; }
  std::string_view line() const { return m_current; }
  const std::vector<std::string_view>& tokens() const { return m_tokens; }
  const std::string& file_name() const { return m_file; }
  /// Byte offset just past the current line (where the next line starts).
  std::size_t offset() const { return m_pos; }

  [[noreturn]] void fail(const std::string& problem) const;
  Input_location here() const { return Input_location::at_line(m_file, m_line); }

  double to_double(std::string_view token, const char* what) const;
  /// A non-negative integer no larger than `max`.
  std::uint64_t to_unsigned(std::string_view token, const char* what,
                            std::uint64_t max = UINT64_MAX) const;
  std::int64_t to_signed(std::string_view token, const char* what) const;

 private:
  std::string_view m_text;
  std::string m_file;
  char m_comment;
  std::size_t m_pos = 0;
  std::size_t m_line = 0;
  std::string_view m_current;
  std::vector<std::string_view> m_tokens;
  std::size_t m_max_tokens;
};

bool is_blank(char c);
/// The tokens of `line`, at most `max` of them.
void split_tokens(std::string_view line, std::vector<std::string_view>& out,
                  std::size_t max = static_cast<std::size_t>(-1));
/// The token of `line` at or after `pos` (empty at the end of the line); `pos` moves past it.
std::string_view next_token(std::string_view line, std::size_t& pos);
/// How many tokens `line` has.
std::size_t count_tokens(std::string_view line);
/// Quotes a token for an error message, shortened and with non-printable bytes escaped.
std::string quote(std::string_view token);

/// Strict conversions; they return false instead of throwing so callers choose the message.
enum class Number_status { ok, malformed, out_of_range, not_finite };
Number_status parse_double(std::string_view token, double& value);
Number_status parse_unsigned(std::string_view token, std::uint64_t& value);
Number_status parse_signed(std::string_view token, std::int64_t& value);

}  // namespace internal
}  // namespace meshfit

#endif  // MESHFIT_SRC_TEXT_PARSER_H
