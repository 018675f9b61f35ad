// Delivery: how a result becomes a file with the bound it records, for tables and cubes alike. A
// recorded bound is the result's own (its integration) plus what the output's encoding adds,
// measured on the values the file stores (io/storage.hpp); values the encoding cannot hold are
// refused, or clamped and recorded where the request asks (png_range, clamp_f16).
#include "families/delivery.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>

#include "brdfbake/error_figures.hpp"
#include "families/family.hpp"
#include "io/astc_ktx2.hpp"
#include "io/atomic_file.hpp"
#include "io/cubemap_io.hpp"
#include "io/ktx2.hpp"
#include "io/storage.hpp"

namespace brdfbake {

// ---- Bounds ----------------------------------------------------------------------------------------

// Rounded up to three significant digits: the recorded text, read back, is never below the bound.
std::string error_bound_text(double v) {
  if (!(v > 0) || !std::isfinite(v)) return detail::fmt_number(v, "%.3g");
  const double scale = std::pow(10.0, std::floor(std::log10(v)) - 2);
  // (1 - 1e-12): a bound that prints exactly (0.00123) stays itself; the loop then steps up where
  // the division or the printing rounded below it.
  double r = std::ceil(v / scale * (1 - 1e-12)) * scale;
  std::string text = detail::fmt_number(r, "%.3g");
  for (int i = 0; i < 3 && std::strtod(text.c_str(), nullptr) < v; ++i) text = detail::fmt_number(r += scale, "%.3g");
  return text;
}

}  // namespace brdfbake

