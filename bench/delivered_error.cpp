// What a user's file delivers: for each DFG kind x size x storage, the bound on |stored - converged|
// the file records (integration + storage, measured on the stored values) and what a bilinear lookup
// adds between texel centres and at the edges; the configurations engines ship; and, when cmgen is
// installed, the error of Filament's own table against our converged reference.
//
//   build/bench/delivered_error [--device SELECTOR]     (prints Markdown for docs/BENCHMARKS.md)
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "brdfbake/backend.hpp"
#include "brdfbake/dfg_lut.hpp"
#include "brdfbake/tables.hpp"

namespace fs = std::filesystem;
using namespace brdfbake;

namespace {

struct Storage {
  const char* name;
  const char* file;
  const char* pixel;
};
const Storage kStorages[] = {{"float32 (.exr)", "t.exr", "f32"},
                             {"binary16 (.ktx2)", "t.ktx2", "f16"},
                             {"16-bit PNG (scaled)", "t.png", "f16"},
                             {"RGBE (.hdr)", "t.hdr", "f16"}};

struct Row {
  double delivered = 0, interior = 0, edge = 0;
};

Row measure(Backend& backend, TableKind kind, int size, const Storage& s, const fs::path& dir) {
  TableRequest t;
  t.kind = kind;
  t.params = {{"size", double(size)}};
  t.pixel = s.pixel;
  t.output = (dir / s.file).string();
  if (std::string(s.file) == "t.png") t.params.push_back({"png_range", std::string("scale")});
  validate_table(t);
  const BakeResult r = bake_table(t, backend);
  const WriteReport w = write_result(r, t, t.output);
  Row row;
  row.delivered = w.error_bound.value_or(-1);
  row.interior = std::stod(r.table()->meta("interpolation_error"));
  row.edge = std::stod(r.table()->meta("edge_error"));
  return row;
}

// Filament's DFG table (cmgen --ibl-dfg-multiscatter) against the converged reference at its texel
// centres: its x channel against our bias, y against albedo; both row orders are tried and the
// better one is reported (the file's row order is not documented).
void cmgen_row(const fs::path& dir, int size) {
  if (std::system("command -v cmgen >/dev/null 2>&1") != 0) {
    std::printf("\n(cmgen not installed: Filament's own table not measured)\n");
    return;
  }
  const fs::path exr = dir / "filament_dfg.exr";
  const std::string cmd = "cmgen --quiet --ibl-dfg=" + exr.string() +
                          " --ibl-dfg-multiscatter --size=" + std::to_string(size) + " >/dev/null 2>&1";
  if (std::system(cmd.c_str()) != 0 || !fs::exists(exr)) {
    std::printf("\n(cmgen failed to write its DFG table)\n");
    return;
  }
  auto in = OIIO::ImageInput::open(exr.string());
  if (!in) return;
  const OIIO::ImageSpec spec = in->spec();
  std::vector<float> px(size_t(spec.width) * size_t(spec.height) * size_t(spec.nchannels));
  in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data());
  in->close();
  LutSpec ref;
  ref.kind = LutKind::GgxMultiscatter;
  ref.width = spec.width;
  ref.height = spec.height;
  const Table truth = bake_lut_reference(ref);
  double best = HUGE_VAL;
  const char* order = "";
  for (int flip = 0; flip < 2; ++flip) {
    double worst = 0;
    for (int j = 0; j < spec.height; ++j)
      for (int i = 0; i < spec.width; ++i)
        for (int c = 0; c < 2; ++c) {
          const int row = flip ? spec.height - 1 - j : j;
          const double v = px[(size_t(row) * size_t(spec.width) + size_t(i)) * size_t(spec.nchannels) + size_t(c)];
          worst = std::max(worst, std::fabs(v - double(truth.at(i, j, c))));
        }
    if (worst < best) {
      best = worst;
      order = flip ? "row 0 = roughness 1" : "row 0 = roughness 0";
    }
  }
  std::printf(
      "\nFilament's table (`cmgen --ibl-dfg-multiscatter --size=%d`, float EXR, %s): max |value - "
      "converged| at its texel centres = %.2g (channels bias, albedo)\n",
      size, order, best);
}

}  // namespace

int main(int argc, char** argv) {
  std::string selector;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--device") selector = argv[i + 1];
  auto backend = Backend::open(selector);
  const fs::path dir = fs::temp_directory_path() / ("brdfbake-delivered-bench-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::printf("device: %s\n\n", backend->name().c_str());
  std::printf(
      "| kind | size | storage | stored within (file's error_bound_mixed) | bilinear between centres | bilinear at the "
      "edges "
      "|\n");
  std::printf("|---|---:|---|---:|---:|---:|\n");
  for (TableKind kind : {TableKind::Ggx, TableKind::GgxMultiscatter, TableKind::Charlie})
    for (int size : {16, 32, 64, 128})
      for (const Storage& s : kStorages) {
        const Row r = measure(*backend, kind, size, s, dir);
        std::printf("| %s | %d | %s | %.2g | %.2g | %.2g |\n", table_kind_name(kind), size, s.name, r.delivered,
                    r.interior, r.edge);
      }
  std::printf("\nThe configurations engines ship, baked by brdfbake:\n\n");
  std::printf(
      "| engine configuration | our kind | stored within | bilinear between centres | at the edges "
      "|\n|---|---|---:|---:|---:|\n");
  const struct {
    const char* engine;
    TableKind kind;
    int size;
    int storage;
  } engines[] = {{"three.js 16² RG16F", TableKind::Ggx, 16, 1},
                 {"Bevy 64² (RGBA16F)", TableKind::GgxMultiscatter, 64, 1},
                 {"Filament 128² RGB16F", TableKind::GgxMultiscatter, 128, 1},
                 {"Unreal 32² fp32", TableKind::Ggx, 32, 0}};
  for (const auto& e : engines) {
    const Row r = measure(*backend, e.kind, e.size, kStorages[e.storage], dir);
    std::printf("| %s | %s %d² %s | %.2g | %.2g | %.2g |\n", e.engine, table_kind_name(e.kind), e.size,
                kStorages[e.storage].name, r.delivered, r.interior, r.edge);
  }
  cmgen_row(dir, 128);
  fs::remove_all(dir);
  return 0;
}
