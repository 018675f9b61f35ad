// The names of an enum's values, in one table per enum: the name of a value, the value of a name
// (with the one error message every option uses), and the list a schema's one_of offers. Each family
// keeps its tables beside its model, so the schema, the parser and the metadata read the same list.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "brdfbake/error.hpp"

namespace brdfbake::detail {

template <class E>
struct EnumName {
  E value;
  const char* name;
};

// "a", "a or b", "a, b or c".
template <class E, size_t N>
std::string enum_alternatives(const EnumName<E> (&table)[N]) {
  std::string out;
  for (size_t i = 0; i < N; ++i) out += (i == 0 ? "" : i + 1 == N ? " or " : ", ") + std::string(table[i].name);
  return out;
}

// The value named `name`; an unknown name throws "unknown WHAT 'NAME' (expected a, b or c)".
template <class E, size_t N>
E enum_from_name(const EnumName<E> (&table)[N], const std::string& name, const char* what) {
  for (const EnumName<E>& entry : table)
    if (name == entry.name) return entry.value;
  throw Error("unknown " + std::string(what) + " '" + name.substr(0, 60) + "' (expected " + enum_alternatives(table) +
              ")");
}

// The name of `value` ("?" for a value the table lacks, which a test of each table rules out).
template <class E, size_t N>
const char* enum_name(const EnumName<E> (&table)[N], E value) {
  for (const EnumName<E>& entry : table)
    if (entry.value == value) return entry.name;
  return "?";
}

// Every name, in the table's order (a schema's one_of).
template <class E, size_t N>
std::vector<std::string> enum_names(const EnumName<E> (&table)[N]) {
  std::vector<std::string> out;
  for (const EnumName<E>& entry : table) out.emplace_back(entry.name);
  return out;
}

}  // namespace brdfbake::detail
