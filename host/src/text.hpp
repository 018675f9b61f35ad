// Small text helpers shared by the parsers (parameter lists, table files, view labels).
#pragma once

#include <string>
#include <vector>

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

}  // namespace brdfbake::detail
