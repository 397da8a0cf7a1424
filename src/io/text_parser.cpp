#include "text_parser.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

namespace meshfit {
namespace internal {

std::string read_all(std::istream& in, const std::string& file_name) {
  std::string text;
  try {
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  } catch (const std::ios_base::failure& e) {
    throw Invalid_input(Input_location{file_name, 0, Input_location::no_offset},
                        std::string("read error: ") + e.what());
  }
  if (in.bad()) throw Invalid_input(Input_location{file_name, 0, Input_location::no_offset},
                                    "read error");
  return text;
}

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw Invalid_input(Input_location{path, 0, Input_location::no_offset},
                        "not a regular file (a directory?)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Invalid_input(Input_location{path, 0, Input_location::no_offset},
                               "cannot open the file for reading");
  // One allocation of the file's size (read_all's growing string peaks at twice or three times it).
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || size == 0) return read_all(in, path);
  std::string text(static_cast<std::size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  if (in.gcount() != static_cast<std::streamsize>(size) || in.bad())
    throw Invalid_input(Input_location{path, 0, Input_location::no_offset}, "read error");
  return text;
}

bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

std::string_view next_token(std::string_view line, std::size_t& pos) {
  const std::size_t n = line.size();
  while (pos < n && is_blank(line[pos])) ++pos;
  const std::size_t start = pos;
  while (pos < n && !is_blank(line[pos])) ++pos;
  return line.substr(start, pos - start);
}

std::size_t count_tokens(std::string_view line) {
  std::size_t pos = 0, count = 0;
  while (!next_token(line, pos).empty()) ++count;
  return count;
}

void split_tokens(std::string_view line, std::vector<std::string_view>& out, std::size_t max) {
  out.clear();
  std::size_t pos = 0;
  while (out.size() < max) {
    const std::string_view t = next_token(line, pos);
    if (t.empty()) break;
    out.push_back(t);
  }
}

std::string quote(std::string_view token) {
  static const char hex[] = "0123456789abcdef";
  std::string s = "'";
  const std::size_t shown = token.size() > 40 ? 40 : token.size();
  for (std::size_t i = 0; i < shown; ++i) {
    const unsigned char c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      s += static_cast<char>(c);
    } else {
      s += "\\x";
      s += hex[c >> 4];
      s += hex[c & 15];
    }
  }
  if (shown < token.size()) s += "...";
  return s + "'";
}

Line_reader::Line_reader(std::string_view text, std::string file_name, char comment, std::size_t max_tokens)
    : m_text(text), m_file(std::move(file_name)), m_comment(comment), m_max_tokens(max_tokens) {
  if (m_text.substr(0, 3) == "\xEF\xBB\xBF") m_pos = 3;  // UTF-8 byte-order mark
}

bool Line_reader::next_raw() {
  if (m_pos >= m_text.size()) return false;
  std::size_t end = m_pos;
  while (end < m_text.size() && m_text[end] != '\n' && m_text[end] != '\r') ++end;
  m_current = m_text.substr(m_pos, end - m_pos);
  if (end < m_text.size()) {
    // CRLF is one line break; a lone CR is one too.
    if (m_text[end] == '\r' && end + 1 < m_text.size() && m_text[end + 1] == '\n') ++end;
    ++end;
  }
  m_pos = end;
  ++m_line;
  split_tokens(m_current, m_tokens, m_max_tokens);
  return true;
}

bool Line_reader::next() {
  while (next_raw()) {
    if (m_tokens.empty()) continue;
    if (m_comment != '\0' && m_tokens.front().front() == m_comment) continue;
    return true;
  }
  m_tokens.clear();
  m_current = std::string_view();
  return false;
}

void Line_reader::fail(const std::string& problem) const { throw Invalid_input(here(), problem); }

Number_status parse_double(std::string_view token, double& value) {
  if (token.empty()) return Number_status::malformed;
  std::string_view t = token;
  if (t.front() == '+') t.remove_prefix(1);
  if (t.empty() || t.front() == '+' || (t.size() < token.size() && t.front() == '-'))
    return Number_status::malformed;
  const auto res = std::from_chars(t.data(), t.data() + t.size(), value,
                                   std::chars_format::general);
  if (res.ptr != t.data() + t.size()) return Number_status::malformed;
  if (res.ec == std::errc::result_out_of_range) {
    // from_chars reports underflow (1e-400) like overflow; only overflow is an error.
    const std::string copy(t);
    const double v = std::strtod(copy.c_str(), nullptr);
    if (std::isinf(v)) return Number_status::out_of_range;
    value = v;
    return Number_status::ok;
  }
  if (res.ec != std::errc()) return Number_status::malformed;
  if (!std::isfinite(value)) return Number_status::not_finite;
  return Number_status::ok;
}

Number_status parse_unsigned(std::string_view token, std::uint64_t& value) {
  std::string_view t = token;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  if (t.empty() || t.front() < '0' || t.front() > '9') return Number_status::malformed;
  const auto res = std::from_chars(t.data(), t.data() + t.size(), value);
  if (res.ec == std::errc::result_out_of_range) return Number_status::out_of_range;
  if (res.ec != std::errc() || res.ptr != t.data() + t.size()) return Number_status::malformed;
  return Number_status::ok;
}

Number_status parse_signed(std::string_view token, std::int64_t& value) {
  std::string_view t = token;
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  if (t.empty() || (t.size() < token.size() && t.front() == '-')) return Number_status::malformed;
  const auto res = std::from_chars(t.data(), t.data() + t.size(), value);
  if (res.ec == std::errc::result_out_of_range) return Number_status::out_of_range;
  if (res.ec != std::errc() || res.ptr != t.data() + t.size()) return Number_status::malformed;
  return Number_status::ok;
}

double Line_reader::to_double(std::string_view token, const char* what) const {
  double v = 0;
  switch (parse_double(token, v)) {
    case Number_status::ok: return v;
    case Number_status::out_of_range:
      fail(std::string(what) + " " + quote(token) + " is out of the range of a double");
    case Number_status::not_finite:
      fail(std::string(what) + " " + quote(token) + " is not a finite number");
    case Number_status::malformed: break;
  }
  fail(std::string("expected a number for ") + what + ", found " + quote(token));
}

std::uint64_t Line_reader::to_unsigned(std::string_view token, const char* what,
                                       std::uint64_t max) const {
  std::uint64_t v = 0;
  const Number_status s = parse_unsigned(token, v);
  if (s == Number_status::malformed) {
    std::int64_t neg = 0;
    if (parse_signed(token, neg) == Number_status::ok && neg < 0)
      fail(std::string(what) + " " + quote(token) + " is negative");
    fail(std::string("expected a non-negative integer for ") + what + ", found " + quote(token));
  }
  if (s == Number_status::out_of_range || v > max)
    fail(std::string(what) + " " + quote(token) + " is too large (at most " +
         std::to_string(max) + ")");
  return v;
}

std::int64_t Line_reader::to_signed(std::string_view token, const char* what) const {
  std::int64_t v = 0;
  const Number_status s = parse_signed(token, v);
  if (s == Number_status::out_of_range) fail(std::string(what) + " " + quote(token) + " is too large");
  if (s != Number_status::ok) fail(std::string("expected an integer for ") + what + ", found " + quote(token));
  return v;
}

}  // namespace internal
}  // namespace meshfit
