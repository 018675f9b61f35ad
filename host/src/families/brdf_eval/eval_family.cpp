// The eval family (kind eval): a BRDF model evaluated at (wi, wo) pairs read from a file (pairs.cpp
// reads and writes them as streams), in chunks through an evaluator of the backend, so a stream's
// memory stays constant whatever its size. Its descriptor, and the registration of the BRDF
// evaluation engine's kernels (kernel.hpp), which the tabulate family (tabulate_family.cpp) shares.
// Engine: names.cpp, material.cpp, evaluator.cpp, tabulate.cpp and kernels/brdf_eval.cl; reference:
// reference.cpp (host/reference/src/brdf_eval.cpp); tests: tests/device/test_brdf_eval.cpp,
// tests/reference/test_brdf_reference.cpp.
#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>

#include "families/brdf_eval/kernel.hpp"
#include "families/brdf_eval/pairs.hpp"
#include "families/family.hpp"
#include "families/kernels.hpp"
#include "families/spec_schema.hpp"
#include "io/atomic_file.hpp"

namespace brdfbake {

namespace detail {
namespace {

// The example request's material: one in memory (read_materials takes JSON text).
constexpr const char* kExampleMaterial =
    R"({"materials": [{"name": "velvet", "model": "gltf-correlated", "baseColor": [0.3, 0.05, 0.1], "roughness": 0.8, "sheenColor": [0.9, 0.3, 0.4], "sheenRoughness": 0.5}]})";

std::vector<std::string> model_names() {
  std::vector<std::string> v;
  for (BrdfModel m : brdf_models()) v.push_back(brdf_model_name(m));
  return v;
}

// The material and model a request names (read from its material file).
struct Chosen {
  NamedMaterial material;
  BrdfModel model = BrdfModel::Disney;
};

Chosen choose_material(const TableRequest& t, const FieldName& name) {
  const std::string path = t.text("material");
  const auto materials = read_materials(path);
  if (!t.find("name") && materials.size() > 1) {
    std::string names;
    for (size_t i = 0; i < materials.size() && i < 8; ++i)
      names += (i ? ", '" : "'") + materials[i].name.substr(0, 60) + "'";
    if (materials.size() > 8) names += " and " + std::to_string(materials.size() - 8) + " more";
    throw FieldError("name", path + " holds " + std::to_string(materials.size()) + " materials; choose one with " +
                                 name("name") + " (" + names + ")");
  }
  Chosen c{find_material(materials, t.text("name"), path), BrdfModel::Disney};
  std::optional<BrdfModel> chosen;
  if (t.find("model")) chosen = brdf_model_from_name(t.text("model"));
  c.model = resolve_model(chosen, c.material);
  return c;
}

// The schema; what it sets of EvalOptions (the material, model and pairs are read by the family).
SpecSchema<EvalOptions> make_eval_schema() {
  using T = ParamType;
  SpecSchema<EvalOptions> s;
  s.param(ParamDef("material", T::Path, "material file: our JSON, or a .gltf").needed())
      .param(ParamDef("name", T::Name, "the material to use when the file holds several"))
      .param(ParamDef("model", T::Name, "the BRDF model").one_of(model_names()).defaults_to("the material's own"))
      .param(
          ParamDef(
              "input", T::Path,
              "pairs: CSV with the header wi_x,wi_y,wi_z,wo_x,wo_y,wo_z, or float32 with binary (- : standard input)")
              .needed())
      .param(ParamDef("binary", T::Flag, "raw little-endian float32: 6 a pair in, 3 a pair out").def(false))
      .bind(&EvalOptions::fast_math, "fast_math",
            ParamDef("fast_math", T::Flag, "build the kernels with -cl-fast-relaxed-math (opt-in)").def(false))
      .common("precision", "precision", [](EvalOptions& o, const TableRequest& t) { o.precision = t.precision; })
      .internal("specialize", "measured by the bench")
      .internal("lanes", "measured by the bench");
  return s;
}

const SpecSchema<EvalOptions>& eval_schema() {
  static const SpecSchema<EvalOptions> s = make_eval_schema();
  return s;
}

EvalOptions eval_options(const TableRequest& t) { return eval_schema().fill(t); }

std::string describe(std::uint64_t pairs, const Chosen& c, const TableRequest& t, const Backend& b,
                     double device_seconds) {
  return std::to_string(pairs) + (pairs == 1 ? " pair, " : " pairs, ") + brdf_model_name(c.model) + ", material '" +
         c.material.name + "', " +
         (b.is_reference() ? std::string("reference (fp64)") : std::string(precision_name(t.precision))) + " on " +
         b.name() + " (device " + fmt_number(device_seconds, "%.3f") + " s)";
}

class EvalFamily final : public Family {
 public:
  std::vector<TableKind> kinds() const override { return {TableKind::Eval}; }
  std::uint64_t estimated_bytes(const TableRequest& t) const override {
    // A job's eval reads every pair first: 6 doubles in, 3 out and the writer's copy (96 bytes a
    // pair), plus the input's bytes. The pairs are counted from the input's size: a float32 pair is
    // 24 bytes, the shortest CSV line ("0,0,1,0,0,1") 12.
    std::error_code ec;
    const std::string input = t.text("input");
    const double bytes =
        input.empty() || input == "-" ? 0.0 : static_cast<double>(std::filesystem::file_size(input, ec));
    const double pairs = ec ? 0.0 : bytes / (t.flag("binary") ? 24.0 : 12.0);
    return static_cast<std::uint64_t>((ec ? 0.0 : bytes) + 96 * pairs) + (std::uint64_t(1) << 20);
  }
  std::string command() const override { return "eval"; }
  // The BRDF evaluation engine's kernel, which the tabulate family runs too.
  void register_kernels(KernelRegistry& r) const override {
    r.add<BrdfEvalKernel>(Platform::OpenCl, [](Backend& b) { return make_opencl_brdf_eval(*b.device()); });
    r.add<BrdfEvalKernel>(Platform::Reference, [](Backend&) { return make_reference_brdf_eval(); });
  }
  TableExample example(TableKind) const override {
    TableExample e;
    e.request.params = {{"material", std::string(kExampleMaterial)}, {"input", std::string("example pairs")}};
    e.pairs = {0.0,  0.0, 1.0,         0.0, 0.0, 1.0,           // normal incidence, mirror
               -0.5, 0.0, 0.866025404, 0.5, 0.0, 0.866025404,   // 30 degrees, mirror
               -0.5, 0.0, 0.866025404, 0.0, 0.5, 0.866025404};  // 30 degrees, out of plane
    return e;
  }
  CommandText command_text() const override {
    return {"evaluate a BRDF model at (wi, wo) pairs, streaming CSV or float32",
            "Evaluate a BRDF at (wi, wo) pairs, streaming CSV or float32",
            "brdfbake eval --material examples/materials.json --name gold -i examples/pairs.csv -o gold_f.csv"};
  }
  bool streams() const override { return true; }
  std::string summary(TableKind) const override {
    return "a BRDF evaluated at (wi, wo) pairs: CSV or float32 in, f (without the cosine) out";
  }

