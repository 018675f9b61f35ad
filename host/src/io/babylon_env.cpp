// Babylon.js .env files (see babylon_env.hpp).
#include "io/babylon_env.hpp"

#include <cmath>
#include <cstring>

#include "brdfbake/engines.hpp"
#include "brdfbake/error.hpp"
#include "io/json_input.hpp"

namespace brdfbake::io {
namespace {

int full_chain_levels(int width) {
  int levels = 0;
  for (int w = width; w > 0; w >>= 1) ++levels;
  return levels;
}

}  // namespace

std::vector<uint8_t> encode_babylon_env(const BabylonEnv& env) {
  if (env.width < 1 || (env.width & (env.width - 1)) != 0)
    throw Error(".env: the face size must be a power of two, not " + std::to_string(env.width));
  const size_t expected = 6u * size_t(full_chain_levels(env.width));
  if (env.images.size() != expected)
    throw Error(".env: " + std::to_string(env.images.size()) + " images for width " + std::to_string(env.width) +
                "; Babylon requires the full chain, " + std::to_string(expected));
  nlohmann::ordered_json manifest;
  manifest["version"] = 2;
  manifest["width"] = env.width;
  manifest["imageType"] = "image/png";
  nlohmann::ordered_json irradiance = nlohmann::ordered_json::object();
  for (size_t k = 0; k < 9; ++k) {
    for (double v : env.polynomial[k])
      if (!std::isfinite(v)) throw Error(".env: a spherical polynomial coefficient is not finite");
    irradiance[kBabylonPolynomialNames[k]] = env.polynomial[k];
  }
  manifest["irradiance"] = irradiance;
  nlohmann::ordered_json mipmaps = nlohmann::ordered_json::array();
  size_t position = 0;
  for (const auto& image : env.images) {
    mipmaps.push_back({{"length", image.size()}, {"position", position}});
    position += image.size();
  }
  manifest["specular"] = {{"mipmaps", mipmaps}, {"lodGenerationScale", env.lod_generation_scale}};
  for (const auto& [k, v] : env.extra.items()) manifest[k] = v;
  // Babylon builds the manifest string byte by byte from char codes: ASCII only.
  const std::string text = manifest.dump(-1, ' ', true);
  size_t total = 8 + text.size() + 1;
  for (const auto& image : env.images) total += image.size();
  std::vector<uint8_t> out(total, 0);  // sized up front (GCC 12 misreads growth from the 8-byte magic)
  std::memcpy(out.data(), kBabylonEnvMagic, 8);
  std::memcpy(out.data() + 8, text.data(), text.size());
  size_t at = 8 + text.size() + 1;  // after the manifest's terminating NUL
  for (const auto& image : env.images) {
    if (!image.empty()) std::memcpy(out.data() + at, image.data(), image.size());
    at += image.size();
  }
  return out;
}

BabylonEnv decode_babylon_env(const std::vector<uint8_t>& bytes) {
  if (bytes.size() < 9 || std::memcmp(bytes.data(), kBabylonEnvMagic, 8) != 0)
    throw Error(".env: not a Babylon environment file (bad magic bytes)");
  size_t nul = 8;
  while (nul < bytes.size() && bytes[nul] != 0) ++nul;
  if (nul == bytes.size()) throw Error(".env: the manifest has no NUL terminator");
  // the input policy's parser (io/json_input.hpp): depth and size limits, the field named
  const nlohmann::ordered_json manifest =
      io::parse_json(std::string(bytes.begin() + 8, bytes.begin() + std::ptrdiff_t(nul)), ".env manifest");
  BabylonEnv env;
  try {
    if (manifest.at("version").get<int>() != 2 && manifest.at("version").get<int>() != 1)
      throw Error(".env: unsupported version " + io::json_excerpt(manifest.at("version")));
    env.width = manifest.at("width").get<int>();
    const auto& irradiance = manifest.at("irradiance");
    for (size_t k = 0; k < 9; ++k)
      env.polynomial[k] = irradiance.at(kBabylonPolynomialNames[k]).get<std::array<double, 3>>();
    const auto& specular = manifest.at("specular");
    env.lod_generation_scale = specular.value("lodGenerationScale", 0.8);
    const auto& mipmaps = specular.at("mipmaps");
    const size_t expected = 6u * size_t(std::lround(std::log2(double(env.width))) + 1);
    if (mipmaps.size() != expected)
      throw Error(".env: " + std::to_string(mipmaps.size()) + " images, Babylon expects " + std::to_string(expected));
    const size_t data = nul + 1;
    for (const auto& m : mipmaps) {
      const size_t position = m.at("position").get<size_t>(), length = m.at("length").get<size_t>();
      if (position > bytes.size() - data || length > bytes.size() - data - position)
        throw Error(".env: an image runs past the end of the file");
      env.images.emplace_back(bytes.begin() + std::ptrdiff_t(data + position),
                              bytes.begin() + std::ptrdiff_t(data + position + length));
    }
    for (const auto& [k, v] : manifest.items())
      if (k != "version" && k != "width" && k != "imageType" && k != "irradiance" && k != "specular") env.extra[k] = v;
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string(".env: malformed manifest: ") + e.what());
  }
  return env;
}

}  // namespace brdfbake::io
