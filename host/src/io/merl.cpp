// MERL BRDF binaries: writer, reader and the reader's lookup. See merl.hpp for the layout.
#include "io/merl.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "brdfbake/error.hpp"
#include "brdfbake/math/conventions.hpp"
#include "io/atomic_file.hpp"
#include "io/json_input.hpp"
#include "io/special_files.hpp"

namespace brdfbake {
namespace {

using brdfbake::math::kPi;
constexpr double kHalfPi = 0.5 * kPi;
constexpr std::size_t kHeaderBytes = 3 * sizeof(std::int32_t);

Vec3 normalize(const Vec3& v) {
  const double len = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  return {v.x / len, v.y / len, v.z / len};
}

// Rotation of v about the y axis by `angle` (right-handed), and about z.
Vec3 rotate_y(const Vec3& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {v.x * c + v.z * s, v.y, v.z * c - v.x * s};
}
Vec3 rotate_z(const Vec3& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {v.x * c - v.y * s, v.x * s + v.y * c, v.z};
}

}  // namespace

namespace io {

MerlAngles merl_bin_centre(int i, int j, int k) {
  const double u = (i + 0.5) / kMerlThetaH;
  return {u * u * kHalfPi, (j + 0.5) / kMerlThetaD * kHalfPi, (k + 0.5) / kMerlPhiD * kPi};
}

void half_diff_to_directions(double theta_h, double theta_d, double phi_d, Vec3& wi, Vec3& wo) {
  const double st = std::sin(theta_h), ct = std::cos(theta_h);
  const double sd = std::sin(theta_d), cd = std::cos(theta_d);
  const Vec3 d{sd * std::cos(phi_d), sd * std::sin(phi_d), cd};
  wi = rotate_y(d, theta_h);
  // wi.h = cos td for h = (sin th, 0, cos th)
  wo = {2.0 * cd * st - wi.x, -wi.y, 2.0 * cd * ct - wi.z};
}

// std_coords_to_half_diff_coords: h = normalize(wi + wo), theta_h = acos(h.z), phi_h = atan2(h.y, h.x);
// diff = R_y(-theta_h) R_z(-phi_h) wi, theta_d = acos(diff.z), phi_d = atan2(diff.y, diff.x).
std::size_t merl_index(const Vec3& wi_in, const Vec3& wo_in) {
  for (double c : {wi_in.x, wi_in.y, wi_in.z, wo_in.x, wo_in.y, wo_in.z})
    if (!std::isfinite(c)) throw Error("merl_lookup: a direction is not finite");
  if ((wi_in.x == 0.0 && wi_in.y == 0.0 && wi_in.z == 0.0) || (wo_in.x == 0.0 && wo_in.y == 0.0 && wo_in.z == 0.0))
    throw Error("merl_lookup: a direction is the zero vector");
  const Vec3 wi = normalize(wi_in), wo = normalize(wo_in);
  const Vec3 h = normalize({wi.x + wo.x, wi.y + wo.y, wi.z + wo.z});
  const double theta_h = std::acos(std::clamp(h.z, -1.0, 1.0));
  const double phi_h = std::atan2(h.y, h.x);
  const Vec3 diff = rotate_y(rotate_z(wi, -phi_h), -theta_h);
  const double theta_d = std::acos(std::clamp(diff.z, -1.0, 1.0));
  double phi_d = std::atan2(diff.y, diff.x);
  if (phi_d < 0.0) phi_d += kPi;  // reciprocity
  // theta_half_index: sqrt(theta_h / (pi/2)) * 90, floored and clamped (0 for theta_h <= 0). The
  // clamp comes before the conversion to int: a NaN (opposite directions, wi + wo = 0) or an
  // out-of-range double converted to int is undefined behaviour.
  auto bin = [](double x, int n) { return x >= 0.0 && x < n ? static_cast<int>(x) : x >= n ? n - 1 : 0; };
  const int i = theta_h > 0.0 ? bin(std::sqrt(theta_h / kHalfPi) * kMerlThetaH, kMerlThetaH) : 0;
  const int j = bin(theta_d / kHalfPi * kMerlThetaD, kMerlThetaD);
  const int k = bin(phi_d / kPi * kMerlPhiD, kMerlPhiD);
  return (static_cast<std::size_t>(i) * kMerlThetaD + static_cast<std::size_t>(j)) * kMerlPhiD +
         static_cast<std::size_t>(k);
}

}  // namespace io

void write_merl(const MerlTable& table, const std::string& path) {
  if (table.values.size() != 3 * kMerlBins)
    io::throw_write_error(
        path, "a MERL table holds 3 x 90 x 90 x 180 values (got " + std::to_string(table.values.size()) + ")");
  std::string bytes(kHeaderBytes + table.values.size() * sizeof(double), '\0');
  const std::int32_t dims[3] = {kMerlThetaH, kMerlThetaD, kMerlPhiD};
  std::memcpy(bytes.data(), dims, kHeaderBytes);
  char* cursor = bytes.data() + kHeaderBytes;
  for (std::size_t c = 0; c < 3; ++c) {
    for (std::size_t b = 0; b < kMerlBins; ++b) {
      const double f = table.values[c * kMerlBins + b];
      if (std::isnan(f)) io::throw_write_error(path, "the table holds a NaN (bin " + std::to_string(b) + ")");
      const double stored = f < 0.0 ? kMerlBelowHorizon : f / io::kMerlScale[c];
      std::memcpy(cursor, &stored, sizeof stored);
      cursor += sizeof stored;
    }
  }
  nlohmann::ordered_json sidecar;
  sidecar["file"] = std::filesystem::path(path).filename().string();
  sidecar["format"] =
      "MERL BRDF binary: int32 dims 90 90 180 (theta_h, theta_d, phi_d), then 3 x 1458000 doubles, "
      "channel-major (red, green, blue), little-endian";
  nlohmann::ordered_json meta = nlohmann::ordered_json::object();
  for (const auto& [key, value] : table.metadata) meta[key] = value;
  sidecar["metadata"] = meta;
  const std::string json_text = io::json_text(sidecar) + "\n";
  io::TempFile binary(path);
  io::write_bytes(binary, bytes);
  io::TempFile json(path + ".json");
  io::write_bytes(json, json_text);
  binary.commit();
  json.commit();
}

namespace {

// The values of a MERL binary whose header was read: checks the dimensions and the size before
// anything is allocated (a hostile header may promise any size).
void check_merl_header(const std::string& origin, const unsigned char* header, std::uint64_t file_size) {
  std::int32_t dims[3];
  std::memcpy(dims, header, kHeaderBytes);
  if (dims[0] != kMerlThetaH || dims[1] != kMerlThetaD || dims[2] != kMerlPhiD)
    throw Error("'" + origin + "' is not a MERL BRDF file (dimensions " + std::to_string(dims[0]) + " x " +
                std::to_string(dims[1]) + " x " + std::to_string(dims[2]) + ", expected 90 x 90 x 180)");
  const std::uint64_t expected = kHeaderBytes + 3 * std::uint64_t(kMerlBins) * sizeof(double);
  if (file_size != expected)
    throw Error("'" + origin + "' is not a MERL BRDF file (" + std::to_string(file_size) + " bytes, expected " +
                std::to_string(expected) + ")");
}

}  // namespace

MerlTable decode_merl(const std::string& bytes, const std::string& origin) {
  if (bytes.size() < kHeaderBytes) throw Error("'" + origin + "' is not a MERL BRDF file (shorter than its header)");
  check_merl_header(origin, reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size());
  MerlTable table;
  table.values.resize(3 * kMerlBins);
  const char* cursor = bytes.data() + kHeaderBytes;
  for (std::size_t c = 0; c < 3; ++c) {
    for (std::size_t b = 0; b < kMerlBins; ++b) {
      double stored;
      std::memcpy(&stored, cursor, sizeof stored);
      cursor += sizeof stored;
      if (std::isnan(stored) || std::isinf(stored))
        throw Error("'" + origin + "' holds a value that is not finite (channel " + std::to_string(c) + ", bin " +
                    std::to_string(b) + ")");
      table.values[c * kMerlBins + b] = stored < 0.0 ? kMerlBelowHorizon : stored * io::kMerlScale[c];
    }
  }
  return table;
}

MerlTable read_merl(const std::string& path) {
  std::error_code ec;
  namespace fs = std::filesystem;
  if (fs::is_directory(path, ec)) throw Error("cannot read '" + path + "': it is a folder");
  // A MERL file's size is fixed by its header: a FIFO or a device is refused, never read.
  if (const std::string problem = io::input_problem(path, io::Streams::No);
      !problem.empty() && problem != "no such file")
    throw Error("cannot read '" + path + "': " + problem);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read '" + path + "': " + (fs::exists(path, ec) ? "permission denied" : "no such file"));
  const std::uint64_t size = fs::file_size(path, ec);
  if (ec) throw IoError("cannot read '" + path + "': " + ec.message());
  unsigned char header[kHeaderBytes];
  if (size < kHeaderBytes || !in.read(reinterpret_cast<char*>(header), kHeaderBytes))
    throw Error("'" + path + "' is not a MERL BRDF file (shorter than its header)");
  check_merl_header(path, header, size);
  std::string bytes(static_cast<size_t>(size), '\0');
  in.seekg(0);
  if (!in.read(bytes.data(), static_cast<std::streamsize>(size)))
    throw IoError("cannot read '" + path + "': read error");
  MerlTable table = decode_merl(bytes, path);
  // The sidecar's metadata, when it can be read: a sidecar we cannot read only loses the metadata.
  if (fs::is_regular_file(path + ".json", ec)) {
    try {
      const nlohmann::ordered_json j = io::parse_json(io::read_text_file(path + ".json", "sidecar"), path + ".json");
      if (j.is_object() && j.contains("metadata") && j.at("metadata").is_object())
        for (auto it = j.at("metadata").begin(); it != j.at("metadata").end(); ++it)
          if (it->is_string()) table.metadata.emplace_back(it.key(), it->get<std::string>());
    } catch (const Error&) {
    }
  }
  return table;
}

Rgb merl_lookup(const MerlTable& table, const Vec3& wi, const Vec3& wo) {
  if (table.values.size() != 3 * kMerlBins) throw Error("merl_lookup: not a MERL table");
  const std::size_t b = io::merl_index(wi, wo);
  return Rgb{table.values[b], table.values[kMerlBins + b], table.values[2 * kMerlBins + b]};
}

}  // namespace brdfbake
