// A real Filament program: loads a KTX1 file with Filament's own image::KtxBundle (Debian
// libfilament-dev 1.9), reads its 9 SH coefficients with getSphericalHarmonics() and every blob of
// every level, maps the header with image::KtxUtility as Filament's texture loader does, and prints
// what it found as JSON on standard output:
//   {"ok": true, "cubemap": true, "levels": 3, "width": 64, "sh": [27 numbers] | null,
//    "blob_bytes": [[per face], ...], "pixel_data_type": N, "pixel_data_format": N, "texture_format": N}
// Exit code 1 (with the reason on standard error) when the file cannot be read.
#include <image/KtxBundle.h>
#include <image/KtxUtility.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: filament_ktx_check FILE.ktx\n");
    return 2;
  }
  std::ifstream in(argv[1], std::ios::binary);
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 64) {
    std::fprintf(stderr, "%s: too small for a KTX file\n", argv[1]);
    return 1;
  }
  image::KtxBundle ktx(bytes.data(), uint32_t(bytes.size()));
  const image::KtxInfo& info = ktx.getInfo();
  std::printf("{\"ok\": true, \"cubemap\": %s, \"levels\": %u, \"width\": %u, \"height\": %u",
              ktx.isCubemap() ? "true" : "false", ktx.getNumMipLevels(), info.pixelWidth, info.pixelHeight);
  std::printf(", \"pixel_data_type\": %d, \"pixel_data_format\": %d, \"texture_format\": %d",
              int(image::ktx::toPixelDataType(info)), int(image::ktx::toPixelDataFormat(info)),
              int(image::ktx::toTextureFormat(info)));
  filament::math::float3 sh[9];
  if (ktx.getSphericalHarmonics(sh)) {
    std::printf(", \"sh\": [");
    for (int k = 0; k < 9; ++k) std::printf("%s%.9g, %.9g, %.9g", k ? ", " : "", sh[k].x, sh[k].y, sh[k].z);
    std::printf("]");
  } else {
    std::printf(", \"sh\": null");
  }
  std::printf(", \"blob_bytes\": [");
  for (uint32_t level = 0; level < ktx.getNumMipLevels(); ++level) {
    std::printf("%s[", level ? ", " : "");
    for (uint32_t face = 0; face < (ktx.isCubemap() ? 6u : 1u); ++face) {
      uint8_t* data = nullptr;
      uint32_t size = 0;
      if (!ktx.getBlob({level, 0, face}, &data, &size)) {
        std::fprintf(stderr, "%s: level %u face %u: getBlob failed\n", argv[1], level, face);
        return 1;
      }
      std::printf("%s%u", face ? ", " : "", size);
    }
    std::printf("]");
  }
  std::printf("]}\n");
  return 0;
}
