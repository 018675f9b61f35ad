#include "cli_env.hpp"

#include <cstdio>
#include <filesystem>

namespace brdfbake::cli {

namespace {

CubeImageLayout layout_from_name(const std::string& n) {
  if (n == "faces") return CubeImageLayout::Faces;
  if (n == "cross") return CubeImageLayout::HorizontalCross;
  if (n == "vcross") return CubeImageLayout::VerticalCross;
  if (n == "equirect") return CubeImageLayout::Equirect;
  throw UsageError("--layout must be faces, cross, vcross or equirect (got '" + n + "')");
}

}  // namespace

void add_cube_output_options(cxxopts::Options& options) {
  options.add_options()
      ("sanitize", "replace NaN, infinite and negative pixels instead of refusing the input")
      ("pixel", "f16 | f32", cxxopts::value<std::string>()->default_value("f16"))
      ("layout", "folder output: faces | cross | vcross | equirect", cxxopts::value<std::string>()->default_value("faces"))
      ("image-format", "folder output: exr | hdr", cxxopts::value<std::string>()->default_value("exr"))
      ("dds-legacy", ".dds output: the legacy header (D3DFMT 113/116) instead of DX10");
}

CubeFormat cube_container_option(const cxxopts::ParseResult& r, const std::string& path) {
  const CubeFormat format = cube_format_from_path(path);
  return format == CubeFormat::Dds && r.count("dds-legacy") ? CubeFormat::DdsLegacy : format;
}

CubeWriteOptions cube_write_options(const cxxopts::ParseResult& r) {
  CubeWriteOptions wo;
  const std::string pixel = r["pixel"].as<std::string>();
  if (pixel == "f16") wo.pixel = PixelType::F16;
  else if (pixel == "f32") wo.pixel = PixelType::F32;
  else throw UsageError("--pixel must be f16 or f32 (got '" + pixel + "')");
  wo.layout = layout_from_name(r["layout"].as<std::string>());
  const std::string image_format = r["image-format"].as<std::string>();
  if (image_format == "exr") wo.image_format = CubeImageFormat::Exr;
  else if (image_format == "hdr") wo.image_format = CubeImageFormat::Hdr;
  else throw UsageError("--image-format must be exr or hdr (got '" + image_format + "')");
  return wo;
}

std::string output_probe(const std::string& path, CubeFormat format) {
  if (format != CubeFormat::Directory) return path;
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return (std::filesystem::path(path) / "probe").string();
  std::string d = path;
  while (d.size() > 1 && d.back() == '/') d.pop_back();
  return d;
}

EnvImage load_environment_option(const cxxopts::ParseResult& r, bool quiet) {
  EnvLoadOptions lo;
  lo.sanitize = r.count("sanitize") > 0;
  EnvImage env = load_environment(r["env"].as<std::string>(), lo);
  if (!quiet && env.sanitize.replaced)
    std::fprintf(stderr, "sanitized '%s': replaced %zu NaN, %zu infinite and %zu negative values\n",
                 env.source.c_str(), env.sanitize.nan, env.sanitize.infinite, env.sanitize.negative);
  return env;
}

}  // namespace brdfbake::cli
