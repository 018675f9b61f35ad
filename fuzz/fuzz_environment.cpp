// The environment loader, through its public entry point load_environment, with the input written
// to a file in a folder of our own. The first byte chooses what the rest becomes:
//   0: an equirect or cross image (.hdr), 1: a KTX2 cube, 2: six face files (.hdr, the same bytes
//   each, through the "{face}" pattern), 3: a KTX2 cube with --sanitize; bit 7: --sanitize.
// Radiance headers that promise more than 2^20 pixels are skipped: the memory budget checked from
// image headers lands with the image-reader merge (docs/RELIABILITY.md, "Untrusted input"); until
// then such a header makes the reader allocate what it promises. OpenEXR (fuzzed upstream by
// OSS-Fuzz) gets its own harness with the new reader.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "brdfbake/environment.hpp"
#include "fuzz.hpp"

namespace {

// The pixels a Radiance header's resolution line ("-Y 512 +X 1024") promises, or 0.
double radiance_pixels(const std::string& bytes) {
  const size_t at = bytes.find("\n\n");
  if (at == std::string::npos) return 0;
  const std::string line = bytes.substr(at + 2, 64);
  char a[3] = {0}, b[3] = {0};
  long h = 0, w = 0;
  if (std::sscanf(line.c_str(), "%2s %ld %2s %ld", a, &h, b, &w) != 4) return 0;
  return double(h) * double(w);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace brdfbake;
  namespace fs = std::filesystem;
  if (size < 1) return 0;
  const fs::path& dir = fuzz::scratch_dir("env");
  const std::string bytes = fuzz::text(data + 1, size - 1);
  const int mode = data[0] & 3;
  EnvLoadOptions options;
  options.sanitize = (data[0] & 0x80) != 0 || mode == 3;
  options.builtin_width = 16;
  if (mode != 1 && mode != 3 && (radiance_pixels(bytes) > double(1 << 20) || radiance_pixels(bytes) < 0)) return 0;
  std::string spec;
  if (mode == 0) {
    spec = (dir / "env.hdr").string();
    std::ofstream(spec, std::ios::binary) << bytes;
  } else if (mode == 2) {
    for (const char* face : {"px", "nx", "py", "ny", "pz", "nz"})
      std::ofstream(dir / (std::string("face_") + face + ".hdr"), std::ios::binary) << bytes;
    spec = (dir / "face_{face}.hdr").string();
  } else {
    spec = (dir / "env.ktx2").string();
    std::ofstream(spec, std::ios::binary) << bytes;
  }
  fuzz::expect_answer([&] {
    const EnvImage env = load_environment(spec, options);
    // What the loader accepts is finite and non-negative (refused or sanitized otherwise).
    for (float v : env.rgb)
      if (!(v >= 0.0f) || !std::isfinite(v)) __builtin_trap();
  });
  return 0;
}
