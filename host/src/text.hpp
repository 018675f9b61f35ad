// Small text helpers shared by the parsers, messages and metadata: split, join and numbers as text.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "brdfbake/tables.hpp"

namespace brdfbake::detail {

// The fields of `text` between `sep` characters, empty ones included ("a,,b" -> a, "", b; "" -> "").
inline std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> out;
  size_t start = 0;
  for (;;) {
    const size_t at = text.find(sep, start);
    out.push_back(text.substr(start, at == std::string::npos ? std::string::npos : at - start));
    if (at == std::string::npos) break;
    start = at + 1;
  }
  return out;
}

// The items with `sep` between them ("a, b, c").
inline std::string join(const std::vector<std::string>& items, const std::string& sep = ", ") {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) out += (i ? sep : std::string()) + items[i];
  return out;
}

// `v` through one printf conversion of a double: "%.9g" (the default) is enough digits for a float to
// be read back exactly; messages use fewer ("%.3g"), never more than fit 64 characters.
inline std::string fmt_number(double v, const char* printf_format = "%.9g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, printf_format, v);
  return buf;
}

// A fraction as a percentage people read: "114%", "3.9%", "0.45%" (never "1.1e+02%"): whole percents
// from 10 %, one decimal from 1 %, two below; the page and the sheets print the same.
inline std::string percent_text(double fraction) {
  char b[32];
  if (fraction >= 0.0995)
    std::snprintf(b, sizeof b, "%.0f%%", 100.0 * fraction);
  else if (fraction >= 0.00995)
    std::snprintf(b, sizeof b, "%.1f%%", 100.0 * fraction);
  else
    std::snprintf(b, sizeof b, "%.2f%%", 100.0 * fraction);
  return b;
}

// A bound as text, rounded up to three significant digits: the recorded text is never below it
// (error_bound_text, brdfbake/tables.hpp, the same for the library's users). Every file, manifest
// and key that records a bound uses it (delivery, io's ASTC keys, the engines' metadata).
inline std::string bound_text(double v) { return error_bound_text(v); }
// Each of `bounds` as bound_text, separated by spaces (per-level metadata).
inline std::string bounds_text(const std::vector<double>& bounds) {
  std::vector<std::string> items;
  for (double b : bounds) items.push_back(error_bound_text(b));
  return join(items, " ");
}

}  // namespace brdfbake::detail
