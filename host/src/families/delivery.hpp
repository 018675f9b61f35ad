// Internal: delivery, how every result becomes a file (tables and cubes, delivery.cpp) with the
// bound it records, shared by the families' write() and the job's manifest. One rounding rule:
// every recorded bound (error_bound, storage_error, integration_error_bound) is its value rounded
// up to three significant digits (bound_text), so that no file or manifest records less than was
// measured.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "brdfbake/environment.hpp"
#include "brdfbake/io.hpp"
#include "brdfbake/tables.hpp"
#include "families/field_error.hpp"
#include "text.hpp"

namespace brdfbake::detail {

// What a family's output may be.
struct OutputFormats {
  std::vector<std::string> extensions;  // lower case with the dot, e.g. ".exr"; the first is the default
  std::string description;              // "table formats (.exr .png .hdr .ktx2 .csv .h)"
};

// bound_text and bounds_text: text.hpp.

// clamp_f16, shared by the table and cube writers: finite values beyond 65504 become +-65504
// (returns how many; NaN and infinity are left for the writer to refuse); record_f16_clamp adds the
// count to `w`'s details and a warning naming `path`, and returns the f16_clamped metadata text;
// with_f16_clamp_error is the storage error measured on the clamped values with the clamping itself
// (relative to the largest value) included.
size_t clamp_to_binary16(std::vector<float>& values);
std::string record_f16_clamp(WriteReport& w, const std::string& path, size_t count, double largest);
double with_f16_clamp_error(double measured, double largest);
// clamp_f16: binary16 outputs clamp values beyond 65504 and record it instead of refusing them.
ParamDef clamp_f16_param();

// ---- Tables ----------------------------------------------------------------------------------------

// The formats every 2-D table family writes.
OutputFormats table_formats();
// The output parameters of table families (symbol for .h, png_range for .png), appended to a schema.
void add_table_output_params(std::vector<ParamDef>& schema);
// Writes a Table result with the request's format and pixel type; `bound` is the table's own
// (integration) bound, to which the storage error is added; a delivered bound above `limit` (the
// request's max_error) is refused before anything is written.
WriteReport write_table_result(const Table& table, const TableRequest& t, const std::string& path,
                               std::optional<double> bound, std::optional<double> limit = std::nullopt);

// A file's bytes made in memory, and what write() would have reported for it.
struct WrittenBytes {
  WriteReport report;
  std::string bytes;
};
// The file write_table_result would write to t.output, made in memory (the same bytes, the same
// report, messages naming t.output), where its format is built there (io encode_table: .exr,
// .ktx2, .csv, .h); std::nullopt, having done nothing, for the others.
std::optional<WrittenBytes> table_result_bytes(const Table& table, const TableRequest& t, std::optional<double> bound,
                                               std::optional<double> limit = std::nullopt);
// write_result's file in memory where the family makes it there (Family::write_bytes), after the
// same finiteness check; std::nullopt: write it. The server's POST /v1/tables sends these bytes
// (runner.cpp, deliver_bytes) without a scratch file.
std::optional<WrittenBytes> write_result_bytes(const BakeResult& r, const TableRequest& t);

// ---- Cubes -----------------------------------------------------------------------------------------

// The containers a cube family writes, and the request's.
OutputFormats cube_formats();
CubeFormat cube_format_of(const TableRequest& t);
CubeWriteOptions cube_write_options_of(const TableRequest& t, const std::string& stem);
// The output parameters of a cube (folder layout, image format, clamp_f16), appended to a schema.
void add_cube_output_params(std::vector<ParamDef>& schema);
// Checks the output's format against a cube output; throws FieldError.
void check_cube_output(const TableRequest& t, const FieldName& name);
// Writes a cube with the request's container and pixel type, refusing texels the pixel type cannot
// hold (binary16 beyond 65504: a real sun) and adding the storage rounding to `bound`.
// pixel astc4x4 / astc6x6: the ASTC block size (4 or 6), else 0; astcenc's effort for them
// (ASTCENC_PRE_MEDIUM: a 256^2 chain in about a second a block size on two cores).
int astc_block_of(const TableRequest& t);
inline constexpr double kAstcQuality = 60.0;

WriteReport write_cube_result(const CubeLevels& cube, const TableRequest& t, const std::string& path,
                              const std::string& stem, std::optional<double> bound);

}  // namespace brdfbake::detail
