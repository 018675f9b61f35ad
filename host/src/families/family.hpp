// Internal: one descriptor per table family, the single home of everything the front ends need to
// know about it: its kinds, its typed schema, its rules across fields, its default file name, the
// formats it writes, how it bakes on a backend and how it writes the result. The job runner, the
// scene planner's requests, every command-line command, the server and the Python package reach a
// family only through its descriptor (docs/ARCHITECTURE.md, "How to add a table family").
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "brdfbake/output_checks.hpp"
#include "brdfbake/tables.hpp"
#include "families/delivery.hpp"
#include "families/field_error.hpp"
#include "text.hpp"

namespace brdfbake::detail {

// A family's command-line command as the help shows it.
struct CommandText {
  std::string usage;        // its line in `brdfbake --help`
  std::string description;  // the first line of `brdfbake <command> --help`
  std::string example;      // one example command line for `brdfbake <command> --help`
};

// One field of a family's spec struct and what sets it (families/spec_schema.hpp).
struct SpecField {
  std::string field;      // the struct's member, e.g. "width"
  std::string parameter;  // the schema parameter, or the field every table has ("precision", "kind"),
                          // that sets it; empty when none does (`reason` says why)
  std::string reason;
};

class KernelRegistry;

class Family {
 public:
  virtual ~Family() = default;

  virtual std::vector<TableKind> kinds() const = 0;
  // A kind's name in jobs, requests and options ("ggx-multiscatter"); a family of one kind is named
  // as its command.
  virtual std::string kind_name(TableKind) const { return command(); }
  // The command-line command that bakes one request of the family ("lut", "fresnel", ...).
  virtual std::string command() const = 0;
  virtual CommandText command_text() const = 0;
  virtual std::string summary(TableKind kind) const = 0;
  virtual const std::vector<ParamDef>& schema(TableKind kind) const = 0;
  // The pixel type written when the request names none.
  virtual std::string default_pixel() const { return "f16"; }
  virtual bool uses_environment() const { return false; }
  // Whether baking the validated request computes on the OpenCL device (SH alone runs on the host):
  // front ends start opening the device while they read the inputs (Backend::prepare).
  virtual bool needs_device(const TableRequest&) const { return true; }
  // Whether the command line streams it (standard input to standard output) instead of baking it
  // whole (eval_stream).
  virtual bool streams() const { return false; }

  // The family's rules across fields, after every field passed its schema check and the defaults
  // were filled in; may resolve dependent defaults (t.set). Throws FieldError.
  virtual void check(TableRequest& t, const FieldName& name) const = 0;
  virtual std::string default_output(const TableRequest& t) const = 0;
  virtual OutputFormats formats(const TableRequest& t) const = 0;
  // Checks that the output's extension and format fit the request; throws FieldError("output" or
  // "format", ...).
  virtual void check_output(const TableRequest& t, const FieldName& name) const;
  // The files a validated request writes beside its output (the preview's NAME.json and EXRs) and
  // reads beside its path parameters (a bake folder's files): every output rule holds for them as
  // for the output (brdfbake/output_checks.hpp). `field` is the parameter they belong to, `beside`
  // says which of its files it is.
  virtual std::vector<RequestFile> outputs_beside(const TableRequest&) const { return {}; }
  virtual std::vector<RequestFile> inputs_beside(const TableRequest&) const { return {}; }

  // Every field of the spec struct a kind bakes from, with the parameter that sets it (the spec's
  // SpecSchema): a field added to the struct without one fails a test. Empty for a family without a
  // SpecSchema yet.
  virtual std::vector<SpecField> spec_fields(TableKind) const { return {}; }
  // A small, fast, valid request of the kind (not yet validated), with what it reads beside its
  // parameters: the device tests, the parity tests and the server's warm-up bake it.
  virtual TableExample example(TableKind kind) const = 0;
  // Registers the family's kernel implementations, one per platform (families/kernels.hpp).
  virtual void register_kernels(KernelRegistry&) const {}

  virtual BakeResult bake(const TableRequest& t, Backend& backend, const BakeInputs& inputs,
                          const BakeProgress& progress) const = 0;
  virtual WriteReport write(const BakeResult& r, const TableRequest& t, const std::string& path) const = 0;
  // The file write() makes at t.output, made in memory where the family can (a table in a format
  // built there: table_result_bytes); std::nullopt: write() it. Tables override it.
  virtual std::optional<WrittenBytes> write_bytes(const BakeResult&, const TableRequest&) const { return std::nullopt; }

  // About how many bytes a bake of the validated request holds at its peak, host and device
  // together: the result, its device buffers and the copy the writer encodes (the environment image
  // excluded: environment_bytes). Computed from the parameters alone, before anything is allocated,
  // so that the server can refuse what would not fit (estimate_table_bytes).
  virtual std::uint64_t estimated_bytes(const TableRequest& t) const = 0;
};

// The family that bakes `kind`.
const Family& family_of(TableKind kind);
// Every family, in the order of table_kinds() (registry.cpp: the one list of families).
const std::vector<const Family*>& families();

// ---- Helpers the families share ----------------------------------------------------------------

std::string lower_extension(const std::string& path);
// The extension the request's output has (or its format names, e.g. "dds-legacy" -> ".dds").
std::string output_extension(const TableRequest& t);
// A table output (DFG, Fresnel, thin film, tabulate grids): format from `format` or the extension.
TableFormat table_output_format(const TableRequest& t);
PixelType pixel_of(const TableRequest& t);
Rgb rgb_of(const ParamValue& v);
// A value as part of a file name: "1.5", "0.9_0.6_0.2".
std::string name_part(const ParamValue& v);
// What a shader's bilinear lookup of `table` (texel i's centre at u = (i + 0.5) / width, clamp to
// edge) misses, over probe points at lookup coordinates us x vs against `probe`, the table's quantity
// evaluated there (probe.width = us.size(), probe.height = vs.size()); abs below 1, relative above.
struct LookupError {
  double interior = 0.0;  // between the outermost texel centres: the interpolation error
  double edge = 0.0;      // within half a texel of an edge, where clamp to edge holds the outer texel
};
LookupError bilinear_lookup_error(const Table& table, const std::vector<double>& us, const std::vector<double>& vs,
                                  const Table& probe);
// The lookup coordinates where a table's lookup error is measured: the lines between texel centres
// (i / n) and points closing in on both edges.
std::vector<double> probe_coordinates(int n);

// The peak bytes of a float grid of `cells` cells and `channels` channels: the host table, its
// device buffer and the writer's copy (4 bytes a value each), and the cells' coordinates.
std::uint64_t grid_bytes(double cells, double channels);

// Radiance near FLT_MAX (docs/RELIABILITY.md, "Outputs"): the device sums radiance in fp32, where a
// sum of values near 3.4e38 overflows to infinity. An environment whose largest value exceeds
// kRadianceHeadroom is baked from a copy scaled by a power of two (exact in binary floating point:
// only exponents change), and the results are scaled back in double. Returns the environment to
// bake (`in` itself, or `storage` holding the copy) and sets *scale to the factor the results are
// multiplied by (1 when no copy was made).
inline constexpr double kRadianceHeadroom = 4294967296.0;  // 2^32
const EnvImage& headroom_environment(const EnvImage& in, EnvImage& storage, double* scale);
// "12 NaN, 0 infinite and 3 negative values replaced" for an environment --sanitize changed, else "".
std::string sanitize_note(const EnvImage& env);

}  // namespace brdfbake::detail
