// SPDX-License-Identifier: MIT
#include "io/csv_format.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace slidebeam::io {

namespace {
/// Appends repr(x) to out (see python_repr).
void append_repr(std::string& out, double x) {
  if (std::isnan(x)) {
    out += "nan";
    return;
  }
  if (std::isinf(x)) {
    out += x > 0 ? "inf" : "-inf";
    return;
  }
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::scientific);
  // buf: [-]d[.ddd]e(+|-)XX
  const char* p = buf;
  if (*p == '-') {
    out += '-';
    ++p;
  }
  char digits[32];
  int n = 0;
  for (; *p != 'e'; ++p)
    if (*p != '.') digits[n++] = *p;
  int exponent = 0;
  std::from_chars(p + (p[1] == '+' ? 2 : 1), res.ptr, exponent);
  const int decpt = exponent + 1;  // digits d1 d2 ... with the point after decpt of them
  if (decpt > -4 && decpt <= 16) {
    if (decpt <= 0) {
      out += "0.";
      out.append(static_cast<size_t>(-decpt), '0');
      out.append(digits, static_cast<size_t>(n));
    } else if (decpt >= n) {
      out.append(digits, static_cast<size_t>(n));
      out.append(static_cast<size_t>(decpt - n), '0');
      out += ".0";
    } else {
      out.append(digits, static_cast<size_t>(decpt));
      out += '.';
      out.append(digits + decpt, static_cast<size_t>(n - decpt));
    }
    return;
  }
  out += digits[0];
  if (n > 1) {
    out += '.';
    out.append(digits + 1, static_cast<size_t>(n - 1));
  }
  const int e = std::abs(exponent);
  out += exponent < 0 ? "e-" : "e+";
  if (e < 10) out += '0';
  const auto r = std::to_chars(buf, buf + sizeof buf, e);
  out.append(buf, r.ptr);
}
}  // namespace

std::string python_repr(double x) {
  std::string out;
  append_repr(out, x);
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
          append_repr(out, v);
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
