#pragma once
// Numbers as text for tables and CSVs: printf's %.*E and %.*f.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace pb4u {

// v in scientific notation with `digits` after the point: scientific(1234.5, 2) = "1.23E+03".
inline std::string scientific(double v, int digits) {
  char s[40];
  std::snprintf(s, sizeof s, "%.*E", digits, v);
  return s;
}

// v with `digits` significant digits (printf's %.*g), and `non_finite` for NaN and infinities:
// significant(1234.5678, 6, "nan") = "1234.57".
inline std::string significant(double v, int digits, const char* non_finite) {
  if (!std::isfinite(v)) return non_finite;
  char s[40];
  std::snprintf(s, sizeof s, "%.*g", digits, v);
  return s;
}

// v rounded to `digits` significant digits: what %.*g prints, read back (NaN and infinities
// unchanged). A figure put into JSON this way keeps the digits the tables show.
inline double round_to_significant(double v, int digits) {
  if (!std::isfinite(v)) return v;
  char s[40];
  std::snprintf(s, sizeof s, "%.*g", digits, v);
  return std::strtod(s, nullptr);
}

// v with `digits` after the point: fixed(3.14159, 2) = "3.14".
inline std::string fixed(double v, int digits) {
  char s[40];
  std::snprintf(s, sizeof s, "%.*f", digits, v);
  return s;
}

}  // namespace pb4u
