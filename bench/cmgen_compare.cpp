// Side by side with Filament's cmgen (issue 11): each job of the table run by brdfbake and
// by cmgen as whole processes, interleaved, with wall time, peak memory and our error.
//
//   cmgen_compare [--runs N] [--jobs startup,dfg,sh,irradiance,ggx256,charlie256,ggx1024] [--env FILE]
//                 [--brdfbake PATH] [--cmgen PATH] [--baseline PATH] [--shared DIR] [--keep] [--write-4k PATH]
// --env FILE: the 1k input of the environment jobs (default venice_sunset_1k.hdr; rooitou_park_1k.hdr
// has the bright sun); the 4k input is it upsampled 4x. --write-4k PATH: only write that input.
//
// Every job: one warm-up run of each tool (kernel binary cache, page cache), then N rounds (default
// 5), each running every tool once, starting with a different one each round; each run is a
// fork/exec whose wall time comes from a steady clock and whose peak memory is wait4's ru_maxrss.
// --baseline runs our commands with another brdfbake build too (before/after a change). Printed: the medians of each
// tool, the median of the per-pair ratios ours/cmgen, the median peak memory, and our error against an independent
// reference computed here:
//   dfg         max abs error of our 128^2 multiscatter table against the converged double
//               reference (bake_lut_reference);
//   sh          max |L_lm - L_lm,ref| / L_00,ref of our radiance SH against an independent double
//               quadrature of the input equirect itself (2 x 2 Gauss-Legendre nodes per pixel);
//   irradiance  max and RMS relative error of our 64^2 irradiance cube (E / pi) on an 8 x 8 grid
//               of texels per face against brute-force cosine convolution of the input equirect;
//   chains      RMS and max relative error of the worst level of our KTX2 (as stored) on a grid of
//               texels per face (8 x 8 at 256^2, 2 x 2 at 1024^2) against the scalar double
//               reference filtering the file's own level 0 (chain_error); charlie256 runs ours only
//               (cmgen has no Charlie filter).
// The 4096x2048 input of ggx1024 is the shared 1k map upsampled bilinearly into a temporary file,
// removed at the end with everything else (--keep keeps the folder).
// Without cmgen (Debian: apt-get install libfilament-tools) only our side runs, and it says so.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "brdfbake/dfg_lut.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/io.hpp"
#include "brdfbake/math/conventions.hpp"
#include "brdfbake/math/cubemap.hpp"
#include "brdfbake/math/equirect.hpp"
#include "brdfbake/math/sh.hpp"
#include "brdfbake/reference/envmap.hpp"
#include "io/image_file.hpp"

#ifndef BRDFBAKE_CLI
#define BRDFBAKE_CLI "brdfbake"
#endif
#ifndef BRDFBAKE_SHARED_DIR
#define BRDFBAKE_SHARED_DIR "../shared"
#endif

using namespace brdfbake;
namespace fs = std::filesystem;

namespace {

using brdfbake::math::kPi;

struct Run {
  double seconds = 0;
  double peak_mib = 0;
};

// Runs argv in `cwd` with stdout and stderr to `log`; throws when it does not exit with 0.
Run run(const std::vector<std::string>& argv, const fs::path& cwd, const fs::path& log) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::fflush(nullptr);  // the child must not inherit (and print again) buffered output
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    if (::chdir(cwd.c_str()) != 0) ::_exit(126);
    FILE* out = std::freopen(log.c_str(), "a", stdout);
    if (out == nullptr || ::dup2(::fileno(stdout), 2) < 0) ::_exit(126);
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  rusage usage{};
  if (::wait4(pid, &status, 0, &usage) != pid) throw std::runtime_error("wait4 failed");
  Run r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.peak_mib = double(usage.ru_maxrss) / 1024.0;  // Linux: KiB
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::string cmd;
    for (const auto& a : argv) cmd += a + " ";
    throw std::runtime_error("'" + cmd + "' failed (status " + std::to_string(status) + "); see " + log.string());
  }
  return r;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string find_in_path(const std::string& name) {
  if (name.find('/') != std::string::npos) return fs::exists(name) ? name : "";
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && ::access((fs::path(dir) / name).c_str(), X_OK) == 0) return (fs::path(dir) / name).string();
  return "";
}

