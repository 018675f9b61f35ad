// Internal: the preview's files (the descriptor's write): NAME.png, the contact sheet (split-sum,
// reference and error panels, labelled, the numbers under each sphere), and beside it
// NAME_splitsum.exr, NAME_reference.exr and NAME.json.
#pragma once

#include <string>

#include "brdfbake/preview.hpp"
#include "brdfbake/view.hpp"

namespace brdfbake::detail::preview {

// The names beside the sheet: NAME_splitsum.exr, NAME_reference.exr, NAME.json for NAME.png.
std::string sibling(const std::string& sheet_path, const std::string& suffix);

// The contact sheet (8-bit sRGB) with its regions ("split-sum", "reference", "error", "sphere", ...).
ContactSheet preview_sheet(const PreviewResult& r, const std::string& title);

// Every number of the result, as the JSON writes it.
std::string preview_json(const PreviewResult& r, const std::string& environment, const std::string& sheet_path);

// The relative error of the split-sum render at a pixel (NaN off the spheres).
std::vector<float> error_image(const PreviewResult& r);

// Writes the four files; the EXRs and the JSON are staged and renamed after the sheet.
void write_preview(const PreviewResult& r, const std::string& environment, const std::string& sheet_path);

}  // namespace brdfbake::detail::preview
