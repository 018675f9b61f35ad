// The KTX2 container reader (decode_ktx2): any bytes. A file it accepts must encode again and
// decode to the same texture (the writer and the reader agree on every accepted file).
#include <cstdlib>

#include "fuzz.hpp"
#include "io/ktx2.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace brdfbake;
  const auto image = fuzz::accepted([&] { return io::decode_ktx2(data, size); });
  if (!image) return 0;
  fuzz::invariant("an accepted KTX2 image encodes and decodes to the same texture", [&] {
    const std::vector<uint8_t> again = io::encode_ktx2(*image);
    const io::Ktx2Image back = io::decode_ktx2(again);
    fuzz::require(back.level_data == image->level_data && back.key_values == image->key_values &&
                      back.width == image->width && back.height == image->height && back.faces == image->faces &&
                      back.vk_format == image->vk_format,
                  "decode_ktx2(encode_ktx2(image)) == image");
  });
  return 0;
}
