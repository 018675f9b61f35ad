// Writing tables to files. Every writer writes to a temporary name in the destination folder and
// renames it when complete, so a failed write leaves no partial file; errors throw brdfbake::Error.
#pragma once

#include <optional>
#include <ostream>
#include <string>

#include "brdfbake/table.hpp"

namespace brdfbake {

enum class TableFormat { Exr, Png, Hdr, Ktx2, Csv, CHeader };
// F16 / F32: IEEE half / float per channel. R11G11B10: OpenGL's packed unsigned float
// GL_R11F_G11F_B10F (no alpha, no sign, 6/6/5 mantissa bits, max 65024/65024/64512), written to
// KTX1 cubemaps (Filament's IBL format) only; tables refuse it.
enum class PixelType { F16, F32, R11G11B10 };

// The format named by a file's extension (.exr .png .hdr .ktx2 .csv .h), or by a --format name
// ("exr", "png", "hdr", "ktx2", "csv", "h"). Throws brdfbake::Error for anything else.
TableFormat table_format_from_path(const std::string& path);
TableFormat table_format_from_name(const std::string& name);

struct TableWriteOptions {
  PixelType pixel = PixelType::F16;  // for .ktx2 and .h; .exr is always float32, .png 16-bit
  std::string symbol;                // C identifier for .h (default: derived from the file name)
};

// Writes `table` to `path` in `format`, atomically.
void write_table(const Table& table, const std::string& path, TableFormat format,
                 const TableWriteOptions& options = {});
// The bytes write_table would write to `path`, made in memory, for the formats of one file built
// there (.exr, .ktx2, .csv, .h); std::nullopt for .png and .hdr (and its JSON sidecar), which only
// write_table writes. Errors name `path` as write_table's do.
std::optional<std::string> encode_table(const Table& table, const std::string& path, TableFormat format,
                                        const TableWriteOptions& options = {});
// Throws the Error a write to `path` would give (missing folder, no permission, a path through a
// regular file), by creating and removing a temporary file beside it: commands call it before
// slow work so that a bad output path fails at once. A FIFO, a device or standard output named as
// a file (/dev/stdout) is refused (bad input: the write would replace it) unless the output
// `streams` (CSV tables, eval's output), which writes it in place (docs/RELIABILITY.md, "Special files").
void check_output_path(const std::string& path, bool streams = false);

// CSV to a stream (for `-o -`): '#' metadata lines, a header row naming every column, one row per cell.
void write_table_csv(const Table& table, std::ostream& out);

}  // namespace brdfbake