std::string first_line(const std::string& file, const std::string& key) {
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(key, 0) == 0) {
      const size_t start = line.find_first_not_of(" \t", line.find(':') + 1);
      return start == std::string::npos ? "" : line.substr(start);
    }
  return "";
}

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

struct Job {
  std::string name, description;
  std::vector<std::string> ours, theirs;  // theirs empty: no cmgen counterpart
};

// ---- Our errors ------------------------------------------------------------------------------------

std::string dfg_error(const fs::path& exr) {
  LutSpec spec;
  spec.kind = LutKind::GgxMultiscatter;
  spec.width = spec.height = 128;
  const Table ref = bake_lut_reference(spec);
  const io::FloatImage ours = io::read_image(exr.string(), io::ImageLimits{});
  if (ours.width != ref.width || ours.height != ref.height) return "size mismatch";
  double worst = 0;
  for (int j = 0; j < ref.height; ++j)
    for (int i = 0; i < ref.width; ++i)
      for (int c = 0; c < ref.channel_count(); ++c)
        worst = std::max(worst, std::fabs(double(ours.pixels[size_t((j * ref.width + i) * ours.channels + c)]) -
                                          double(ref.at(i, j, c))));
  char text[64];
  std::snprintf(text, sizeof text, "max abs %.1e vs the double reference", worst);
  return text;
}

// The radiance SH of the equirect as its pixels define it, each pixel constant over its cell,
// integrated over the cell's (u, v) square with 2 x 2 Gauss-Legendre nodes (error O(h^4): ~1e-11
// at 1k), dl = 2 pi^2 cos(latitude) du dv, the reference's basis: independent of
// host/src/families/irradiance/sh_projection.cpp's separable integrals.
std::vector<double> equirect_sh(const EnvImage& env, int order) {
  const double node[2] = {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)};
  std::vector<double> sum(size_t(order * order) * 3, 0.0);
  for (int y = 0; y < env.height; ++y)
    for (int x = 0; x < env.width; ++x) {
      const float* l = &env.rgb[3 * (size_t(y) * size_t(env.width) + size_t(x))];
      for (double a : node)
        for (double b : node) {
          const double u = (x + a) / env.width, v = (y + b) / env.height;
          const double dl = 2.0 * kPi * kPi * std::cos(kPi * (0.5 - v)) * 0.25 / (double(env.width) * env.height);
          const auto basis = math::sh_basis(order, math::equirect_direction(u, v));
          for (size_t k = 0; k < basis.size(); ++k)
            for (size_t c = 0; c < 3; ++c) sum[3 * k + c] += double(l[c]) * basis[k] * dl;
        }
    }
  return sum;
}

std::string sh_error(const fs::path& json_file, const EnvImage& env) {
  std::ifstream in(json_file);
  const nlohmann::json j = nlohmann::json::parse(in);
  const auto ref = equirect_sh(env, 3);
  double worst = 0;
  for (size_t k = 0; k < 9; ++k)
    for (size_t c = 0; c < 3; ++c)
      worst = std::max(worst, std::fabs(j.at("radiance").at(k).at(c).get<double>() - ref[3 * k + c]) / ref[c]);
  char text[80];
  std::snprintf(text, sizeof text, "max %.1e of L00 vs a 2x2-node quadrature of every input pixel", worst);
  return text;
}

