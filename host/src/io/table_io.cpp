// Writing tables: the format lookup and one writer per output format.
//
// Image orientation, the same in every image format (.exr, .png, .hdr, .ktx2): texel (i, j) of a
// table, column i along x and row j along y, is pixel x = i, y = j, and row j = 0 is stored first
// in the file, so it is the top row in an image viewer (in KTX2 terms, KTXorientation "rd"). Table
// channels map in order to R, G, B, A. Where a format needs more channels than the table has, the
// missing colour channels are written as 0 and a missing alpha (.ktx2 only) as 1; see each writer.
//
// Every writer goes through io::TempFile or io::write_file_atomically: the file appears complete
// or not at all, and every failure throws Error("cannot write '<path>': <reason>").
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string_view>

#include "brdfbake/error.hpp"
#include "brdfbake/io.hpp"
#include "io/atomic_file.hpp"
#include "io/half.hpp"
#include "io/image_file.hpp"
#include "io/ktx2.hpp"
#include "io/rgbe.hpp"
#include "io/special_files.hpp"
#include "text.hpp"

#ifndef BRDFBAKE_VERSION
#define BRDFBAKE_VERSION "unknown"
#endif

namespace brdfbake {
namespace {

namespace fs = std::filesystem;

constexpr const char* kGenerator = "brdfbake " BRDFBAKE_VERSION;
// Prefix of our keys in formats whose metadata namespace we share (EXR, PNG, KTX2).
constexpr const char* kKeyPrefix = "brdfbake:";
constexpr const char* kExpectedExtensions = ".exr, .png, .hdr, .ktx2, .csv or .h";

struct FormatName {
  TableFormat format;
  const char* name;
};
constexpr FormatName kFormatNames[] = {{TableFormat::Exr, "exr"}, {TableFormat::Png, "png"},
                                       {TableFormat::Hdr, "hdr"}, {TableFormat::Ktx2, "ktx2"},
                                       {TableFormat::Csv, "csv"}, {TableFormat::CHeader, "h"}};

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

const FormatName* find_format_name(const std::string& name) {
  const std::string lower = lowercase(name);
  for (const FormatName& entry : kFormatNames) {
    if (lower == entry.name) return &entry;
  }
  return nullptr;
}

size_t texel_count(const Table& table) { return static_cast<size_t>(table.width) * static_cast<size_t>(table.height); }

size_t channel_count(const Table& table) { return table.channels.size(); }

// Shape checks shared by every format.
void check_table(const Table& table, const std::string& path) {
  if (table.width <= 0 || table.height <= 0) {
    io::throw_write_error(
        path, "the table is empty (" + std::to_string(table.width) + "x" + std::to_string(table.height) + ")");
  }
  if (table.channels.empty()) io::throw_write_error(path, "the table has no channels");
  if (table.data.size() != texel_count(table) * channel_count(table)) {
    io::throw_write_error(path, "the table holds " + std::to_string(table.data.size()) + " values, expected " +
                                    std::to_string(table.width) + " x " + std::to_string(table.height) + " x " +
                                    std::to_string(channel_count(table)));
  }
}

// The coordinates that CSV rows carry: x for every column, y for every row of a 2-D table
// (a table with a y_name), and a 1-D table has one row.
void check_coordinates(const Table& table, const std::string& where) {
  if (table.x.size() != static_cast<size_t>(table.width)) {
    io::throw_write_error(where, "the table has " + std::to_string(table.x.size()) + " x coordinates for width " +
                                     std::to_string(table.width));
  }
  if (table.y_name.empty() && table.height != 1) {
    io::throw_write_error(where, "a table of height " + std::to_string(table.height) + " needs a y_name");
  }
  if (!table.y_name.empty() && table.y.size() != static_cast<size_t>(table.height)) {
    io::throw_write_error(where, "the table has " + std::to_string(table.y.size()) + " y coordinates for height " +
                                     std::to_string(table.height));
  }
}

void check_channel_limit(const Table& table, const std::string& path, size_t limit, const char* format) {
  if (channel_count(table) > limit) {
    io::throw_write_error(path, std::string("the ") + format + " format holds at most " + std::to_string(limit) +
                                    " channels; the table has " + std::to_string(channel_count(table)));
  }
}

using detail::join;

// Replaces or appends an entry, keeping keys unique.
void set_entry(Metadata& metadata, const std::string& key, const std::string& value) {
  auto it = std::find_if(metadata.begin(), metadata.end(), [&](const auto& entry) { return entry.first == key; });
  if (it != metadata.end()) {
    it->second = value;
  } else {
    metadata.emplace_back(key, value);
  }
}

// The metadata an image file records: the table's, plus the channel names in file order.
Metadata image_metadata(const Table& table) {
  Metadata metadata = table.metadata;
  set_entry(metadata, "channels", join(table.channels, ","));
  return metadata;
}

// Metadata values on one line, for formats whose metadata is line-oriented text (CSV, C header).
std::string one_line(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '\r', ' ');
  return text;
}

// %.9g: nine significant digits round-trip every float.

// ---- Image formats ------------------------------------------------------------------------------

// The metadata as image attributes or text chunks: "brdfbake:KEY".
std::vector<std::pair<std::string, std::string>> prefixed(const Metadata& metadata) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& [key, value] : metadata) out.emplace_back(kKeyPrefix + key, value);
  return out;
}

