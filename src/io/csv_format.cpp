// SPDX-License-Identifier: MIT
#include "io/csv_format.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace slidebeam::io {

std::string python_repr(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::scientific);
  // buf: [-]d[.ddd]e(+|-)XX
  const char* p = buf;
  std::string out;
  if (*p == '-') {
    out += '-';
    ++p;
  }
  std::string digits;
  for (; *p != 'e'; ++p)
    if (*p != '.') digits += *p;
  *res.ptr = 0;
  const int exponent = std::atoi(p + 1);
  const int decpt = exponent + 1;  // digits d1 d2 ... with the point after decpt of them
  const int n = static_cast<int>(digits.size());
  if (decpt > -4 && decpt <= 16) {
    if (decpt <= 0)
      out += "0." + std::string(static_cast<size_t>(-decpt), '0') + digits;
    else if (decpt >= n)
      out += digits + std::string(static_cast<size_t>(decpt - n), '0') + ".0";
    else
      out += digits.substr(0, static_cast<size_t>(decpt)) + "." + digits.substr(static_cast<size_t>(decpt));
    return out;
  }
  out += digits[0];
  if (n > 1) out += "." + digits.substr(1);
  const int e = std::abs(exponent);
  out += exponent < 0 ? "e-" : "e+";
  if (e < 10) out += '0';
  out += std::to_string(e);
  return out;
}

namespace {
void put_text(std::string& out, const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) {
    out += s;
    return;
  }
  out += '"';
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
}
}  // namespace

std::string csv_rows(const double* values, std::size_t rows, const std::string& kinds,
                     const std::vector<std::string>& text) {
  const std::size_t cols = kinds.size();
  if (kinds.find('s') != std::string::npos && text.size() != rows)
    throw std::invalid_argument("csv_rows: one text entry per row needed");
  std::string out;
  out.reserve(rows * cols * 20);
  char buf[32];
  for (std::size_t i = 0; i < rows; ++i) {
    for (std::size_t j = 0; j < cols; ++j) {
      if (j) out += ',';
      const double v = values[i * cols + j];
      switch (kinds[j]) {
        case 'f':
          out += python_repr(v);
          break;
        case 'i': {
          const auto res = std::to_chars(buf, buf + sizeof buf, static_cast<long long>(v));
          out.append(buf, res.ptr);
          break;
        }
        case 's':
          put_text(out, text[i]);
          break;
        default:
          throw std::invalid_argument(std::string("csv_rows: unknown column kind '") + kinds[j] + "'");
      }
    }
    out += "\r\n";
  }
  return out;
}

}  // namespace slidebeam::io
