#pragma once
// Private to core/src/exchange: number text for the exchange formats. std::to_chars, not
// printf: a Qt host (MeshLab, FreeCAD) may have set a decimal-comma locale, and the target
// tools read '.' only.
#include <charconv>
#include <string>

namespace thermodec::exchange_text {

// Shortest text that reads back to the same double.
inline std::string real(double x) {
  char buf[40];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

// A real as Fortran-family input languages (ESATAN, SINDA) want it: never an integer literal
// ("6000.0", not "6000"), upper-case exponent.
inline std::string fortran_real(double x) {
  std::string s = real(x);
  for (char& c : s)
    if (c == 'e') c = 'E';
  if (s.find_first_of(".En") == std::string::npos) {  // n: "nan"/"inf" are refused upstream
    const std::size_t e = s.find('E');
    s.insert(e == std::string::npos ? s.size() : e, ".0");
  }
  return s;
}

// A NASTRAN real of at most `width` characters, always with a decimal point ("1." not "1"),
// upper-case exponent, as many significant digits as fit.
inline std::string nastran_real(double x, int width) {
  for (int p = 17; p >= 1; --p) {
    char buf[48];
    const auto r = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, p);
    std::string s(buf, r.ptr);
    for (char& c : s)
      if (c == 'e') c = 'E';
    if (s.find('.') == std::string::npos) {
      const std::size_t e = s.find('E');
      s.insert(e == std::string::npos ? s.size() : e, ".");
    }
    if (static_cast<int>(s.size()) <= width) return s;
  }
  return "0.";
}

}  // namespace thermodec::exchange_text
