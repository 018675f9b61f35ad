// Table kinds and the family registry's public face: what a table request holds, the typed schema
// of every kind, validation, and one call that bakes any kind on any backend and one that writes the
// result. The job runner, the command-line tool, the server and the Python package all go through
// these calls; each family has one home (host/src/families/, docs/ARCHITECTURE.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "brdfbake/backend.hpp"
#include "brdfbake/brdf.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/error.hpp"
#include "brdfbake/params.hpp"
#include "brdfbake/preview.hpp"
#include "brdfbake/table.hpp"

namespace brdfbake {

// ---- Kinds ---------------------------------------------------------------------------------------

enum class TableKind {
  Ggx,              // DFG: scale, bias, diffuse (brdfbake/dfg_lut.hpp)
  GgxMultiscatter,  // DFG: bias, albedo, diffuse (energy compensation)
  Charlie,          // DFG: Charlie sheen albedo
  Fresnel,          // a Fresnel reflectance table (brdfbake/fresnel.hpp)
  ThinFilm,         // thin-film interference Fresnel over (cos_theta, film thickness)
  Prefilter,        // a prefiltered radiance mip chain of the environment (brdfbake/environment.hpp)
  Irradiance,       // diffuse irradiance of the environment: SH coefficients (and a cube)
  Eval,             // a BRDF evaluated at (wi, wo) pairs read from a file (brdfbake/brdf.hpp)
  Tabulate,         // a BRDF tabulated: MERL, grid, directional albedo or slice
  Preview,          // material spheres: the split-sum render against the reference (brdfbake/preview.hpp)
};
// "ggx" | "ggx-multiscatter" | "charlie" | "fresnel" | "thin-film" | "prefilter" | "irradiance" |
// "eval" | "tabulate"; throws Error naming the known kinds otherwise.
TableKind table_kind_from_name(const std::string& name);
const char* table_kind_name(TableKind kind);
const std::vector<TableKind>& table_kinds();
// The command-line command that bakes one table of the kind ("lut" for the DFG kinds, "fresnel", ...).
std::string table_kind_command(TableKind kind);
// The one-table commands of the command-line tool, one per family, in the order of table_kinds():
// its name ("lut"), its line in `brdfbake --help`, and the description and example of
// `brdfbake <name> --help`.
struct TableCommandText {
  std::string name, usage, description, example;
};
const std::vector<TableCommandText>& table_commands();
// One line: what the kind bakes.
std::string table_kind_summary(TableKind kind);
// Whether this build bakes `kind`; when not, *why says what is missing.
bool table_kind_available(TableKind kind, std::string* why = nullptr);
// Whether the kind reads the job's environment (prefilter, irradiance).
bool table_kind_uses_environment(TableKind kind);
// Whether the command line streams the kind from standard input to standard output (eval).
bool table_kind_streams(TableKind kind);
// The pixel type ("f16" or "f32") written when a request names none.
std::string table_kind_default_pixel(TableKind kind);

// A kind this build cannot bake: the job stops before anything is written (exit 1: the request is
// valid, this build lacks what it needs).
class NotAvailableError : public RuntimeFailure {
 public:
  explicit NotAvailableError(const std::string& m) : RuntimeFailure(m) {}
};

// ---- Requests ------------------------------------------------------------------------------------

// Which rule asked for a table, what for, and for which materials.
struct Request {
  std::string rule;                    // e.g. "metallic-roughness", "KHR_materials_sheen"
  std::string purpose;                 // what the renderer does with the table
  std::vector<std::string> materials;  // material labels, "#3 Name"
  std::string note;                    // e.g. the clearcoat roughness range
};

// One table to bake: its kind, its own parameters (table_schema(kind)) and the fields every kind
// shares.
struct TableRequest {
  TableKind kind = TableKind::Ggx;
  Params params;  // the kind's parameters; validate_table fills defaults in schema order
  Precision precision = Precision::Fp32;
  std::string device;       // selector ("" = the job's / the default), or "reference"
  std::string environment;  // prefilter, irradiance ("" = the job's)
  std::string output;       // file path (relative to a job's output folder)
  std::string format;       // "" = from the output's extension
  std::string pixel;        // f16 | f32 (.ktx2, .h and cube containers); "" = the kind's default
  std::vector<Request> requested_by;
  // The parameters the request named itself (validate_table records them before filling defaults).
  std::vector<std::string> given;

