// Internal: every value read from a bake folder (its manifest.json, an SH JSON, a glTF light, the KTX
// "sh" key, the DFG tables, the cubes), typed, range- and finiteness-checked, a failure a one-line
// brdfbake::Error (exit 2 in the CLI, brdfbake.InputError in Python) that names the file and the
// field's path as a job spells it ("files[2].path"). A bake folder is input like any other: a
// hand-edited or hostile manifest must never be an undefined read, a raw [json.exception...] or a
// render with NaN in it (issue 34, class 6).
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake::detail::bake_read {

using json = nlohmann::ordered_json;

// Bounds of what a bake folder may hold, each with its reason. fp32 shading (the split-sum render is
// a shader's arithmetic) overflows near 3.4e38: a sum of 9 coefficients times polynomials of at most 3,
// times pi, and a cube texel mixed with its neighbours and weighted by a DFG term stay finite below these.
inline constexpr double kMaxShCoefficient = 1e20;  // |SH coefficient| (radiance of the brightest sun ~1e9)
inline constexpr double kMaxCubeTexel = 1e30;      // |texel| of a decoded cube (half floats stop at 65504)
inline constexpr double kMaxTableValue = 1e3;      // |value| of a DFG or charlie table: albedos, fractions of 1

// A JSON value and where it was read: `file` the file, `path` the field ("" for the document).
class Field {
 public:
  Field(const json& value, std::string file, std::string path = {});

  // "'FILE': PATH" (or "'FILE'" for the document), the start of every message about this value.
  std::string where() const;
  [[noreturn]] void fail(const std::string& problem) const;

  bool is_object() const { return value_->is_object(); }
  // The member `key`: required (an object holding it), or optional (absent: nullopt); either way this
  // value must be an object.
  Field at(const std::string& key) const;
  std::optional<Field> find(const std::string& key) const;
  // The elements of an array (required to be one).
  std::vector<Field> elements() const;

  std::string string() const;
  // A string naming a file inside the bake folder: relative, no ".." component, no NUL.
  std::string file_name() const;
  double number(double lo, double hi) const;  // finite, in [lo, hi]
  int integer(int lo, int hi) const;          // an integer number in [lo, hi]
  // An optional string member; `fallback` when absent.
  std::string string_or(const std::string& key, const std::string& fallback) const;

  const json& value() const { return *value_; }
  const std::string& file() const { return file_; }

 private:
  const json* value_;
  std::string file_;
  std::string path_;
};

// SH coefficients (9 or more RGB rows, as the target stores them): an array of [r, g, b] rows (or a
// flat array), every number finite and within kMaxShCoefficient; exactly `count` numbers.
std::vector<double> sh_numbers(const Field& a, std::size_t count);
// Numbers parsed from text (Filament's "sh" key, sh.txt): `count` of them, finite, within kMaxShCoefficient;
// `what` names the source ("'F_ibl.ktx': the sh key").
std::vector<double> sh_text_numbers(const std::string& text, std::size_t count, const std::string& what);

// ---- The manifest of a bake folder ----------------------------------------------------------

std::string join_path(const std::string& folder, const std::string& file);
// The file of the manifest's engine file set ("engine.files", an array of file names) whose name ends
// in `tail`, joined to `folder`: nullopt when none (engine_file: an Error saying to bake with --target).
std::optional<std::string> find_engine_file(const Field& manifest, const std::string& folder, const std::string& tail);
std::string engine_file(const Field& manifest, const std::string& folder, const std::string& tail);
// The first entry of the manifest's "files" of `kind` (every entry an object with a string "kind"):
// for the prefilter, of the distribution `distribution`; for the irradiance, its SH JSON.
std::optional<Field> manifest_entry(const Field& manifest, const std::string& kind,
                                    const std::string& distribution = "ggx");
// An entry's file, joined to `folder` ("path", a file name inside the folder).
std::string entry_file(const Field& entry, const std::string& folder);

// A decoded cube: at least one level, every texel finite and within kMaxCubeTexel.
void check_cube(const CubeLevels& cube, const std::string& file);
// A table the shading looks up: non-empty, at least `channels` channels, every value finite and within
// kMaxTableValue.
void check_table(const Table& table, const std::string& file, int channels);

}  // namespace brdfbake::detail::bake_read
