// SPDX-License-Identifier: MIT
#pragma once
/// @file Tables of numbers as CSV text, each float exactly as Python's repr writes it (the
/// shortest text that reads back to the same double): the run history written at the end of a
/// run, thousands of rows, without a Python call per number.

#include <string>
#include <vector>

namespace slidebeam::io {

/// `x` as Python's repr(float) writes it: shortest round trip, fixed notation for
/// 1e-4 <= |x| < 1e16, else d.ddde+XX; "nan", "inf", "-inf".
std::string python_repr(double x);

/// Rows of `values` (row-major, `kinds.size()` columns) as CSV lines ending in "\r\n" (as
/// Python's csv module writes them). kinds[j]: 'f' the float's repr, 'i' an integer, 's' the
/// row's entry of `text` (quoted where CSV needs it; the column's value is ignored).
std::string csv_rows(const double* values, std::size_t rows, const std::string& kinds,
                     const std::vector<std::string>& text);

}  // namespace slidebeam::io