  const std::vector<ParamDef>& schema(TableKind) const override { return eval_schema().schema(); }
  std::vector<SpecField> spec_fields(TableKind) const override { return eval_schema().fields(); }

  void check(TableRequest& t, const FieldName& name) const override {
    try {
      (void)choose_material(t, name);
    } catch (const FieldError&) {
      throw;
    } catch (const Error& e) {
      throw FieldError("material", e.what());
    }
  }

  std::string default_output(const TableRequest& t) const override {
    std::string stem = "eval";
    if (t.find("model")) stem += "_" + t.text("model");
    if (t.find("name")) stem += "_" + t.text("name");
    return stem + (t.flag("binary") ? ".f32" : ".csv");
  }
  OutputFormats formats(const TableRequest& t) const override {
    if (t.flag("binary")) return {{".f32", ".bin", ".raw", ""}, "float32 (any file name)"};
    return {{".csv", ""}, "CSV (any file name)"};
  }
  // The output's bytes are chosen by `binary`, not by the file name.
  void check_output(const TableRequest& t, const FieldName&) const override {
    if (!t.format.empty()) throw FieldError("format", "eval's output is CSV, or float32 with binary: give no format");
  }

  BakeResult bake(const TableRequest& t, Backend& backend, const BakeInputs& inputs,
                  const BakeProgress&) const override {
    const Chosen c = choose_material(t, [](const std::string& f) { return f; });
    std::unique_ptr<PairEvaluator> ev;
    auto get = [&]() -> PairEvaluator& {
      if (!ev) ev = make_evaluator(backend, c.model, {c.material.params}, eval_options(t));
      return *ev;
    };
    EvalResult res;
    double device_seconds = 0.0;
    if (inputs.pairs) {  // in memory: the same chunks through the same evaluator
      res.pairs = inputs.pair_count;
      res.values.assign(3 * inputs.pair_count, 0.0);
      const size_t chunk = get().chunk_pairs();
      for (size_t at = 0; at < inputs.pair_count; at += chunk) {
        const size_t n = std::min(chunk, inputs.pair_count - at);
        EvalTiming timing;
        get().eval(inputs.pairs + 6 * at, n, res.values.data() + 3 * at, &timing);
        device_seconds += timing.device_seconds;
      }
    } else {
      PairInput in(t.text("input"));
      res.pairs = stream_pairs(
          in, t.flag("binary"), get, &device_seconds,
          [&](const double* f, size_t n) { res.values.insert(res.values.end(), f, f + 3 * n); }, kMaxPairsInMemory);
    }
    res.material = c.material.name;
    res.metadata = {{"model", brdf_model_name(c.model)}, {"material", material_to_json(c.material)}};
    BakeResult r;
    r.error_bound_definition =
        "not measured (f at the given directions; the kernels' agreement with the reference "
        "is in docs/BENCHMARKS.md, \"Bulk BRDF evaluation\")";
    r.device_seconds = device_seconds;
    r.summary = describe(res.pairs, c, t, backend, device_seconds);
    r.artifact = std::move(res);
    return r;
  }

