#include "io/storage.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "io/codecs.hpp"
#include "io/rgbe.hpp"

namespace brdfbake::io {

namespace {

double metric(float stored, float value) {
  if (!std::isfinite(stored) || !std::isfinite(value)) return HUGE_VAL;
  return std::fabs(double(stored) - double(value)) / std::max(1.0, std::fabs(double(value)));
}

}  // namespace

StorageReport measure_storage(const Table& table, TableFormat format, PixelType pixel) {
  StorageReport r;
  const std::size_t channels = table.channels.size();
  const std::size_t count = table.data.size();
  auto out_of_range = [&](float v) {
    ++r.out_of_range;
    r.largest = std::max(r.largest, std::isfinite(v) ? std::fabs(double(v)) : HUGE_VAL);
  };
  switch (format) {
    case TableFormat::Exr:
    case TableFormat::Csv:
      // float32 EXR; CSV prints %.9g, which reads back as the same float32
      r.encoding = format == TableFormat::Exr ? "float32" : "decimal text, 9 significant digits (exact for float32)";
      for (float v : table.data)
        if (!std::isfinite(v)) out_of_range(v);
      return r;
    case TableFormat::Ktx2:
    case TableFormat::CHeader:
      if (pixel == PixelType::F32) {
        r.encoding = "float32";
        for (float v : table.data)
          if (!std::isfinite(v)) out_of_range(v);
        return r;
      }
      r.encoding = "binary16 (round to nearest even)";
      for (float v : table.data) {
        const float s = half_round_trip(v);
        if (!std::isfinite(s))
          out_of_range(v);
        else
          r.max_error = std::max(r.max_error, metric(s, v));
      }
      return r;
    case TableFormat::Png:
      r.encoding = "16-bit UNORM (round(v * 65535))";
      for (float v : table.data) {
        if (!(v >= 0.0f && v <= 1.0f)) out_of_range(v);
        r.max_error = std::max(r.max_error, metric(unorm16_decode(unorm16_encode(v)), v));
      }
      return r;
    case TableFormat::Hdr: {
      r.encoding = "Radiance RGBE (shared exponent, truncated mantissas)";
      const std::size_t texels = channels ? count / channels : 0;
      for (std::size_t t = 0; t < texels; ++t) {
        float in[3] = {0, 0, 0}, out[3];
        for (std::size_t c = 0; c < channels && c < 3; ++c) {
          in[c] = table.data[t * channels + c];
          if (!(in[c] >= 0.0f && in[c] <= kRgbeMax)) out_of_range(in[c]);
        }
        // as the writer: negatives and NaN to 0, beyond kRgbeMax to kRgbeMax, then the codec
        float clean[3];
        for (int c = 0; c < 3; ++c) clean[c] = in[c] >= 0.0f ? std::min(in[c], kRgbeMax) : 0.0f;
        uint8_t bytes[4];
        float_to_rgbe(clean, bytes);
        rgbe_to_float(bytes, out);
        for (std::size_t c = 0; c < channels && c < 3; ++c) r.max_error = std::max(r.max_error, metric(out[c], in[c]));
      }
      return r;
    }
  }
  return r;
}

StorageReport measure_cube_storage(const std::vector<std::vector<float>>& levels, PixelType pixel) {
  StorageReport r;
  r.encoding = pixel == PixelType::F16 ? "binary16 (round to nearest even)" : "float32";
  constexpr size_t kChunk = 4096;
  std::vector<uint16_t> bits(kChunk);
  std::vector<float> back(kChunk);
  float worst = 0.0f;  // the largest |stored - value| / |value| (alpha, 1, is stored exactly)
  for (const auto& level : levels)
    for (size_t k0 = 0; k0 < level.size(); k0 += kChunk) {
      const size_t n = std::min(kChunk, level.size() - k0);
      const float* v = level.data() + k0;
      const float* s = v;
      if (pixel == PixelType::F16) {  // the round trip of the chunk, at once
        floats_to_half_bits(v, n, bits.data());
        half_bits_to_floats(bits.data(), n, back.data());
        s = back.data();
      }
      // One compare a value (d > worst |v| is d / |v| > worst without the division, which is taken
      // only when the worst grows); the rare values that cannot be stored are counted in a second
      // look only where the first found one.
      bool all_finite = true;
      for (size_t k = 0; k < n; ++k) {
        const float d = std::fabs(s[k] - v[k]), a = std::max(std::fabs(v[k]), 1e-30f);
        all_finite &= (d <= 3.4e38f) & (a <= 3.4e38f);  // false for NaN and infinity
        if (d > worst * a) worst = d / a;
      }
      if (all_finite) continue;
      for (size_t k = 0; k < n; ++k)
        if (!std::isfinite(v[k]) || !std::isfinite(s[k])) {
          ++r.out_of_range;
          r.largest = std::max(r.largest, std::isfinite(v[k]) ? std::fabs(double(v[k])) : HUGE_VAL);
        }
    }
  // (with values that cannot be stored the caller refuses or clamps and measures again)
  r.max_error = r.out_of_range == 0 ? double(worst) : 0.0;
  return r;
}

}  // namespace brdfbake::io
