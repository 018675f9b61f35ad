// Internal: a family's parameters bound to the fields of its spec struct, written once. Each entry is
// the ParamDef the front ends see (job field, option, help, Python keyword) and how its validated
// value fills the spec; a spec field that no parameter sets is listed too, with the reason. So the
// schema itself fills the spec (SpecSchema::fill), and a field added to a spec without an entry
// fails Registry.EverySpecFieldHasASchemaEntry (tests/host/test_registry.cpp), which counts the
// struct's fields against Family::spec_fields.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "brdfbake/params.hpp"
#include "brdfbake/tables.hpp"
#include "families/family.hpp"

namespace brdfbake::detail {

// The value of a validated parameter as a field's type: numbers (int fields truncate integral
// values), flags, text and colours; other types take a conversion (e.g. an enum from its name).
template <class T>
T param_as(const ParamValue& v) {
  if constexpr (std::is_same_v<T, bool>) {
    return std::get<bool>(v);
  } else if constexpr (std::is_arithmetic_v<T>) {
    return static_cast<T>(std::get<double>(v));
  } else if constexpr (std::is_same_v<T, std::string>) {
    return std::get<std::string>(v);
  } else if constexpr (std::is_same_v<T, Rgb>) {
    return rgb_of(v);
  } else {
    static_assert(std::is_same_v<T, bool>, "no conversion from a parameter to this field's type: give one");
    return T{};
  }
}

// A conversion for SpecSchema::bind: a Name parameter's value through `from_name` (an enum).
template <class E>
std::function<E(const ParamValue&)> by_name(E (*from_name)(const std::string&)) {
  return [from_name](const ParamValue& v) { return from_name(std::get<std::string>(v)); };
}

template <class Spec>
class SpecSchema {
 public:
  // Sets the spec from the whole validated request (fields whose value depends on several).
  using Fill = std::function<void(Spec&, const TableRequest&)>;

  // A parameter that sets `member` to its value, when the request has one.
  template <class T>
  SpecSchema& bind(T Spec::*member, const char* field, ParamDef def) {
    return bind(member, field, std::move(def), [](const ParamValue& v) { return value_for<T>(v); });
  }
  // The same through `convert(const ParamValue&)`, e.g. an enum from its name.
  template <class T, class Convert>
  SpecSchema& bind(T Spec::*member, const char* field, ParamDef def, Convert convert) {
    const std::string name = def.name;
    return bind(field, std::move(def), [member, name, convert](Spec& s, const TableRequest& t) {
      if (const ParamValue* v = t.find(name)) s.*member = convert(*v);
    });
  }
  // A parameter whose field takes more than its value (fill reads the request; an empty fill: the
  // family sets the field itself, from rules across fields).
  SpecSchema& bind(const char* field, ParamDef def, Fill fill) {
    fields_.push_back({field, def.name, ""});
    fills_.push_back(std::move(fill));
    schema_.push_back(std::move(def));
    return *this;
  }
  // A field set by one of the fields every table has ("precision") or by the kind.
  SpecSchema& common(const char* field, const char* table_field, Fill fill) {
    fields_.push_back({field, table_field, ""});
    fills_.push_back(std::move(fill));
    return *this;
  }
  // A field no parameter sets, and why.
  SpecSchema& internal(const char* field, const char* reason) {
    fields_.push_back({field, "", reason});
    return *this;
  }
  // Parameters no spec field holds (how the result is written, what the family alone reads).
  SpecSchema& param(ParamDef def) {
    schema_.push_back(std::move(def));
    return *this;
  }
  SpecSchema& params(const std::vector<ParamDef>& defs) {
    schema_.insert(schema_.end(), defs.begin(), defs.end());
    return *this;
  }

  const std::vector<ParamDef>& schema() const { return schema_; }
  const std::vector<SpecField>& fields() const { return fields_; }

  // The spec of a validated request: the struct's own defaults, each field set by its entry.
  Spec fill(const TableRequest& t) const {
    Spec s;
    for (const Fill& f : fills_)
      if (f) f(s, t);
    return s;
  }

 private:
  template <class T>
  static T value_for(const ParamValue& v) {
    if constexpr (is_optional<T>::value)
      return param_as<typename T::value_type>(v);
    else
      return param_as<T>(v);
  }
  template <class T>
  struct is_optional : std::false_type {};
  template <class T>
  struct is_optional<std::optional<T>> : std::true_type {};

  std::vector<ParamDef> schema_;
  std::vector<SpecField> fields_;
  std::vector<Fill> fills_;
};

}  // namespace brdfbake::detail