// .exr: float32, channels named R, G, B, A in table order (a 1-channel table is just "R"),
// ZIP compression, every metadata entry as a string attribute "brdfbake:KEY".
std::string encode_exr(const Table& table, const std::string& path) {
  check_channel_limit(table, path, 4, ".exr");
  return io::encode_exr(path, table.width, table.height, table.channel_count(), table.data.data(),
                        prefixed(image_metadata(table)));
}

void write_exr(const Table& table, const std::string& path) {
  check_channel_limit(table, path, 4, ".exr");
  io::TempFile temp(path);
  io::write_exr(temp, table.width, table.height, table.channel_count(), table.data.data(),
                prefixed(image_metadata(table)));
  temp.commit();
}

// .png: 16-bit, values clamped to [0, 1] and quantised to round(v * 65535). One channel is grey;
// two channels are padded to RGB with blue = 0 (grey + alpha would misread them); three are RGB,
// four RGBA. Metadata goes into tEXt chunks ("brdfbake:KEY"); if any value was clamped (NaN counts,
// and becomes 0), the entry "clamped_values" says how many.
void write_png(const Table& table, const std::string& path) {
  check_channel_limit(table, path, 4, ".png");
  const size_t channels = channel_count(table);
  const size_t file_channels = channels == 2 ? 3 : channels;
  std::vector<uint16_t> pixels(texel_count(table) * file_channels, 0);
  size_t clamped = 0;
  for (size_t texel = 0; texel < texel_count(table); ++texel) {
    for (size_t c = 0; c < channels; ++c) {
      const float value = table.data[texel * channels + c];
      const float unit = std::isnan(value) ? 0.0f : std::clamp(value, 0.0f, 1.0f);
      if (!(value >= 0.0f && value <= 1.0f)) ++clamped;
      pixels[texel * file_channels + c] = static_cast<uint16_t>(std::lround(unit * 65535.0f));
    }
  }
  Metadata metadata = image_metadata(table);
  if (clamped > 0) set_entry(metadata, "clamped_values", std::to_string(clamped));
  // PNG keywords are 1 to 79 bytes (PNG specification, "tEXt Textual data"); libpng would drop or
  // reject longer ones.
  constexpr size_t kMaxPngKeyword = 79;
  for (const auto& entry : metadata) {
    if (std::string(kKeyPrefix).size() + entry.first.size() > kMaxPngKeyword) {
      io::throw_write_error(path, "metadata key '" + entry.first +
                                      "' is too long for a PNG text chunk (79 bytes with the '" + kKeyPrefix +
                                      "' prefix)");
    }
  }
  io::TempFile temp(path);
  io::write_png16(temp, table.width, table.height, static_cast<int>(file_channels), pixels.data(), prefixed(metadata));
  temp.commit();
}