namespace brdfbake::detail {

namespace {

std::string count_text(size_t n, const char* what) { return std::to_string(n) + " " + what + (n == 1 ? "" : "s"); }

}  // namespace

// ---- Tables ----------------------------------------------------------------------------------------

OutputFormats table_formats() {
  return {{".exr", ".png", ".hdr", ".ktx2", ".csv", ".h"}, "a table format (.exr .png .hdr .ktx2 .csv .h)"};
}

ParamDef clamp_f16_param() {
  return ParamDef("clamp_f16", ParamType::Flag,
                  "f16 outputs: clamp values beyond 65504 to 65504 (counted, recorded as f16_clamped, and warned "
                  "about) instead of refusing them")
      .def(false)
      .output();
}

size_t clamp_to_binary16(std::vector<float>& values) {
  size_t count = 0;
  for (float& v : values)
    if (std::isfinite(v) && std::fabs(v) > 65504.0f) {
      v = std::copysign(65504.0f, v);
      ++count;
    }
  return count;
}

std::string record_f16_clamp(WriteReport& w, const std::string& path, size_t count, double largest) {
  const std::string text = std::to_string(count) + " value" + (count == 1 ? "" : "s") +
                           " beyond 65504 clamped to 65504 (binary16's largest), the largest " +
                           fmt_number(largest, "%.6g");
  w.details.push_back({"f16_clamped", std::to_string(count)});
  w.warnings.push_back("'" + path + "': " + text);
  return text;
}

double with_f16_clamp_error(double measured, double largest) {
  return std::max(measured, (largest - 65504.0) / largest);  // the clamping, relative
}

void add_table_output_params(std::vector<ParamDef>& s) {
  s.push_back(ParamDef("symbol", ParamType::Name, "C identifier of the array in a .h output").output());
  s.push_back(clamp_f16_param());
  s.push_back(ParamDef("png_range", ParamType::Name,
                       "16-bit .png holds [0, 1]: refuse other values, scale each channel by its largest value "
                       "(recorded as png_scale), or clamp them (recorded)")
                  .one_of({"refuse", "scale", "clamp"})
                  .def(std::string("refuse"))
                  .output());
}

namespace {

// A 16-bit PNG holds [0, 1]: values outside are refused, or scaled per channel, or clamped, as the
// request's png_range says (both recorded in the table's metadata and `w`'s details).
void apply_png_range(Table& out, io::StorageReport& s, WriteReport& w, const TableRequest& t, PixelType pixel,
                     const std::string& path) {
  const std::string policy = t.text("png_range", "refuse");
  if (policy == "refuse")
    throw Error("'" + path + "': " + count_text(s.out_of_range, "value") + " outside [0, 1] (largest " +
                fmt_number(s.largest, "%.4g") +
                "), which a 16-bit PNG cannot hold: write .exr or .ktx2, or give png_range scale (or clamp)");
  if (policy == "scale") {
    // Each channel divided by its largest value (at least 1): stored = value / scale.
    const size_t channels = out.channels.size();
    std::vector<double> scale(channels, 1.0);
    for (size_t k = 0; k < out.data.size(); ++k)
      scale[k % channels] = std::max(scale[k % channels], std::fabs(double(out.data[k])));
    std::string text;
    for (size_t c = 0; c < channels; ++c) text += (c ? "," : "") + fmt_number(scale[c], "%.9g");
    for (size_t k = 0; k < out.data.size(); ++k) out.data[k] = float(double(out.data[k]) / scale[k % channels]);
    out.set_meta("png_scale", text);
    out.set_meta("png_scale_definition", "value = stored * png_scale (per channel, in the order of channels)");
    w.details.push_back({"png_scale", text});
    const io::StorageReport scaled = io::measure_storage(out, TableFormat::Png, pixel);
    // the scaled error, back in the table's units
    double worst = 0.0;
    for (double k : scale) worst = std::max(worst, k);
    s.max_error = scaled.max_error * worst;
    s.out_of_range = scaled.out_of_range;
  } else {
    out.set_meta("png_clamped", count_text(s.out_of_range, "value") + " clamped to [0, 1], the largest " +
                                    fmt_number(s.largest, "%.6g"));
    w.details.push_back({"png_clamped", std::to_string(s.out_of_range)});
    s.out_of_range = 0;  // asked for: the error is measured (it includes the clamping)
  }
}

// Values the format cannot hold are refused, naming the option that fixes it.
// The file's error figure under its kind's name (brdfbake/error_figures.hpp, docs/CONVENTIONS.md
// "Error figures"): error_name, NAME and error_definition, in place of what the bake recorded under
// the legacy `error_bound` and its definition (kept as integration_error_bound_definition).
void set_error_figure(Metadata& meta, TableKind kind, const std::string& value) {
  meta.erase(std::remove_if(meta.begin(), meta.end(),
                            [](const auto& kv) {
                              return kv.first == kLegacyErrorBoundName || kv.first == "error_bound_definition";
                            }),
             meta.end());
  const ErrorFigure& e = error_figure(kind);
  const auto set = [&meta](const std::string& k, const std::string& v) {
    for (auto& kv : meta)
      if (kv.first == k) {
        kv.second = v;
        return;
      }
    meta.emplace_back(k, v);
  };
  set("error_name", e.name);
  set(e.name, value);
  set("error_definition", e.definition);
}

void refuse_out_of_range(const io::StorageReport& s, TableFormat format, PixelType pixel, const std::string& path) {
  if ((format == TableFormat::Ktx2 || format == TableFormat::CHeader) && pixel == PixelType::F16)
    throw Error("'" + path + "': " + count_text(s.out_of_range, "value") + " beyond 65504 (largest " +
                fmt_number(s.largest, "%.6g") +
                "), which binary16 cannot hold: give pixel f32 (--pixel f32), or clamp_f16 (--clamp-f16) to clamp and "
                "record them");
  throw Error("'" + path + "': " + count_text(s.out_of_range, "value") + " the format cannot hold (largest |value| " +
              fmt_number(s.largest, "%.6g") + "): no NaN or infinity is written");
}

// The delivered bound, `bound` plus the storage error: refused above `limit` (the request's
// max_error), else recorded with its parts in the table's metadata.
void record_table_bound(Table& out, WriteReport& w, const io::StorageReport& s, double bound,
                        std::optional<double> limit, TableFormat format, const std::string& path, TableKind kind) {
  w.error_bound = bound + s.max_error;
  if (limit && *w.error_bound > *limit)
    throw Error("'" + path + "': the stored values would be within " + bound_text(*w.error_bound) +
                " of converged (integration " + bound_text(bound) + " + " + s.encoding + " " + bound_text(s.max_error) +
                "), above max_error " + fmt_number(*limit) + ": " +
                (format == TableFormat::Png || format == TableFormat::Hdr ? "write .exr, .csv or a .ktx2 with pixel f32"
                                                                          : "give pixel f32 (--pixel f32)"));
  out.set_meta("integration_error_bound", bound_text(bound));
  const std::string definition = out.meta("error_bound_definition");
  if (!definition.empty()) out.set_meta("integration_error_bound_definition", definition);
  out.set_meta("storage_error", bound_text(s.max_error));
  out.set_meta("storage_encoding", s.encoding);
  set_error_figure(out.metadata, kind, bound_text(*w.error_bound));
}

}  // namespace

namespace {

// write_table_result, or with `bytes` its file made in memory (the format must be one encode_table
// makes).
WriteReport write_or_encode_table(const Table& table, const TableRequest& t, const std::string& path,
                                  std::optional<double> bound, std::optional<double> limit, std::string* bytes) {
  const TableFormat format = path == "-" && t.format.empty() ? TableFormat::Csv : table_output_format(t);
  const PixelType pixel = pixel_of(t);
  Table out = table;
  io::StorageReport s = io::measure_storage(out, format, pixel);
  WriteReport w;
  if (format == TableFormat::Png && s.out_of_range > 0) apply_png_range(out, s, w, t, pixel, path);
  if (s.out_of_range > 0 && (format == TableFormat::Ktx2 || format == TableFormat::CHeader) &&
      pixel == PixelType::F16 && t.flag("clamp_f16") && std::isfinite(s.largest)) {
    // asked for (the largest value is finite: nothing non-finite to refuse below)
    const double largest = s.largest;
    out.set_meta("f16_clamped", record_f16_clamp(w, path, clamp_to_binary16(out.data), largest));
    s = io::measure_storage(out, format, pixel);
    s.max_error = with_f16_clamp_error(s.max_error, largest);
  }
  if (s.out_of_range > 0) refuse_out_of_range(s, format, pixel, path);
  w.storage_error = s.max_error;
  w.encoding = s.encoding;
  if (bound) record_table_bound(out, w, s, *bound, limit, format, path, t.kind);
  if (path == "-") {
    write_table_csv(out, std::cout);
    return w;
  }
  TableWriteOptions o;
  o.pixel = pixel;
  o.symbol = t.text("symbol");
  if (bytes) {
    std::optional<std::string> encoded = encode_table(out, path, format, o);
    if (!encoded) throw Error("'" + path + "': internal: this format is not made in memory");
    *bytes = std::move(*encoded);
    return w;
  }
  write_table(out, path, format, o);
  return w;
}

}  // namespace

WriteReport write_table_result(const Table& table, const TableRequest& t, const std::string& path,
                               std::optional<double> bound, std::optional<double> limit) {
  return write_or_encode_table(table, t, path, bound, limit, nullptr);
}

std::optional<WrittenBytes> table_result_bytes(const Table& table, const TableRequest& t, std::optional<double> bound,
                                               std::optional<double> limit) {
  const TableFormat format = table_output_format(t);
  if (format == TableFormat::Png || format == TableFormat::Hdr || pixel_of(t) == PixelType::R11G11B10)
    return std::nullopt;
  WrittenBytes out;
  out.report = write_or_encode_table(table, t, t.output, bound, limit, &out.bytes);
  return out;
}

// ---- Cubes -----------------------------------------------------------------------------------------

OutputFormats cube_formats() {
  return {{".ktx2", ".ktx", ".dds", ""}, "a cube container (.ktx2 .ktx .dds) or a folder of images"};
}

CubeFormat cube_format_of(const TableRequest& t) {
  CubeFormat f = cube_format_from_path(t.output);
  if (f == CubeFormat::Dds && t.format == "dds-legacy") f = CubeFormat::DdsLegacy;
  return f;
}

CubeWriteOptions cube_write_options_of(const TableRequest& t, const std::string& stem) {
  CubeWriteOptions o;
  o.pixel = pixel_of(t);
  const std::string layout = t.text("layout", "faces");
  o.layout = layout == "cross"      ? CubeImageLayout::HorizontalCross
             : layout == "vcross"   ? CubeImageLayout::VerticalCross
             : layout == "equirect" ? CubeImageLayout::Equirect
                                    : CubeImageLayout::Faces;
  o.image_format = t.text("image_format", "exr") == "hdr" ? CubeImageFormat::Hdr : CubeImageFormat::Exr;
  o.stem = stem;
  return o;
}

// The output parameters of a cube: folder layout and image format.
void add_cube_output_params(std::vector<ParamDef>& s) {
  s.push_back(ParamDef("layout", ParamType::Name, "folder output: the images of each level")
                  .one_of({"faces", "cross", "vcross", "equirect"})
                  .def(std::string("faces"))
                  .output());
  s.push_back(ParamDef("image_format", ParamType::Name, "folder output: .exr (float) or .hdr (RGBE) images")
                  .one_of({"exr", "hdr"})
                  .def(std::string("exr"))
                  .output());
  s.push_back(clamp_f16_param());
}

void check_cube_output(const TableRequest& t, const FieldName& name) {
  const std::string ext = output_extension(t);
  const bool folder = cube_format_from_path(t.output) == CubeFormat::Directory;
  if (!t.format.empty() && t.format != ext.substr(1) && t.format != "dds-legacy")
    throw FieldError("format", "'" + t.format + "' is not a cube container (ktx2, ktx, dds, dds-legacy)");
  if (t.format == "dds-legacy" && lower_extension(t.output) != ".dds")
    throw FieldError("format", "dds-legacy writes a .dds file (got '" + t.output + "')");
  if (!t.format.empty() && lower_extension(t.output) != ext)
    throw FieldError("format", "'" + t.format + "' does not match the extension of '" + t.output + "'");
  if (astc_block_of(t) && cube_format_from_path(t.output) != CubeFormat::Ktx2)
    throw FieldError("pixel",
                     t.pixel + " is stored in KTX2 only (the output is '" + t.output + "'; give a .ktx2 file)");
  if (!folder && (t.find("layout") && t.text("layout") != "faces"))
    throw FieldError("layout", "is for folder outputs (the output is '" + t.output + "')");
  (void)name;
}

// Writes a cube with the request's container and pixel type, refusing texels the pixel type cannot
// hold (binary16 beyond 65504: a real sun) and adding the storage rounding to `bound`.
int astc_block_of(const TableRequest& t) { return t.pixel == "astc4x4" ? 4 : t.pixel == "astc6x6" ? 6 : 0; }

namespace {

// ASTC HDR KTX2 (pixel astc4x4 / astc6x6): compressed, decoded again by astcenc and compared
// (io/astc_ktx2). The storage error is the largest over the levels of the RMS relative difference
// of the decoded values (the chains' bound is an RMS; a block's darkest channels beside a sun
// differ by up to 100 % and more, recorded per level in astc_max_rel_error_per_level), added to
// `bound` as binary16's rounding is.
WriteReport write_astc_cube(const CubeLevels& cube, int block, const std::string& path, std::optional<double> bound,
                            TableKind kind) {
  const io::AstcCube astc = io::compress_astc_cube(cube, block, kAstcQuality);
  WriteReport w;
  w.storage_error = 0.0;
  for (double e : astc.rms_rel_error) w.storage_error = std::max(w.storage_error, e);
  w.encoding = "ASTC " + std::to_string(block) + "x" + std::to_string(block) + " HDR (astcenc, quality " +
               fmt_number(kAstcQuality) + "; the largest RMS relative difference of a level's decoded values)";
  CubeLevels out;
  out.size = cube.size;
  out.metadata = cube.metadata;
  out.set_meta("storage_error", bound_text(w.storage_error));
  out.set_meta("storage_encoding", w.encoding);
  if (bound) {
    w.error_bound = *bound + w.storage_error;
    set_error_figure(out.metadata, kind, bound_text(*w.error_bound));
  }
  const std::vector<uint8_t> bytes = io::astc_ktx2_bytes(out, astc, kAstcQuality);
  io::write_file_atomically(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  return w;
}

}  // namespace

WriteReport write_cube_result(const CubeLevels& cube, const TableRequest& t, const std::string& path,
                              const std::string& stem, std::optional<double> bound) {
  if (const int block = astc_block_of(t)) return write_astc_cube(cube, block, path, bound, t.kind);
  const PixelType pixel = pixel_of(t);
  io::StorageReport s = io::measure_cube_storage(cube.levels, pixel);
  WriteReport w;
  std::optional<CubeLevels> clamped;  // a copy only when asked to clamp and there is something to clamp
  if (s.out_of_range > 0 && pixel == PixelType::F16 && t.flag("clamp_f16") && std::isfinite(s.largest)) {
    clamped = cube;
    size_t count = 0;
    for (auto& level : clamped->levels) count += clamp_to_binary16(level);
    const double largest = s.largest;
    clamped->set_meta("f16_clamped", record_f16_clamp(w, path, count, largest));
    s = io::measure_cube_storage(clamped->levels, pixel);
    s.max_error = with_f16_clamp_error(s.max_error, largest);
  }
  if (s.out_of_range > 0) {
    const std::string what = std::to_string(s.out_of_range) + " texel value" + (s.out_of_range == 1 ? "" : "s");
    if (pixel == PixelType::F16 && std::isfinite(s.largest))
      throw Error("'" + path + "': " + what + " beyond 65504 (largest " + fmt_number(s.largest, "%.6g") +
                  "), which binary16 cannot hold: give pixel f32 (--pixel f32), or clamp_f16 (--clamp-f16) to clamp "
                  "and record them");
    throw Error("'" + path + "': " + what + " not finite: no NaN or infinity is written");
  }
  const CubeLevels& cube_out = clamped ? *clamped : cube;
  TableRequest at = t;
  at.output = path;
  w.storage_error = s.max_error;
  w.encoding = s.encoding;
  if (!bound) {
    // nothing to add to the metadata: written as it is (a copy of a 1024^2 chain is 128 MiB)
    write_cubemap(cube_out, path, cube_format_of(at), cube_write_options_of(at, stem));
    return w;
  }
  // the bound's figures added to a copy of the metadata, not of the levels (every chain records a
  // bound: a copy of a 1024^2 chain is 128 MiB)
  CubeLevels figures;
  figures.metadata = cube_out.metadata;
  w.error_bound = *bound + s.max_error;
  figures.set_meta("storage_error", bound_text(s.max_error));
  figures.set_meta("storage_encoding", s.encoding);
  set_error_figure(figures.metadata, t.kind, bound_text(*w.error_bound));
  io::write_cubemap_with_metadata(cube_out, figures.metadata, path, cube_format_of(at),
                                  cube_write_options_of(at, stem));
  return w;
}

}  // namespace brdfbake::detail
