// brdfbake view FILE... -o SHEET.png [--exposure EV] [--tonemap aces|reinhard|clamp] [...]
#include <cstdio>
#include <iostream>

#include "brdfbake/output_checks.hpp"
#include "brdfbake/view.hpp"
#include "cli_common.hpp"

namespace brdfbake::cli {

int cmd_view(int argc, char** argv) {
  cxxopts::Options options("brdfbake view",
                           "Draw any outputs of brdfbake (cubes, tables, SH, MERL, eval values, a bake's folder or "
                           "manifest.json) into one contact sheet, an 8-bit sRGB PNG (docs/VIEW.md)");
  // clang-format off
  options.add_options()
      ("files", "files or folders to show", cxxopts::value<std::vector<std::string>>())
      ("o,output", "the contact sheet (.png)", cxxopts::value<std::string>())
      ("exposure", "EV: HDR radiance is multiplied by 2^EV before the tone map (default: chosen per picture, its log-average luminance shown at 0.18 and its 99th percentile at most 1; each caption says the EV)", cxxopts::value<std::string>())
      ("tonemap", "aces | reinhard | clamp: the curve from radiance to display (default: aces)", cxxopts::value<std::string>())
      ("face-size", "pixels a cube face is shown at, every level alike (default: 64)", cxxopts::value<std::string>())
      ("table-size", "pixels of a table image's longer side (default: 160)", cxxopts::value<std::string>())
      ("width", "the sheet's width in pixels (default: 1400)", cxxopts::value<std::string>())
      ("title", "the sheet's first line (default: brdfbake view)", cxxopts::value<std::string>())
      ("quiet", "no summary line")
      ("h,help", "this help");
  // clang-format on
  options.parse_positional({"files"});
  options.positional_help("FILE...");
  const auto r = parse(options, argc, argv);
  if (r.count("help")) {
    std::cout
        << options.help()
        << "\nexamples:\n  brdfbake view out/ -o out/contact_sheet.png\n"
           "  brdfbake view prefilter_ggx_256.ktx2 dfg_ggx_multiscatter_128.exr irradiance_sh3.json -o sheet.png\n";
    return 0;
  }
  if (!r.unmatched().empty()) throw UsageError("unexpected argument '" + r.unmatched().front() + "'");
  if (!r.count("files")) throw UsageError("missing the files to view (brdfbake view FILE... -o SHEET.png)");
  if (!r.count("output")) throw UsageError("missing -o SHEET.png");
  const std::string out = r["output"].as<std::string>();
  if (out.size() < 5 || out.substr(out.size() - 4) != ".png")
    throw UsageError("-o must name a .png file (got '" + out + "')");
  ViewOptions o;
  if (r.count("exposure")) o.exposure = finite_number(r, "exposure");
  if (r.count("tonemap")) {
    try {
      o.tone_map = tone_map_from_name(r["tonemap"].as<std::string>());
    } catch (const Error& e) {
      throw UsageError(std::string("--tonemap: ") + e.what());
    }
  }
  if (r.count("face-size")) o.face_size = integer(r, "face-size");
  if (r.count("table-size")) o.table_size = integer(r, "table-size");
  if (r.count("width")) o.max_width = integer(r, "width");
  if (r.count("title")) o.title = r["title"].as<std::string>();
  check_output_path(out);
  {  // the sheet is none of the files it draws (`view s.png -o s.png`), nor in a folder it draws
    std::vector<RequestFile> inputs;
    for (const auto& f : r["files"].as<std::vector<std::string>>()) inputs.push_back({"the viewed file", f, false, ""});
    check_outputs_not_inputs({{"-o", out, false, ""}}, inputs);
  }
  const ContactSheet sheet = render_contact_sheet(r["files"].as<std::vector<std::string>>(), o);
  write_contact_sheet(sheet, out);
  if (!r.count("quiet")) {
    std::fprintf(stderr, "%s: %dx%d, %zu file%s; %s\n", out.c_str(), sheet.width, sheet.height, sheet.files.size(),
                 sheet.files.size() == 1 ? "" : "s", sheet.tone_map_text.c_str());
    for (const auto& s : sheet.skipped) std::fprintf(stderr, "skipped %s\n", s.c_str());
  }
  return 0;
}

}  // namespace brdfbake::cli
