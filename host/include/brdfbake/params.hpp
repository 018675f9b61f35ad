// Typed parameters: the schema every table family declares once (name, type, range, default, help)
// and the values a job, a command line or a binding gives for them. The job parser, the command-line
// options, their help and the Python functions are all generated from these schemas, so a parameter
// exists in one front end exactly when it exists in the others (model: pbrt-v4's typed parameter
// dictionaries, src/pbrt/paramdict.cpp).
#pragma once

#include <cmath>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace brdfbake {

// A parameter value: a flag, a number, a name (or path), or a list of numbers (an RGB triple, a
// range, a resolution).
using ParamValue = std::variant<bool, double, std::string, std::vector<double>>;
struct Param {
  std::string name;
  ParamValue value;
};
using Params = std::vector<Param>;  // in the schema's canonical order once validated

enum class ParamType {
  Int,      // an integral number in [lo, hi]
  Number,   // a finite number in [lo, hi] (lo_open: lo excluded)
  Name,     // one of `choices` (any text when choices is empty)
  Path,     // a file path (text; opened by the family)
  Flag,     // true or false
  Color,    // a number (grey) or [r, g, b], each in [lo, hi]
  Range,    // [lo, hi] with lo <= hi, each in the def's [lo, hi]
  IntList,  // 1 to `max_items` integers, each in [lo, hi]
};

struct ParamDef {
  std::string name;  // the job field, snake_case; the command-line option is --name with '-' for '_'
  ParamType type = ParamType::Number;
  double lo = -HUGE_VAL, hi = HUGE_VAL;
  std::vector<std::string> choices;    // Name: the accepted values
  std::optional<ParamValue> fallback;  // the default; none: absent unless given (see default_text)
  std::string help;                    // one line, for --help, docs and Python docstrings
  std::vector<std::string> aliases;    // other spellings also accepted, snake_case as `name`: old names kept
                                       // working (cube_size for chain_size) and shorter ones (sh for sh_order);
                                       // every front end accepts them, and writes only `name`
  std::string default_text;            // a default that depends on others, e.g. "size"
  bool lo_open = false;                // Number: lo itself is refused (e.g. max_error > 0)
  bool required = false;
  bool output_only = false;  // changes how the result is written, not what is baked
  int max_items = 3;         // IntList

  ParamDef() = default;
  ParamDef(std::string n, ParamType t, std::string h) : name(std::move(n)), type(t), help(std::move(h)) {}
  // Chained setters, so that a schema reads as a table: ParamDef("size", Int, "...").range(1, 64).def(16.0)
  ParamDef& range(double l, double h) {
    lo = l;
    hi = h;
    return *this;
  }
  ParamDef& above(double l, double h = HUGE_VAL) {
    lo = l;
    hi = h;
    lo_open = true;
    return *this;
  }
  ParamDef& one_of(std::vector<std::string> c) {
    choices = std::move(c);
    return *this;
  }
  ParamDef& def(ParamValue v) {
    fallback = std::move(v);
    return *this;
  }
  ParamDef& defaults_to(std::string text) {
    default_text = std::move(text);
    return *this;
  }
  ParamDef& alias(std::string a) {
    aliases.push_back(std::move(a));
    return *this;
  }
  ParamDef& needed() {
    required = true;
    return *this;
  }
  ParamDef& output() {
    output_only = true;
    return *this;
  }

  std::string cli_name() const;  // the option's one spelling: "sh-order" for sh_order, "min-size" for min_size
};

// "true", "0.5", "'ggx'", "[1, 2, 3]".
std::string param_value_text(const ParamValue& value);
// The valid range of a definition in words: "an integer in 1..65536", "one of ggx, charlie", ...
std::string param_expectation(const ParamDef& def);
// Checks a value against its definition; throws Error("<field>: must be ... (got ...)"), the field
// named as `field`.
void check_param(const ParamDef& def, const ParamValue& value, const std::string& field);
// Parses the text of a command-line option into a value of the definition's type (numbers may be
// written as 1e6; an Rgb as "v" or "r,g,b"; a Range as "lo,hi"; an IntList as "n" or "n,m,k").
// Throws Error naming `field` for text that is not of the type; the range is checked by check_param.
ParamValue parse_param_text(const ParamDef& def, const std::string& text, const std::string& field);

const ParamDef* find_param_def(const std::vector<ParamDef>& schema, const std::string& name);
// The definition `name` spells: its own name, or else one of its aliases.
const ParamDef* find_param_def_or_alias(const std::vector<ParamDef>& schema, const std::string& name);
// Renames each parameter given by an alias to its definition's name, so that everything after reads
// (and writes) only canonical names. Two spellings of one definition given together are refused:
// Error("<prefix><name>: given together with its alias <alias> (the same option): give one"), the
// names spelled as options ("--chain-size") when `cli`, else as fields ("chain_size"); `prefix` as the caller names its
// fields ("bake: ", "job.json: tables[0]."). Names the schema does not know are left as they are, for the caller's own
// message.
void canonicalize_params(Params& params, const std::vector<ParamDef>& schema, const std::string& prefix, bool cli);
// "--chain-size" (cli) or "chain_size".
std::string spelled_name(const std::string& name, bool cli);

// The one serialisation of schemas, shared by `brdfbake kinds --json` and the Python package:
// a type's name ("integer", "number", "name", "path", "flag", "rgb", "range", "integers"), and a
// schema as a JSON array, one object a parameter: name, option, type, expects, choices, default,
// default_text (the last three when there are any), required, output_only, help, and for numbers
// min, min_exclusive, max (finite ends only) and max_items (integers). `indent` as nlohmann's dump.
const char* param_type_name(ParamType type);
std::string schema_json(const std::vector<ParamDef>& schema, int indent = -1);

}  // namespace brdfbake
