#include "text_fields.hpp"

#include <charconv>
#include <cmath>
#include <system_error>

namespace unjam::io_internal {

namespace {

constexpr std::size_t kMaxQuotedBytes = 40;

std::string Message(std::string_view what, std::string_view problem, std::string_view token) {
  std::string message(what);
  message += ": ";
  message += problem;
  message += ' ';
  message += Quote(token);
  return message;
}

char HexDigit(int v) { return "0123456789abcdef"[v & 15]; }

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

bool IsFieldSeparator(char c) { return c == ' ' || c == '\t'; }

Fields SplitFields(std::string_view line) {
  if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) {
    line = line.substr(0, hash);
  }
  Fields fields;
  std::size_t pos = 0;
  while (pos < line.size()) {
    while (pos < line.size() && IsFieldSeparator(line[pos])) ++pos;
    if (pos == line.size()) break;
    std::size_t end = pos;
    while (end < line.size() && !IsFieldSeparator(line[end])) ++end;
    if (fields.count < Fields::kMaxFields) fields.items[fields.count] = line.substr(pos, end - pos);
    ++fields.count;
    pos = end;
  }
  return fields;
}

std::string Quote(std::string_view token) {
  std::string out = "'";
  for (std::size_t k = 0; k < token.size() && k < kMaxQuotedBytes; ++k) {
    const unsigned char c = static_cast<unsigned char>(token[k]);
    if (c >= 0x20 && c < 0x7f && c != '\\' && c != '\'') {
      out += static_cast<char>(c);
    } else {
      out += "\\x";
      out += HexDigit(c >> 4);
      out += HexDigit(c);
    }
  }
  if (token.size() > kMaxQuotedBytes) out += "...";
  out += '\'';
  return out;
}

double ParseDouble(std::string_view token, std::string_view what) {
  std::string_view digits = token;
  // from_chars rejects '+', but people write it; allow exactly one, before a digit or '.'.
  if (!digits.empty() && digits.front() == '+') {
    digits.remove_prefix(1);
    if (digits.empty() ||
        !(digits.front() == '.' || (digits.front() >= '0' && digits.front() <= '9'))) {
      throw FieldError(Message(what, "malformed number", token));
    }
  }
  const std::string_view body =
      !digits.empty() && digits.front() == '-' ? digits.substr(1) : digits;
  // from_chars accepts "nan", "inf" and "infinity"; a scene never holds them.
  if (!body.empty() &&
      (body.front() == 'n' || body.front() == 'N' || body.front() == 'i' || body.front() == 'I')) {
    throw FieldError(Message(what, "NaN or infinity is not allowed, got", token));
  }
  double value = 0.0;
  const char* end = digits.data() + digits.size();
  const auto [ptr, ec] = std::from_chars(digits.data(), end, value);
  if (ec == std::errc::result_out_of_range) {
    throw FieldError(Message(what, "number outside the range of a double", token));
  }
  if (ec != std::errc() || ptr != end) throw FieldError(Message(what, "malformed number", token));
  if (!std::isfinite(value))
    throw FieldError(Message(what, "NaN or infinity is not allowed, got", token));
  return value;
}

long long ParseInteger(std::string_view token, std::string_view what, long long min,
                       long long max) {
  long long value = 0;
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (ec == std::errc() && ptr == end && value >= min && value <= max) return value;
  std::string problem =
      "expected an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "], got";
  throw FieldError(Message(what, problem, token));
}

std::uint64_t ParseUnsigned64(std::string_view token, std::string_view what) {
  std::uint64_t value = 0;
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (ec == std::errc() && ptr == end) return value;
  throw FieldError(Message(what, "expected an unsigned 64-bit integer, got", token));
}

void AppendDouble(std::string& out, double value) {
  // 32 bytes hold any shortest double ("-2.2250738585072014e-308" is 24).
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

void AppendDoubles(std::string& out, std::initializer_list<double> values) {
  for (const double v : values) {
    out += ' ';
    AppendDouble(out, v);
  }
}

std::string DoubleToString(double value) {
  std::string out;
  AppendDouble(out, value);
  return out;
}

std::string EscapeText(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c == '\\') {
      out += "\\\\";
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c < 0x20 || c == 0x7f) {
      out += "\\x";
      out += HexDigit(c >> 4);
      out += HexDigit(c);
    } else {
      out += ch;
    }
  }
  return out;
}

std::string UnescapeText(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t k = 0; k < text.size(); ++k) {
    if (text[k] != '\\') {
      out += text[k];
      continue;
    }
    const char next = k + 1 < text.size() ? text[k + 1] : '\0';
    if (next == '\\' || next == 'n' || next == 'r' || next == 't') {
      out += next == 'n' ? '\n' : next == 'r' ? '\r' : next == 't' ? '\t' : '\\';
      ++k;
      continue;
    }
    const int high = next == 'x' && k + 2 < text.size() ? HexValue(text[k + 2]) : -1;
    const int low = high >= 0 && k + 3 < text.size() ? HexValue(text[k + 3]) : -1;
    if (low < 0)
      throw FieldError(Message("provenance", "bad escape sequence at", text.substr(k, 4)));
    out += static_cast<char>(high * 16 + low);
    k += 3;
  }
  return out;
}

}  // namespace unjam::io_internal
