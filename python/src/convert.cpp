#include "convert.hpp"

#include <cmath>

namespace brdfbake::python {

namespace {

std::string excerpt(const py::handle& v) {
  std::string s = py::repr(v).cast<std::string>();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

bool is_number(const py::handle& v) {
  return !py::isinstance<py::bool_>(v) && (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v));
}

double number_of(const py::handle& v, const std::string& field) {
  // Integers beyond a double's range: the range check would see inf; say what it is instead.
  try {
    return v.cast<double>();
  } catch (const py::cast_error&) {
    throw Error(field + ": " + excerpt(v) + " is not representable as a number");
  }
}

std::string common_text(const py::dict& common, const char* key) {
  if (!common.contains(key)) return {};
  const py::object v = common[key];
  if (v.is_none()) return {};
  if (!py::isinstance<py::str>(v)) throw Error(std::string(key) + ": must be a string (got " + excerpt(v) + ")");
  return v.cast<std::string>();
}

}  // namespace

ParamValue to_param(const py::handle& v, const std::string& field) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
  if (is_number(v)) return number_of(v, field);
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    std::vector<double> out;
    for (const py::handle e : v) {
      if (!is_number(e)) throw Error(field + ": must be a number or a list of numbers (got " + excerpt(v) + ")");
      out.push_back(number_of(e, field));
    }
    return out;
  }
  throw Error(field + ": must be a number, a string, a boolean or a list of numbers (got " + excerpt(v) + ")");
}

py::object from_param(const ParamValue& v, const ParamDef* d) {
  const bool integral = d && (d->type == ParamType::Int || d->type == ParamType::IntList);
  if (const bool* b = std::get_if<bool>(&v)) return py::bool_(*b);
  if (const double* x = std::get_if<double>(&v)) {
    if (integral && std::isfinite(*x)) return py::int_(static_cast<long long>(*x));
    return py::float_(*x);
  }
  if (const std::string* s = std::get_if<std::string>(&v)) return py::str(*s);
  py::list out;
  for (double x : std::get<std::vector<double>>(v)) {
    if (integral && std::isfinite(x))
      out.append(py::int_(static_cast<long long>(x)));
    else
      out.append(py::float_(x));
  }
  return std::move(out);
}

py::dict params_dict(const Params& params, TableKind kind) {
  py::dict out;
  const auto& schema = table_schema(kind);
  for (const Param& p : params) out[py::str(p.name)] = from_param(p.value, find_param_def(schema, p.name));
  return out;
}

py::dict metadata_dict(const Metadata& metadata) {
  py::dict out;
  for (const auto& [k, v] : metadata) out[py::str(k)] = py::str(v);
  return out;
}

TableRequest make_request(const std::string& kind, const py::list& params, const py::dict& common,
                          const std::string& prefix) {
  TableRequest t;
  t.kind = table_kind_from_name(kind);
  const FieldNaming naming{prefix, false};
  for (const py::handle item : params) {
    const auto pair = item.cast<py::tuple>();
    const std::string name = pair[0].cast<std::string>();
    t.params.push_back({name, to_param(pair[1], naming.field(t.kind, name))});
  }
  if (const std::string p = common_text(common, "precision"); !p.empty()) {
    try {
      t.precision = precision_from_name(p);
    } catch (const Error& e) {
      throw Error(naming.field(t.kind, "precision") + ": " + e.what());
    }
  }
  t.device = common_text(common, "device");
  t.environment = common_text(common, "environment");
  t.output = common_text(common, "output");
  t.format = common_text(common, "format");
  t.pixel = common_text(common, "pixel");
  validate_table(t, naming);
  return t;
}

py::dict request_dict(const TableRequest& t) {
  py::dict d;
  d["kind"] = table_kind_name(t.kind);
  d["parameters"] = params_dict(t.params, t.kind);
  d["precision"] = precision_name(t.precision);
  d["device"] = t.device;
  if (table_kind_uses_environment(t.kind)) d["environment"] = t.environment;
  d["output"] = t.output;
  d["format"] = t.format;
  d["pixel"] = t.pixel;
  return d;
}

}  // namespace brdfbake::python