std::string irradiance_error(const fs::path& ktx2, const EnvImage& env) {
  const EnvImage cube = read_ktx2_cube(ktx2.string(), 0);
  const int s = cube.width, step = std::max(1, s / 8);
  double worst = 0, sum2 = 0;
  int n = 0;
  for (int f = 0; f < 6; ++f)
    for (int j = step / 2; j < s; j += step)
      for (int i = step / 2; i < s; i += step) {
        const auto nrm = math::cube_texel_direction(f, s, i, j);
        double e[3] = {0, 0, 0};
        for (int y = 0; y < env.height; ++y) {
          const double top = kPi * (0.5 - double(y) / env.height), bottom = kPi * (0.5 - double(y + 1) / env.height);
          const double omega = 2.0 * kPi / env.width * (std::sin(top) - std::sin(bottom));
          for (int x = 0; x < env.width; ++x) {
            const auto d = math::equirect_direction((x + 0.5) / env.width, (y + 0.5) / env.height);
            const double cosine = nrm.x * d.x + nrm.y * d.y + nrm.z * d.z;
            if (cosine <= 0) continue;
            const float* l = &env.rgb[3 * (size_t(y) * size_t(env.width) + size_t(x))];
            for (size_t c = 0; c < 3; ++c) e[c] += double(l[c]) * cosine * omega / kPi;
          }
        }
        for (size_t c = 0; c < 3; ++c) {
          const double ours = double(cube.rgb[3 * ((size_t(f) * size_t(s) + size_t(j)) * size_t(s) + size_t(i)) + c]);
          const double rel = std::fabs(ours / e[c] - 1.0);
          worst = std::max(worst, rel);
          sum2 += rel * rel;
          ++n;
        }
      }
  char text[96];
  std::snprintf(text, sizeof text, "max %.1e, RMS %.1e relative vs brute-force convolution (%d texels)", worst,
                std::sqrt(sum2 / n), n / 3);
  return text;
}

// The 1k equirect upsampled 4x bilinearly (columns wrap, rows clamp) and written as RGBE.
// Our prefiltered chain (a KTX2 file) against the scalar double reference: for every level l >= 1,
// an n x n grid of texels per face, each the reference's lobe integral over every texel of the
// file's own level 0 (reference::prefilter_directions; exact solid angles), per channel
// |P - P_ref| / max(P_ref, 1e-3 mean); the worst level's RMS and max. The file's binary16 storage is
// part of what is measured (it is what a user gets).
std::string chain_error(const fs::path& ktx2, EnvDistribution d, int n) {
  const EnvImage level0 = read_ktx2_cube(ktx2.string(), 0);
  reference::EnvCube src;
  src.size = level0.width;
  src.rgb.assign(level0.rgb.begin(), level0.rgb.end());
  double worst_rms = 0, worst_max = 0;
  int levels = 0;
  while ((level0.width >> levels) >= 16) ++levels;  // the chains here end at 16^2
  size_t probes = 0;
  for (int l = 1; l < levels; ++l) {
    const EnvImage got = read_ktx2_cube(ktx2.string(), l);
    const int size = got.width, m = std::min(n, size), stride = size / m;
    std::vector<Vec3> dirs;
    std::vector<size_t> at;
    for (int f = 0; f < 6; ++f)
      for (int j = 0; j < m; ++j)
        for (int i = 0; i < m; ++i) {
          const int ti = i * stride + stride / 2, tj = j * stride + stride / 2;
          dirs.push_back(math::cube_texel_direction(f, size, ti, tj));
          at.push_back(3 * ((size_t(f) * size_t(size) + size_t(tj)) * size_t(size) + size_t(ti)));
        }
    const std::vector<double> want = reference::prefilter_directions(
        src, d == EnvDistribution::Ggx ? reference::EnvLobe::Ggx : reference::EnvLobe::Charlie,
        schedule_roughness(RoughnessSchedule::Linear, l, levels), dirs);
    double mean = 0;
    for (double v : want) mean += v;
    mean /= double(want.size());
    double sum2 = 0, mx = 0;
    for (size_t k = 0; k < dirs.size(); ++k)
      for (size_t c = 0; c < 3; ++c) {
        const double e =
            std::fabs(double(got.rgb[at[k] + c]) - want[3 * k + c]) / std::max(want[3 * k + c], 1e-3 * mean);
        sum2 += e * e;
        mx = std::max(mx, e);
      }
    worst_rms = std::max(worst_rms, std::sqrt(sum2 / double(3 * dirs.size())));
    worst_max = std::max(worst_max, mx);
    probes += dirs.size();
  }
  char b[200];
  std::snprintf(
      b, sizeof b,
      "worst level RMS %.2f%%, max %.1f%% (%zu texels on %d levels vs the double reference, as stored: binary16)",
      100 * worst_rms, 100 * worst_max, probes, levels - 1);
  return b;
}

