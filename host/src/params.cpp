// Typed parameters: checking values against their definitions, and reading command-line text.
#include "brdfbake/params.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>

#include "brdfbake/error.hpp"
#include "text.hpp"

namespace brdfbake {

namespace {

// A number as the user wrote it where possible: integers in full (2147483647, not 2.14748365e+09).
std::string num(double v) {
  char buf[64];
  if (std::isfinite(v) && std::floor(v) == v && std::fabs(v) < 1e15)
    std::snprintf(buf, sizeof buf, "%.0f", v);
  else
    std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

using detail::join;

// At most `n` characters of a user's text, for messages: hostile input may be megabytes long.
std::string clip(const std::string& s, size_t n = 60) { return s.size() <= n ? s : s.substr(0, n) + "..."; }

std::string bounds(const ParamDef& d) {
  const bool lo = std::isfinite(d.lo), hi = std::isfinite(d.hi);
  if (lo && hi) {
    if (d.lo_open) return "greater than " + num(d.lo) + " and at most " + num(d.hi);
    return "in " + num(d.lo) + ".." + num(d.hi);
  }
  if (lo) return (d.lo_open ? "greater than " : "at least ") + num(d.lo);
  if (hi) return "at most " + num(d.hi);
  return "";
}

bool in_bounds(const ParamDef& d, double x) {
  if (!std::isfinite(x)) return false;
  if (d.lo_open ? !(x > d.lo) : !(x >= d.lo)) return false;
  return x <= d.hi;
}

// A number written as the user wrote it: strtod's whole text, finite or not (range is checked later).
bool parse_number(const std::string& text, double* out) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text.front()))) return false;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (*end != '\0') return false;
  *out = v;  // an overflow gives +-HUGE_VAL: refused as not finite by the range check
  return true;
}

using detail::split;  // text.hpp

}  // namespace

std::string ParamDef::cli_name() const {
  std::string s = name;
  std::replace(s.begin(), s.end(), '_', '-');
  return s;
}

const ParamDef* find_param_def(const std::vector<ParamDef>& schema, const std::string& name) {
  for (const auto& d : schema)
    if (d.name == name) return &d;
  return nullptr;
}

const ParamDef* find_param_def_or_alias(const std::vector<ParamDef>& schema, const std::string& name) {
  if (const ParamDef* d = find_param_def(schema, name)) return d;
  for (const auto& d : schema)
    if (std::find(d.aliases.begin(), d.aliases.end(), name) != d.aliases.end()) return &d;
  return nullptr;
}

std::string spelled_name(const std::string& name, bool cli) {
  if (!cli) return name;
  std::string s = name;
  std::replace(s.begin(), s.end(), '_', '-');
  return "--" + s;
}

void canonicalize_params(Params& params, const std::vector<ParamDef>& schema, const std::string& prefix, bool cli) {
  const auto is_alias = [](const ParamDef& d, const std::string& n) {
    return std::find(d.aliases.begin(), d.aliases.end(), n) != d.aliases.end();
  };
  for (const ParamDef& d : schema) {
    if (d.aliases.empty()) continue;
    std::vector<std::string> given;  // the spellings of `d` given, each once (one given twice is the caller's)
    for (const Param& p : params)
      if ((p.name == d.name || is_alias(d, p.name)) && std::find(given.begin(), given.end(), p.name) == given.end())
        given.push_back(p.name);
    if (given.size() > 1) {
      const bool canonical = std::find(given.begin(), given.end(), d.name) != given.end();
      const std::string alias = *std::find_if(given.begin(), given.end(), [&](const auto& g) { return g != d.name; });
      throw Error(prefix + spelled_name(d.name, cli) +
                  (canonical
                       ? ": given together with its alias " + spelled_name(alias, cli)
                       : ": given as both " + spelled_name(given[0], cli) + " and " + spelled_name(given[1], cli)) +
                  " (the same option): give one");
    }
    for (Param& p : params)
      if (is_alias(d, p.name)) p.name = d.name;
  }
}

std::string param_value_text(const ParamValue& v) {
  if (auto b = std::get_if<bool>(&v)) return *b ? "true" : "false";
  if (auto d = std::get_if<double>(&v)) return num(*d);
  if (auto s = std::get_if<std::string>(&v)) return "'" + clip(*s) + "'";
  std::string s = "[";
  const auto& a = std::get<std::vector<double>>(v);
  for (size_t i = 0; i < a.size() && i < 8; ++i) s += (i ? ", " : "") + num(a[i]);
  if (a.size() > 8) s += ", ...";
  return s + "]";
}

