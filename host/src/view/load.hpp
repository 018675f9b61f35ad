// Internal to `brdfbake view`: what a file holds, read by the first reader of a short table that
// claims it (view/load.cpp). A new output format is one more row of that table.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "brdfbake/brdf.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake::view {

// SH coefficients as irradiance writes them (.json).
struct ShView {
  int order = 0;
  std::vector<double> irradiance_over_pi;  // order^2 x RGB
  std::vector<double> radiance;            // order^2 x RGB (may be empty)
  std::string window;
  Metadata metadata;
};

// An HDR image that is neither a table nor a cube (e.g. an equirect environment, an RGBD face of
// EXT_lights_image_based), RGB; or an 8-bit picture (a contact sheet), shown as it is stored.
struct HdrImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
  Metadata metadata;
  bool display_referred = false;  // sRGB-encoded values in [0, 1]: no exposure or tone map
};

// A picture drawn already, shown as it is (8-bit sRGB, row 0 first), with a caption: a preview's
// contact sheet (brdfbake preview, docs/PREVIEW.md), read through its NAME.json.
struct Picture {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  std::string caption;
};

// The files a manifest or a folder lists, with what the manifest says of each.
struct FileList {
  std::vector<std::string> paths;
  std::vector<Metadata> notes;       // per path: kind, error bound, runtime, ... (may be empty)
  std::vector<std::string> skipped;  // what a folder holds that view does not show, each with why
};

struct Item {
  std::string path;
  std::string kind;  // "cube (KTX2)", "table (OpenEXR)", ... as view_kind says
  std::variant<Table, CubeLevels, ShView, MerlTable, HdrImage, FileList, Picture> content;
  // An engine file's irradiance beside its chain: a .env's polynomial, an EXT_lights_image_based
  // light's coefficients, a Filament KTX1's "sh" key (converted back to E/pi coefficients).
  std::optional<ShView> irradiance;
  Metadata notes;  // from a manifest: what it records about this file
};

// The reader that claims `path`: its kind text (view_kind); throws Error for no reader.
std::string kind_of(const std::string& path);
Item load(const std::string& path);

}  // namespace brdfbake::view
