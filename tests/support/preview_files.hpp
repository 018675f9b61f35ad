// Files and wiring the preview's device tests share: a fresh temp folder, a white furnace environment
// file, the shared maps, a job run on the test's own backend.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "brdfbake/backend.hpp"
#include "brdfbake/job.hpp"
#include "support/temp_dir.hpp"

#ifndef BRDFBAKE_SHARED_DIR
#define BRDFBAKE_SHARED_DIR "../shared"
#endif

namespace brdfbake::test {

// A fresh, empty folder `program`/`name` in the test's temporary folder (removed when the test ends).
inline std::filesystem::path temp_dir(const std::string& program, const std::string& name) {
  return test_temp_dir(program + "/" + name);
}

// A uniform environment of radiance 1 as RGBE with flat scanlines (0x80 0x80 0x80 0x81 is exactly
// 1.0), 128 x 64: its chain is 1.0 in every texel, exact in f16 and through Babylon.js's RGBD (D = 1).
inline std::filesystem::path white_hdr(const std::filesystem::path& dir) {
  std::ofstream f(dir / "white.hdr", std::ios::binary);
  f << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 64 +X 128\n";
  for (int i = 0; i < 128 * 64; ++i) f.write("\x80\x80\x80\x81", 4);
  return dir / "white.hdr";
}

// A map of ../shared/envmaps (tests skip with a message where it is absent).
inline std::string shared_envmap(const std::string& name) {
  return (std::filesystem::path(BRDFBAKE_SHARED_DIR) / "envmaps" / name).string();
}

// Run options that run a job's tables on `backend` (borrowed, not owned).
inline RunOptions on_backend(Backend& backend) {
  RunOptions ro;
  ro.backend = [&backend](const std::string&) { return std::shared_ptr<Backend>(&backend, [](Backend*) {}); };
  return ro;
}

}  // namespace brdfbake::test
