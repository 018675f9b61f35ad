// Internal: a problem with one field of a request, as families and delivery report it; the registry
// names the field as the front end spells it (validate_table).
#pragma once

#include <functional>
#include <string>

#include "brdfbake/error.hpp"

namespace brdfbake::detail {

// A problem with one field: the registry prefixes the field as the front end spells it.
class FieldError : public Error {
 public:
  FieldError(std::string field, const std::string& message) : Error(message), field_(std::move(field)) {}
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

// Names another field inside a message, as the front end spells it ("base_ior" in a job,
// "--base-ior" on the command line).
using FieldName = std::function<std::string(const std::string& field)>;

}  // namespace brdfbake::detail