// .hdr: Radiance RGBE, RGB only (missing channels 0). RGBE has no sign, no infinity and no
// metadata: negative and NaN values are written as 0 and values beyond the largest RGBE value
// (exponent byte 255) as that value, each counted in "clamped_values", and the metadata, channel
// names and layout go to a sidecar "FILE.json", written atomically alongside.
void write_hdr(const Table& table, const std::string& path) {
  constexpr float kRgbeMax = io::kRgbeMax;  // (255 / 256) * 2^127
  check_channel_limit(table, path, 3, ".hdr");
  const size_t channels = channel_count(table);
  std::vector<float> pixels(texel_count(table) * 3, 0.0f);
  size_t clamped = 0;
  for (size_t texel = 0; texel < texel_count(table); ++texel) {
    for (size_t c = 0; c < channels; ++c) {
      const float value = table.data[texel * channels + c];
      if (!(value >= 0.0f && value <= kRgbeMax)) ++clamped;
      pixels[texel * 3 + c] = value >= 0.0f ? std::min(value, kRgbeMax) : 0.0f;
    }
  }
  Metadata metadata = table.metadata;
  if (clamped > 0) set_entry(metadata, "clamped_values", std::to_string(clamped));

  nlohmann::ordered_json sidecar;
  sidecar["generator"] = kGenerator;
  sidecar["image"] = fs::path(path).filename().string();
  sidecar["width"] = table.width;
  sidecar["height"] = table.height;
  sidecar["channels"] = table.channels;
  nlohmann::ordered_json rgb = nlohmann::ordered_json::array();
  for (size_t c = 0; c < 3; ++c) {
    rgb.push_back(c < channels ? nlohmann::ordered_json(table.channels[c]) : nullptr);
  }
  sidecar["layout"] = {
      {"orientation", "texel (i, j) is pixel x = i, y = j; row j = 0 is the first (top) row"},
      {"rgb", rgb},
      {"padding", "channels the table lacks are written as 0 (null above)"},
  };
  sidecar["x"] = {{"name", table.x_name}, {"values", table.x}};
  if (!table.y_name.empty()) sidecar["y"] = {{"name", table.y_name}, {"values", table.y}};
  nlohmann::ordered_json meta_object = nlohmann::ordered_json::object();
  for (const auto& [key, value] : metadata) meta_object[key] = value;
  sidecar["metadata"] = meta_object;
  std::string json_text;
  try {
    json_text = sidecar.dump(2) + "\n";
  } catch (const nlohmann::json::exception& e) {  // e.g. invalid UTF-8 in a metadata value
    io::throw_write_error(path + ".json", e.what());
  }

  io::TempFile image_temp(path);
  io::write_rgbe(image_temp, table.width, table.height, pixels.data());
  const std::string json_path = path + ".json";
  io::TempFile json_temp(json_path);
  io::write_bytes(json_temp, json_text);
  image_temp.commit();
  json_temp.commit();
}

// .ktx2: a 2-D texture (1 row for a 1-D table) of VK_FORMAT_R16G16B16A16_SFLOAT (PixelType::F16,
// rounded to nearest even, beyond 65504 infinite) or VK_FORMAT_R32G32B32A32_SFLOAT (F32); missing
// colour channels 0, missing alpha 1. Metadata as key/value pairs "brdfbake:KEY", plus KTXwriter
// and KTXorientation "rd".
std::string encode_ktx2_table(const Table& table, const std::string& path, const TableWriteOptions& options) {
  check_channel_limit(table, path, 4, ".ktx2");
  const bool half = options.pixel == PixelType::F16;
  const size_t channels = channel_count(table);
  const size_t component_bytes = half ? 2 : 4;
  io::Ktx2Image image;
  image.vk_format = half ? io::kVkFormatR16G16B16A16Sfloat : io::kVkFormatR32G32B32A32Sfloat;
  image.width = static_cast<uint32_t>(table.width);
  image.height = static_cast<uint32_t>(table.height);
  std::vector<uint8_t> level(texel_count(table) * 4 * component_bytes);
  for (size_t texel = 0; texel < texel_count(table); ++texel) {
    for (size_t c = 0; c < 4; ++c) {
      const float value = c < channels ? table.data[texel * channels + c] : (c == 3 ? 1.0f : 0.0f);
      uint8_t* out = level.data() + (texel * 4 + c) * component_bytes;
      if (half) {
        const uint16_t bits = io::float_to_half_bits(value);
        out[0] = static_cast<uint8_t>(bits);
        out[1] = static_cast<uint8_t>(bits >> 8);
      } else {
        uint32_t bits = 0;
        std::memcpy(&bits, &value, sizeof bits);
        for (size_t b = 0; b < 4; ++b) out[b] = static_cast<uint8_t>(bits >> (8 * b));
      }
    }
  }
  image.level_data.push_back(std::move(level));
  for (const auto& [key, value] : image_metadata(table)) {
    image.key_values.emplace_back(kKeyPrefix + key, value);
  }
  image.key_values.emplace_back("KTXwriter", kGenerator);
  image.key_values.emplace_back("KTXorientation", "rd");
  std::vector<uint8_t> bytes;
  try {
    bytes = io::encode_ktx2(image);
  } catch (const Error& e) {
    io::throw_write_error(path, e.what());
  }
  return std::string(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

// ---- Text formats -------------------------------------------------------------------------------

// RFC 4180 quoting, only where needed.
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

void write_csv_to(const Table& table, std::ostream& out) {
  for (const auto& [key, value] : table.metadata) {
    out << "# " << one_line(key) << ": " << one_line(value) << '\n';
  }
  out << csv_field(table.x_name.empty() ? "x" : table.x_name);
  if (!table.y_name.empty()) out << ',' << csv_field(table.y_name);
  for (const std::string& channel : table.channels) out << ',' << csv_field(channel);
  out << '\n';
  const int channels = table.channel_count();
  for (int j = 0; j < table.height; ++j) {
    for (int i = 0; i < table.width; ++i) {
      out << detail::fmt_number(table.x[static_cast<size_t>(i)]);
      if (!table.y_name.empty()) out << ',' << detail::fmt_number(table.y[static_cast<size_t>(j)]);
      for (int c = 0; c < channels; ++c) {
        out << ',' << detail::fmt_number(static_cast<double>(table.at(i, j, c)));
      }
      out << '\n';
    }
  }
}

bool is_identifier(const std::string& text) {
  if (text.empty() || std::isdigit(static_cast<unsigned char>(text[0]))) return false;
  return std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isalnum(c) || c == '_'; });
}

