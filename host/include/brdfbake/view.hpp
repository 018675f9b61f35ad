// Pictures of what brdfbake writes (`brdfbake view`, `brdfbake bake --contact-sheet`): one contact
// sheet, an 8-bit sRGB PNG, for any set of outputs:
//   cubes (.ktx2 .ktx .dds, a folder of per-level images)  a labelled horizontal cross per level,
//                                                          with the roughness of the level;
//   tables (.exr .png .hdr .ktx2 .csv .h)                  an image per channel with its axes and a
//                                                          colour scale (a line plot for 1-D tables);
//   SH coefficients (.json)                                a lit sphere and a plot of the bands;
//   MERL tables (.binary)                                  slices over (theta_h, theta_d);
//   eval output (.csv without metadata, .f32)              a plot of f against the pair index;
//   manifest.json, or a bake's output folder               every file it lists.
// HDR radiance is tone-mapped by a stated operator, table values by a stated colour scale; both are
// printed on the sheet. Conventions: docs/VIEW.md.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace brdfbake {

enum class ToneMap {
  Aces,      // Narkowicz 2015's fit of the ACES filmic curve: x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)
  Reinhard,  // x / (1 + x)
  Clamp,     // min(x, 1)
};
ToneMap tone_map_from_name(const std::string& name);  // "aces" | "reinhard" | "clamp"
const char* tone_map_name(ToneMap map);

struct ViewOptions {
  // EV: radiance is multiplied by 2^exposure before the tone map. None: chosen per picture from its
  // content (its log-average luminance at middle grey, its 99th percentile at most 1.0;
  // host/src/view/exposure.hpp), each picture's caption saying the EV it was drawn at.
  std::optional<double> exposure;
  ToneMap tone_map = ToneMap::Aces;
  int face_size = 64;       // pixels a cube face is shown at, every level alike
  int table_size = 160;     // pixels of a table image's longer side
  int max_width = 1400;     // the sheet's width (a file's pictures wrap to the next row)
  std::string title;        // the sheet's first line; empty: "brdfbake view"
  std::string relative_to;  // non-empty: files inside this folder are named relative to it (on the
                            // sheet, in `files` and in the PNG's text)
};

// A rectangle of the sheet and what it shows: tests check pixels against it, tools crop by it.
struct SheetRegion {
  std::string file;   // the file it shows
  std::string role;   // "cube level", "table channel", "table rgb", "colour scale", "plot",
                      // "sphere", "band plot", "merl slice", "file title", "sheet title", "image",
                      // "preview sheet" (a preview's contact sheet, as drawn)
  std::string label;  // e.g. "level 2", the channel's name, the slice's phi_d
  int x = 0, y = 0, width = 0, height = 0;
  double lo = 0.0, hi = 0.0;  // "colour scale" and "table channel": the values mapped to its ends
  bool log_scale = false;     // the scale is over log10 of the values
  double exposure = 0.0;      // "cube level", "sphere", "image": the EV its radiance was drawn at
};

struct ContactSheet {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  // 8-bit sRGB, row 0 (the top) first
  std::vector<SheetRegion> regions;
  std::vector<std::string> files;    // every file shown, in order (a manifest expands to its files),
                                     // named as the sheet names it
  std::string tone_map_text;         // the HDR transfer, as printed on the sheet
  std::string colour_scale_text;     // the table colour scale, as printed on the sheet
  std::vector<std::string> skipped;  // what the folders given hold that view does not show, with why
};

// What `view` makes of a file (e.g. "cube (KTX2)", "table (OpenEXR)", "manifest"); throws Error
// naming the file for one it cannot show.
std::string view_kind(const std::string& path);

// Reads every file (a folder: its manifest.json, else the files in it that view can show) and draws
// the sheet. Throws Error for a file that is missing, unreadable or of a kind view cannot show.
ContactSheet render_contact_sheet(const std::vector<std::string>& paths, const ViewOptions& options = {});
// The sheet as an 8-bit sRGB PNG with its tone map and colour scale in text chunks, atomically.
void write_contact_sheet(const ContactSheet& sheet, const std::string& path);

}  // namespace brdfbake
