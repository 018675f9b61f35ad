// The one-table commands: one per family, named and described by the registry. Their options come
// from the kinds' schemas (fresnel, which has modes of its own, is dispatched to cmd_fresnel.cpp).
#include "cli_table.hpp"

namespace brdfbake::cli {

// One per family, from the registry (brdfbake::table_commands()); fresnel's modes are cmd_fresnel's.
const TableCommand* table_command(const std::string& name) {
  static const std::vector<TableCommand> commands = [] {
    std::vector<TableCommand> v;
    for (const TableCommandText& c : table_commands()) v.push_back({c.name, c.description, c.example, {}, {}, {}});
    return v;
  }();
  for (const auto& c : commands)
    if (c.name == name) return &c;
  return nullptr;
}

}  // namespace brdfbake::cli