  WriteReport write(const BakeResult& r, const TableRequest& t, const std::string& path) const override {
    const EvalResult& e = *r.eval();
    std::string bytes;
    format_results(e.values.data(), e.values.size() / 3, t.flag("binary"), true, bytes);
    io::write_file_atomically(path, bytes);
    WriteReport w;
    w.encoding = t.flag("binary") ? "float32" : "decimal text, 9 significant digits";
    return w;
  }
};

}  // namespace

const Family& eval_family() {
  static const EvalFamily f;
  return f;
}

}  // namespace detail

EvalStreamResult eval_stream(const TableRequest& t, Backend& backend, const std::string& input,
                             const std::string& output) {
  using namespace detail;
  const Chosen c = choose_material(t, [](const std::string& f) { return f; });
  std::unique_ptr<PairEvaluator> ev;
  auto get = [&]() -> PairEvaluator& {
    if (!ev) ev = make_evaluator(backend, c.model, {c.material.params}, eval_options(t));
    return *ev;
  };
  PairInput in(input);
  io::OutputStream out(output);
  EvalStreamResult res;
  bool first = true;
  std::string bytes;
  res.pairs = stream_pairs(in, t.flag("binary"), get, &res.device_seconds, [&](const double* f, size_t n) {
    format_results(f, n, t.flag("binary"), first, bytes);
    first = false;
    out.write(bytes.data(), bytes.size());
  });
  out.commit();
  res.summary = describe(res.pairs, c, t, backend, res.device_seconds);
  return res;
}

}  // namespace brdfbake