bool is_keyword(const std::string& word) {
  static const char* const kKeywords[] = {
      "alignas", "alignof", "and",      "asm",       "auto",     "bool",      "break",     "case",     "catch",
      "char",    "class",   "const",    "constexpr", "continue", "default",   "delete",    "do",       "double",
      "else",    "enum",    "explicit", "export",    "extern",   "false",     "float",     "for",      "friend",
      "goto",    "if",      "inline",   "int",       "long",     "mutable",   "namespace", "new",      "noexcept",
      "not",     "nullptr", "operator", "or",        "private",  "protected", "public",    "register", "restrict",
      "return",  "short",   "signed",   "sizeof",    "static",   "struct",    "switch",    "template", "this",
      "throw",   "true",    "try",      "typedef",   "typeid",   "typename",  "union",     "unsigned", "using",
      "virtual", "void",    "volatile", "while",     "xor"};
  return std::any_of(std::begin(kKeywords), std::end(kKeywords), [&](const char* keyword) { return word == keyword; });
}

// The C identifier for a header: options.symbol, or the file name's stem with every
// non-identifier character replaced by '_', "lut_" before a leading digit and '_' after a keyword.
std::string header_symbol(const std::string& path, const TableWriteOptions& options) {
  if (!options.symbol.empty()) {
    if (!is_identifier(options.symbol) || is_keyword(options.symbol)) {
      io::throw_write_error(path, "symbol '" + options.symbol + "' is not a C identifier");
    }
    return options.symbol;
  }
  std::string symbol = fs::path(path).stem().string();
  for (char& c : symbol) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';
  }
  if (symbol.empty()) symbol = "lut";
  if (std::isdigit(static_cast<unsigned char>(symbol[0]))) symbol = "lut_" + symbol;
  if (is_keyword(symbol)) symbol += '_';
  return symbol;
}

std::string float_literal(float value) {
  std::string text = detail::fmt_number(static_cast<double>(value));
  if (text.find_first_of(".e") == std::string::npos) text += ".0";
  return text + "f";
}

std::string c_header_text(const Table& table, const std::string& path, const TableWriteOptions& options) {
  const std::string symbol = header_symbol(path, options);
  std::string macro = symbol;
  std::transform(macro.begin(), macro.end(), macro.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  const bool half = options.pixel == PixelType::F16;
  std::ostringstream out;
  out << "// " << fs::path(path).filename().string() << ": a table generated by " << kGenerator << ". Do not edit.\n"
      << "//\n"
      << "// " << symbol << "[(j * " << macro << "_WIDTH + i) * " << macro
      << "_CHANNELS + c] is channel c of texel (i, j):\n"
      << "// column i along x (" << one_line(table.x_name) << "), row j along y"
      << (table.y_name.empty() ? "" : " (" + one_line(table.y_name) + ")") << ", row 0 first.\n"
      << "// Channels: " << one_line(join(table.channels, ", ")) << "\n"
      << "// Values: " << (half ? "IEEE 754 binary16 bit patterns (uint16_t)" : "IEEE 754 binary32 (float)") << "\n";
  if (!table.metadata.empty()) out << "//\n// Metadata:\n";
  for (const auto& [key, value] : table.metadata) {
    out << "//   " << one_line(key) << ": " << one_line(value) << "\n";
  }
  out << "#pragma once\n\n#include <stdint.h>\n\n"
      << "#define " << macro << "_WIDTH " << table.width << "\n"
      << "#define " << macro << "_HEIGHT " << table.height << "\n"
      << "#define " << macro << "_CHANNELS " << table.channel_count() << "\n\n"
      << "static const " << (half ? "uint16_t " : "float ") << symbol << "[" << macro << "_WIDTH * " << macro
      << "_HEIGHT * " << macro << "_CHANNELS] = {\n";
  constexpr size_t kValuesPerLine = 8;
  for (size_t k = 0; k < table.data.size(); ++k) {
    const float value = table.data[k];
    if (k % kValuesPerLine == 0) out << "   ";
    if (half) {
      char text[8];
      std::snprintf(text, sizeof text, "0x%04x", io::float_to_half_bits(value));
      out << ' ' << text;
    } else {
      if (!std::isfinite(value)) {
        io::throw_write_error(path, "value " + detail::fmt_number(static_cast<double>(value)) + " at index " +
                                        std::to_string(k) + " has no C float literal");
      }
      out << ' ' << float_literal(value);
    }
    out << (k + 1 < table.data.size() ? "," : "");
    if (k % kValuesPerLine == kValuesPerLine - 1 || k + 1 == table.data.size()) out << '\n';
  }
  out << "};\n";
  return out.str();
}

}  // namespace