  const ParamValue* find(const std::string& name) const;
  bool was_given(const std::string& name) const;
  double number(const std::string& name, double fallback = 0.0) const;
  std::string text(const std::string& name, const std::string& fallback = {}) const;
  bool flag(const std::string& name, bool fallback = false) const;
  std::vector<double> numbers(const std::string& name) const;  // Rgb (3), Range (2), IntList
  void set(const std::string& name, ParamValue value);         // sets or replaces
  // The materials of every request, in order of first appearance, without repeats.
  std::vector<std::string> materials() const;
};

// A small, fast request of a kind that validates, and what it reads beside its parameters: the
// device tests, the parity tests and the server's warm-up bake it, so that a new family is covered
// by them without a new case.
struct TableExample {
  TableRequest request;       // validated; environment kinds name "builtin:sun" (load_environment)
  std::vector<double> pairs;  // eval: 6 values a pair (BakeInputs::pairs); empty otherwise
};
TableExample table_kind_example(TableKind kind);

// ---- Schemas and validation ----------------------------------------------------------------------

// The parameters of a kind, in canonical order: types, ranges, defaults and help, written once.
const std::vector<ParamDef>& table_schema(TableKind kind);
// The fields every table has beside its parameters, in job spelling.
const std::vector<std::string>& table_common_fields();
// Every kind with its schema (schema_json's objects) as `brdfbake kinds --json` prints it:
// {"kinds": [{"kind", "command", "summary", "environment", "default_pixel", "parameters"}, ...],
//  "common_fields": [...]}.
std::string table_kinds_json(int indent = -1);

// How validation names a field in its messages: in a job "<prefix>.<field>" (e.g.
// "job.json: tables[0].size: ..."), on the command line the option as the user types it
// ("--size: ...").
struct FieldNaming {
  std::string prefix;  // job: "job.json: tables[0]"
  bool cli = false;    // command line: "--size"
  std::string field(TableKind kind, const std::string& name) const;
};

// Checks a request field by field (types and ranges from the schema, unknown parameters, the
// family's own rules across fields), fills the defaults in canonical order, the default output name
// when none is given, and checks the output's name and format. Throws Error naming the field.
void validate_table(TableRequest& request, const FieldNaming& naming = {});
// The file name a request is written to when it names none, e.g. "dfg_ggx_multiscatter_128.exr".
std::string default_table_output(const TableRequest& request);
// The parameter of a kind's face or cell count along its first axis, as labels and estimates read it:
// "chain_size" for a prefiltered chain, "size" for the 1-D and 2-D tables (a kind may have none).
const char* table_size_param(TableKind kind);
// A key equal for requests that bake the same data (output fields aside).
std::string table_bake_key(const TableRequest& request);
// About how many bytes baking a validated request holds at its peak, host and device together (the
// result, its device buffers and the writer's copy; the environment image excluded), computed from
// the parameters before anything is allocated. The server refuses requests that would not fit.
std::uint64_t estimate_table_bytes(const TableRequest& request);

// ---- Baking and writing --------------------------------------------------------------------------

// What an eval request produced: f (without the cosine) at every pair, 3 values (r, g, b) a pair.
struct EvalResult {
  std::uint64_t pairs = 0;
  std::vector<double> values;
  std::string material;
  Metadata metadata;
};

// What one bake produced.
struct BakeResult {
  TableKind kind = TableKind::Ggx;
  std::variant<std::monostate, Table, CubeLevels, IrradianceResult, MerlTable, EvalResult, PreviewResult> artifact;
  std::optional<double> error_bound;   // measured; empty where the family measures none
  std::string error_bound_definition;  // what the bound measures
  Params parameters;                   // as baked: every parameter, resolved defaults included
  Metadata details;                    // what else the family reports (channels, levels, ...)
  // What the values hold that their user must know (e.g. reflectance above 1): delivered with the
  // write report's warnings to every front end (deliver_result).
  std::vector<std::string> warnings;
  std::string device;           // the backend's name ("reference" for the oracle)
  std::string summary;          // one line for people: what was baked, how well, how fast
  double seconds = 0.0;         // wall time of the bake
  double device_seconds = 0.0;  // kernel time (0 on the reference)

