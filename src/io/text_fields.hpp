// Text-level helpers for the `.unjam` format: splitting a line into fields, exact number
// parsing and printing, and the escaping of free text. Internal to src/io.
#pragma once

#include <array>
#include <cstdint>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <string_view>

namespace unjam::io_internal {

// A problem with one field. The parser knows the line and turns it into an InputError; the
// helpers below therefore never need the file name or the line number.
class FieldError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The whitespace-separated fields of one line, with any `#` comment removed. Only the first
// kMaxFields are kept (no line of the format has more) but all are counted, so that a line
// with a million fields costs no memory and is still reported with its true field count.
struct Fields {
  static constexpr int kMaxFields = 12;
  std::array<std::string_view, kMaxFields> items;
  long long count = 0;

  bool empty() const { return count == 0; }
  std::string_view operator[](int k) const { return items[k]; }
};

bool IsFieldSeparator(char c);
Fields SplitFields(std::string_view line);

// A token for an error message: quoted, at most a few dozen characters, with control and
// non-ASCII bytes escaped so that binary garbage cannot mangle a terminal or a log.
std::string Quote(std::string_view token);

// Finite doubles only: "nan", "inf" and values beyond the double range are rejected, and
// the whole token must be consumed ("1.0abc" is an error). A single leading '+' is allowed.
double ParseDouble(std::string_view token, std::string_view what);
// A decimal integer in [min, max], the whole token consumed.
long long ParseInteger(std::string_view token, std::string_view what, long long min, long long max);
std::uint64_t ParseUnsigned64(std::string_view token, std::string_view what);

// Appends the shortest decimal that reads back as exactly `value` (std::to_chars).
void AppendDouble(std::string& out, double value);
// Appends each value, preceded by a space, in the same shortest form.
void AppendDoubles(std::string& out, std::initializer_list<double> values);
// Formats a double for a message (same shortest form).
std::string DoubleToString(double value);

// Free text on one line: backslash, control characters and DEL are escaped (\\ \n \r \t
// \xHH); every other byte, including UTF-8, is kept as is.
std::string EscapeText(std::string_view text);
std::string UnescapeText(std::string_view text);

}  // namespace unjam::io_internal