TableFormat table_format_from_path(const std::string& path) {
  const std::string extension = fs::path(path).extension().string();
  if (extension.empty()) {
    throw Error("output file '" + path + "' has no extension (expected " + kExpectedExtensions + ")");
  }
  const FormatName* entry = find_format_name(extension.substr(1));
  if (entry == nullptr) {
    throw Error("unknown output format '" + extension + "' (expected " + kExpectedExtensions + ")");
  }
  return entry->format;
}

TableFormat table_format_from_name(const std::string& name) {
  const FormatName* entry = find_format_name(!name.empty() && name[0] == '.' ? name.substr(1) : name);
  if (entry == nullptr) {
    throw Error("unknown output format '" + name + "' (expected exr, png, hdr, ktx2, csv or h)");
  }
  return entry->format;
}

void write_table(const Table& table, const std::string& path, TableFormat format, const TableWriteOptions& options) {
  check_table(table, path);
  if (options.pixel == PixelType::R11G11B10)
    throw Error("cannot write '" + path +
                "': the R11F_G11F_B10F pixel format is for KTX1 cubemaps only "
                "(no sign, 6-bit mantissas); use f16 or f32 for tables");
  switch (format) {
    case TableFormat::Exr:
      write_exr(table, path);
      return;
    case TableFormat::Png:
      write_png(table, path);
      return;
    case TableFormat::Hdr:
      write_hdr(table, path);
      return;
    case TableFormat::Ktx2:
      io::write_file_atomically(path, encode_ktx2_table(table, path, options));
      return;
    case TableFormat::Csv: {
      check_coordinates(table, path);
      std::ostringstream text;
      write_csv_to(table, text);
      io::write_file_or_stream(path, text.str());  // CSV also goes to a FIFO, a device, /dev/stdout
      return;
    }
    case TableFormat::CHeader:
      io::write_file_atomically(path, c_header_text(table, path, options));
      return;
  }
  throw Error("cannot write '" + path + "': invalid TableFormat value");
}

std::optional<std::string> encode_table(const Table& table, const std::string& path, TableFormat format,
                                        const TableWriteOptions& options) {
  check_table(table, path);
  if (options.pixel == PixelType::R11G11B10) return std::nullopt;  // write_table says why not
  switch (format) {
    case TableFormat::Exr:
      return encode_exr(table, path);
    case TableFormat::Ktx2:
      return encode_ktx2_table(table, path, options);
    case TableFormat::Csv: {
      check_coordinates(table, path);
      std::ostringstream text;
      write_csv_to(table, text);
      return text.str();
    }
    case TableFormat::CHeader:
      return c_header_text(table, path, options);
    case TableFormat::Png:
    case TableFormat::Hdr:
      break;
  }
  return std::nullopt;
}

void write_table_csv(const Table& table, std::ostream& out) {
  check_table(table, "-");
  check_coordinates(table, "-");
  write_csv_to(table, out);
  if (!out) throw Error("cannot write CSV: the output stream failed");
}

void check_output_path(const std::string& path, bool streams) {
  io::check_output_target(path, streams, "output");
  if (io::output_target(path).target == io::OutputTarget::Stream) return;  // written in place
  // A missing folder is created when the output is written: probe the nearest folder that exists.
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path probe_at(path);
  while (!probe_at.parent_path().empty() && !fs::exists(probe_at.parent_path(), ec)) probe_at = probe_at.parent_path();
  if (probe_at.string() != path && fs::exists(probe_at, ec) && !fs::is_directory(probe_at, ec))
    io::throw_write_error(path, "'" + probe_at.string() + "' is not a folder");
  io::TempFile probe(probe_at.string());  // created exclusively beside it, removed on scope exit
}

}  // namespace brdfbake