  const Table* table() const { return std::get_if<Table>(&artifact); }
  const CubeLevels* cube() const { return std::get_if<CubeLevels>(&artifact); }
  const IrradianceResult* irradiance() const { return std::get_if<IrradianceResult>(&artifact); }
  const MerlTable* merl() const { return std::get_if<MerlTable>(&artifact); }
  const EvalResult* eval() const { return std::get_if<EvalResult>(&artifact); }
  const PreviewResult* preview() const { return std::get_if<PreviewResult>(&artifact); }
};

// What a bake reads beside its parameters.
struct BakeInputs {
  const EnvImage* environment = nullptr;  // prefilter, irradiance
  // Called once the bake no longer reads the environment's pixels (prefilter: after the conversion
  // to a cube), so that a caller who owns them and needs them no more can free them; may be empty,
  // may never be called.
  std::function<void()> release_environment;
  // eval: pairs already in memory (6 values a pair: wi, wo), read instead of the `input` file (the
  // Python package's arrays).
  const double* pairs = nullptr;
  std::size_t pair_count = 0;
  // Where a bake may put files of its own for the time it runs (the preview's first bake): a folder
  // that exists; "" = the system's temporary folder. A job gives its staging folder and the server
  // its DATA/tmp, so that nothing is written outside what they own and a killed run's leftovers go
  // with the folder they are in.
  std::string scratch_dir;
};

// Fraction done (0..1) and a short label of the step ("level 2/5").
using BakeProgress = std::function<void(double fraction, const std::string& step)>;

// Throws Error when `backend` cannot bake `request` at all (fp64 asked of a device without it),
// naming the device: front ends call it before slow work (loading an environment).
void check_backend(const TableRequest& request, Backend& backend);

// Whether baking the validated request computes on an OpenCL device (an irradiance request for SH
// alone does not): front ends call Backend::prepare for those before reading inputs.
bool table_needs_device(const TableRequest& request);

// Bakes a validated request on `backend`. Throws Error for what the backend cannot do (e.g. a
// reference prefilter of a large cube, naming the limit), Cancelled when a stop is requested
// (brdfbake/cancel.hpp; checked at every progress report).
BakeResult bake_table(const TableRequest& request, Backend& backend, const BakeInputs& inputs = {},
                      const BakeProgress& progress = {});
// What writing a result stored. The bound a file records is on |stored value - converged value|:
// the result's own bound (its integration) plus what the format's encoding adds, measured on the
// values the file stores (docs/CONVENTIONS.md, "Error bounds").
struct WriteReport {
  std::optional<double> error_bound;  // delivered; empty where the family measures none
  double storage_error = 0.0;         // what the encoding added (0 for float32 and exact text)
  std::string encoding;               // e.g. "binary16 (round to nearest even)"
  Metadata details;                   // e.g. png_scale, clamped values
  std::vector<std::string> warnings;  // what was changed on the way to the file (clamp_f16): front ends show them
};

// A bound as files record it: rounded up to three significant digits, so that the text is never
// below the bound ("1.74e-05" for 1.7301e-05). The server's X-Brdfbake-Error-Bound says the same.
std::string error_bound_text(double bound);

// Writes a result to `path` in the request's format, atomically (a failure leaves nothing); "-"
// writes a table as CSV to standard output. A value the format cannot hold is refused with a
// message naming the option that fixes it (a 16-bit PNG outside [0, 1] unless png_range says
// otherwise; binary16 beyond 65504 unless clamp_f16 is set, which clamps to 65504 and records it;
// NaN or infinity anywhere).
WriteReport write_result(const BakeResult& result, const TableRequest& request, const std::string& path);

// The eval kind streamed: pairs read from `input` ("-": standard input) and results written chunk by
// chunk to `output` ("-": standard output; a file is written to a temporary and renamed at the end),
// so memory stays constant whatever the input's size. The bytes are those write_result writes.
struct EvalStreamResult {
  std::uint64_t pairs = 0;
  double device_seconds = 0.0;
  std::string summary;
};
EvalStreamResult eval_stream(const TableRequest& request, Backend& backend, const std::string& input,
                             const std::string& output);

}  // namespace brdfbake
