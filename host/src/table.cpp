#include "brdfbake/table.hpp"

#include <algorithm>

namespace brdfbake {

void Table::set_meta(const std::string& key, const std::string& value) {
  auto it = std::find_if(metadata.begin(), metadata.end(), [&](const auto& entry) { return entry.first == key; });
  if (it != metadata.end()) {
    it->second = value;
  } else {
    metadata.emplace_back(key, value);
  }
}

std::string Table::meta(const std::string& key) const {
  auto it = std::find_if(metadata.begin(), metadata.end(), [&](const auto& entry) { return entry.first == key; });
  return it != metadata.end() ? it->second : std::string();
}

}  // namespace brdfbake