void write_upsampled(const EnvImage& env, int factor, const fs::path& out) {
  Table t;
  t.width = env.width * factor;
  t.height = env.height * factor;
  t.channels = {"r", "g", "b"};
  t.data.resize(size_t(t.width) * size_t(t.height) * 3);
  for (int y = 0; y < t.height; ++y) {
    const double fy = std::clamp((y + 0.5) / factor - 0.5, 0.0, double(env.height - 1));
    const int y0 = int(fy), y1 = std::min(y0 + 1, env.height - 1);
    const double ty = fy - y0;
    for (int x = 0; x < t.width; ++x) {
      double fx = (x + 0.5) / factor - 0.5;
      if (fx < 0) fx += env.width;
      const int x0 = int(fx) % env.width, x1 = (x0 + 1) % env.width;
      const double tx = fx - std::floor(fx);
      for (size_t c = 0; c < 3; ++c) {
        auto at = [&](int xx, int yy) {
          return double(env.rgb[3 * (size_t(yy) * size_t(env.width) + size_t(xx)) + c]);
        };
        const double v =
            (1 - ty) * ((1 - tx) * at(x0, y0) + tx * at(x1, y0)) + ty * ((1 - tx) * at(x0, y1) + tx * at(x1, y1));
        t.data[3 * (size_t(y) * size_t(t.width) + size_t(x)) + c] = float(v);
      }
    }
  }
  write_table(t, out.string(), TableFormat::Hdr);
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 5;
  std::string jobs_wanted = "startup,dfg,sh,irradiance,ggx256,charlie256,ggx1024";
  std::string ours_bin = BRDFBAKE_CLI, cmgen_name = "cmgen", shared = BRDFBAKE_SHARED_DIR, baseline;
  bool keep = false;
  std::string write_4k;  // --write-4k PATH: only write the 4096x2048 input (for /usr/bin/time -v runs)
  std::string env_file;  // --env FILE: the 1k input (default ../shared/envmaps/venice_sunset_1k.hdr)
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    auto value = [&]() -> std::string {
      if (a + 1 >= argc) {
        std::fprintf(stderr, "cmgen_compare: %s needs a value\n", arg.c_str());
        std::exit(2);
      }
      return argv[++a];
    };
    if (arg == "--runs")
      runs = std::max(1, std::atoi(value().c_str()));
    else if (arg == "--jobs")
      jobs_wanted = value();
    else if (arg == "--brdfbake")
      ours_bin = value();
    else if (arg == "--cmgen")
      cmgen_name = value();
    else if (arg == "--baseline")
      baseline = value();
    else if (arg == "--shared")
      shared = value();
    else if (arg == "--keep")
      keep = true;
    else if (arg == "--write-4k")
      write_4k = value();
    else if (arg == "--env")
      env_file = value();
    else {
      std::fprintf(stderr,
                   "usage: cmgen_compare [--runs N] [--jobs LIST] [--brdfbake PATH] [--cmgen PATH] "
                   "[--baseline PATH] [--shared DIR] [--keep] [--write-4k PATH] [--env FILE]\n");
      return 2;
    }
  }
  auto wanted = [&](const std::string& j) {
    return ("," + jobs_wanted + ",").find("," + j + ",") != std::string::npos;
  };

  const std::string cmgen = find_in_path(cmgen_name);
  const fs::path env1k = env_file.empty() ? fs::path(shared) / "envmaps" / "venice_sunset_1k.hdr" : fs::path(env_file);
  const bool have_env = fs::exists(env1k);
  if (!write_4k.empty()) {
    if (!have_env) {
      std::fprintf(stderr, "cmgen_compare: %s is missing\n", env1k.string().c_str());
      return 1;
    }
    write_upsampled(load_environment(env1k.string()), 4, write_4k);
    return 0;
  }
  char tmpl[] = "/tmp/cmgen_compare.XXXXXX";
  if (::mkdtemp(tmpl) == nullptr) {
    std::perror("mkdtemp");
    return 1;
  }
  const fs::path dir = tmpl;
  const fs::path log = dir / "runs.log";

  std::printf("# brdfbake against cmgen, whole processes\n\n");
  std::printf("- machine: %s, %ld cores; load average before: %s\n", first_line("/proc/cpuinfo", "model name").c_str(),
              ::sysconf(_SC_NPROCESSORS_ONLN), load_average().c_str());
  std::printf("- brdfbake: %s\n", ours_bin.c_str());
  if (!baseline.empty()) std::printf("- before: %s (the same commands, interleaved)\n", baseline.c_str());
  if (cmgen.empty())
    std::printf(
        "- cmgen: NOT FOUND ('%s' is not on PATH; Debian: apt-get install libfilament-tools): "
        "our side only, no ratios\n",
        cmgen_name.c_str());
  else
    std::printf("- cmgen: %s\n", cmgen.c_str());
  std::printf(
      "- runs: 1 warm-up each, then %d rounds per job, each running every tool once (a different one "
      "first each round); medians; peak = wait4 ru_maxrss\n",
      runs);
  if (!have_env) std::printf("- %s is missing: the environment jobs are skipped\n", env1k.string().c_str());
  std::printf("\n");

  try {
    EnvImage env;
    if (have_env) env = load_environment(env1k.string());
    const fs::path env4k = dir / "venice_sunset_4k.hdr";
    if (have_env && wanted("ggx1024")) write_upsampled(env, 4, env4k);

    std::vector<Job> jobs;
    if (wanted("startup")) {
      jobs.push_back({"startup", "`brdfbake --help` (no device, no image)", {ours_bin, "--help"}, {}});
    }
    if (wanted("dfg"))
      jobs.push_back({"dfg",
                      "DFG 128^2 multiscatter",
                      {ours_bin, "lut", "--kind", "ggx-multiscatter", "--size", "128", "--quiet", "-o",
                       (dir / "dfg.exr").string()},
                      {cmgen, "--quiet", "--ibl-dfg=" + (dir / "dfg_cmgen.png").string(), "--ibl-dfg-multiscatter",
                       "--size=128"}});
    if (have_env && wanted("sh"))
      jobs.push_back(
          {"sh",
           "3-band irradiance SH of a 1k HDR",
           {ours_bin, "irradiance", "--env", env1k.string(), "--sh", "3", "--quiet", "-o", (dir / "sh.json").string()},
           {cmgen, "--quiet", "--sh=3", "--sh-irradiance", "--sh-output=" + (dir / "sh_cmgen.txt").string(),
            env1k.string()}});
    if (have_env && wanted("irradiance"))
      jobs.push_back({"irradiance",
                      "irradiance cube 64^2 of a 1k HDR",
                      {ours_bin, "irradiance", "--env", env1k.string(), "--cube", "64", "--quiet", "-o",
                       (dir / "irradiance.ktx2").string()},
                      {cmgen, "--quiet", "--size=64", "--format=hdr",
                       "--ibl-irradiance=" + (dir / "irradiance_cmgen").string(), env1k.string()}});
    if (have_env && wanted("ggx256"))
      jobs.push_back({"ggx256",
                      "GGX chain 256^2 -> 16^2 from a 1k HDR",
                      {ours_bin, "prefilter", "--env", env1k.string(), "--size", "256", "--min-size", "16", "--quiet",
                       "-o", (dir / "ggx256.ktx2").string()},
                      {cmgen, "--quiet", "--size=256", "--format=hdr", "--ibl-min-lod-size=16",
                       "--ibl-ld=" + (dir / "ggx256_cmgen").string(), env1k.string()}});
    if (have_env && wanted("charlie256"))  // cmgen filters GGX only: ours alone
      jobs.push_back({"charlie256",
                      "Charlie chain 256^2 -> 16^2 from a 1k HDR",
                      {ours_bin, "prefilter", "--distribution", "charlie", "--env", env1k.string(), "--size", "256",
                       "--min-size", "16", "--quiet", "-o", (dir / "charlie256.ktx2").string()},
                      {}});
    if (have_env && wanted("ggx1024"))
      jobs.push_back({"ggx1024",
                      "GGX chain 1024^2 -> 16^2 from a 4k HDR",
                      {ours_bin, "prefilter", "--env", env4k.string(), "--size", "1024", "--min-size", "16", "--quiet",
                       "-o", (dir / "ggx1024.ktx2").string()},
                      {cmgen, "--quiet", "--size=1024", "--format=hdr", "--ibl-min-lod-size=16",
                       "--ibl-ld=" + (dir / "ggx1024_cmgen").string(), env4k.string()}});

    std::printf(
        "| job | ours (median s) | cmgen (median s) | ours / cmgen (median of pairs) | peak ours | peak cmgen |%s our "
        "error |\n",
        baseline.empty() ? "" : " before (median s) | peak before |");
    std::printf("|---|---|---|---|---|---|%s---|\n", baseline.empty() ? "" : "---|---|");
    for (const Job& job : jobs) {
      // The contenders: ours, cmgen (when there is one), the baseline build (when given); each
      // iteration starts with a different one.
      std::vector<std::vector<std::string>> commands = {job.ours};
      const bool pair = !cmgen.empty() && !job.theirs.empty();
      const size_t theirs = pair ? commands.size() : 0, before = baseline.empty() ? 0 : commands.size() + pair;
      if (pair) commands.push_back(job.theirs);
      if (!baseline.empty()) {  // the same command, its output beside ours ("before_NAME")
        commands.push_back(job.ours);
        commands.back()[0] = baseline;
        for (size_t k = 1; k + 1 < commands.back().size(); ++k)
          if (commands.back()[k] == "-o") {
            const fs::path out = commands.back()[k + 1];
            commands.back()[k + 1] = (out.parent_path() / ("before_" + out.filename().string())).string();
          }
      }
      for (const auto& c : commands) run(c, dir, log);  // warm-up
      std::vector<std::vector<Run>> runs_of(commands.size());
      std::vector<double> ratios;
      for (int i = 0; i < runs; ++i) {
        for (size_t k = 0; k < commands.size(); ++k) {
          const size_t which = (k + size_t(i)) % commands.size();
          runs_of[which].push_back(run(commands[which], dir, log));
        }
        if (pair) ratios.push_back(runs_of[0].back().seconds / runs_of[theirs].back().seconds);
      }
      std::string error;
      if (job.name == "dfg") error = dfg_error(dir / "dfg.exr");
      if (job.name == "sh") error = sh_error(dir / "sh.json", env);
      if (job.name == "irradiance") error = irradiance_error(dir / "irradiance.ktx2", env);
      if (job.name == "ggx256") error = chain_error(dir / "ggx256.ktx2", EnvDistribution::Ggx, 8);
      if (job.name == "charlie256") error = chain_error(dir / "charlie256.ktx2", EnvDistribution::Charlie, 8);
      if (job.name == "ggx1024") error = chain_error(dir / "ggx1024.ktx2", EnvDistribution::Ggx, 2);
      if (job.name == "startup") error = "-";
      auto seconds = [](const std::vector<Run>& v) {
        std::vector<double> s;
        for (const Run& x : v) s.push_back(x.seconds);
        return median(s);
      };
      auto peak = [](const std::vector<Run>& v) {
        std::vector<double> s;
        for (const Run& x : v) s.push_back(x.peak_mib);
        return median(s);
      };
      char theirs_s[32] = "-", ratio[32] = "-", theirs_peak[32] = "-", before_cols[64] = "";
      if (pair) {
        std::snprintf(theirs_s, sizeof theirs_s, "%.3f", seconds(runs_of[theirs]));
        std::snprintf(ratio, sizeof ratio, median(ratios) < 0.1 ? "%.3f" : "%.2f", median(ratios));
        std::snprintf(theirs_peak, sizeof theirs_peak, "%.0f MiB", peak(runs_of[theirs]));
      }
      if (!baseline.empty())
        std::snprintf(before_cols, sizeof before_cols, " %.3f | %.0f MiB |", seconds(runs_of[before]),
                      peak(runs_of[before]));
      std::printf("| %s | %.3f | %s | %s | %.0f MiB | %s |%s %s |\n", job.description.c_str(), seconds(runs_of[0]),
                  theirs_s, ratio, peak(runs_of[0]), theirs_peak, before_cols, error.c_str());
      std::fflush(stdout);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cmgen_compare: %s\n", e.what());
    if (!keep) fs::remove_all(dir);
    return 1;
  }
  std::printf("\n- load average after: %s\n", load_average().c_str());
  if (keep)
    std::printf("- outputs kept in %s\n", dir.string().c_str());
  else
    fs::remove_all(dir);
  return 0;
}