std::string param_expectation(const ParamDef& d) {
  const std::string b = bounds(d);
  switch (d.type) {
    case ParamType::Int:
      return "an integer" + (b.empty() ? "" : " " + b);
    case ParamType::Number:
      return "a number" + (b.empty() ? "" : " " + b);
    case ParamType::Name:
      return d.choices.empty() ? "a name" : "one of " + join(d.choices);
    case ParamType::Path:
      return "a file path";
    case ParamType::Flag:
      return "true or false";
    case ParamType::Color:
      return "a number or three numbers r,g,b" + (b.empty() ? "" : ", each " + b);
    case ParamType::Range:
      return "two numbers lo,hi with lo <= hi" + (b.empty() ? "" : ", each " + b);
    case ParamType::IntList:
      return "1 to " + std::to_string(d.max_items) + " integers" + (b.empty() ? "" : ", each " + b);
  }
  return "";
}

void check_param(const ParamDef& d, const ParamValue& v, const std::string& field) {
  auto fail = [&]() {
    throw Error(field + ": must be " + param_expectation(d) + " (got " + param_value_text(v) + ")");
  };
  switch (d.type) {
    case ParamType::Int: {
      const double* x = std::get_if<double>(&v);
      if (!x || !in_bounds(d, *x) || std::floor(*x) != *x) fail();
      break;
    }
    case ParamType::Number: {
      const double* x = std::get_if<double>(&v);
      if (!x || !in_bounds(d, *x)) fail();
      break;
    }
    case ParamType::Name: {
      const std::string* s = std::get_if<std::string>(&v);
      if (!s) fail();
      if (!d.choices.empty() && std::find(d.choices.begin(), d.choices.end(), *s) == d.choices.end()) fail();
      break;
    }
    case ParamType::Path: {
      const std::string* s = std::get_if<std::string>(&v);
      if (!s || s->empty() || s->find('\0') != std::string::npos) fail();
      break;
    }
    case ParamType::Flag:
      if (!std::holds_alternative<bool>(v)) fail();
      break;
    case ParamType::Color: {
      if (const double* x = std::get_if<double>(&v)) {
        if (!in_bounds(d, *x)) fail();
      } else if (const auto* a = std::get_if<std::vector<double>>(&v)) {
        if (a->size() != 3) fail();
        for (double c : *a)
          if (!in_bounds(d, c)) fail();
      } else {
        fail();
      }
      break;
    }
    case ParamType::Range: {
      const auto* a = std::get_if<std::vector<double>>(&v);
      if (!a || a->size() != 2 || !in_bounds(d, (*a)[0]) || !in_bounds(d, (*a)[1]) || (*a)[0] > (*a)[1]) fail();
      break;
    }
    case ParamType::IntList: {
      const auto* a = std::get_if<std::vector<double>>(&v);
      const double* x = std::get_if<double>(&v);
      if (x) {
        if (!in_bounds(d, *x) || std::floor(*x) != *x) fail();
        break;
      }
      if (!a || a->empty() || a->size() > static_cast<size_t>(d.max_items)) fail();
      for (double c : *a)
        if (!in_bounds(d, c) || std::floor(c) != c) fail();
      break;
    }
  }
}

ParamValue parse_param_text(const ParamDef& d, const std::string& text, const std::string& field) {
  auto fail = [&]() -> ParamValue {
    throw Error(field + ": must be " + param_expectation(d) + " (got '" + clip(text) + "')");
  };
  switch (d.type) {
    case ParamType::Int:
    case ParamType::Number: {
      double x = 0;
      if (!parse_number(text, &x)) return fail();
      return x;
    }
    case ParamType::Name:
    case ParamType::Path:
      return text;
    case ParamType::Flag:
      if (text == "true" || text == "1" || text == "yes" || text == "on") return true;
      if (text == "false" || text == "0" || text == "no" || text == "off") return false;
      return fail();
    case ParamType::Color:
    case ParamType::Range:
    case ParamType::IntList: {
      const std::vector<std::string> parts = split(text, ',');
      std::vector<double> values;
      for (const auto& p : parts) {
        double x = 0;
        if (!parse_number(p, &x)) return fail();
        values.push_back(x);
      }
      if (d.type == ParamType::Color) {
        if (values.size() == 1) return values[0];
        if (values.size() != 3) return fail();
      }
      if (d.type == ParamType::Range && values.size() != 2) return fail();
      if (d.type == ParamType::IntList && values.size() == 1) return values[0];
      return values;
    }
  }
  return fail();
}

}  // namespace brdfbake
