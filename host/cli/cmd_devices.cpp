// brdfbake devices [--json]
#include <iostream>
#include <nlohmann/json.hpp>

#include "brdfbake/device.hpp"
#include "cli_common.hpp"

namespace brdfbake::cli {

int cmd_devices(int argc, char** argv) {
  cxxopts::Options options("brdfbake devices", "List OpenCL platforms and devices");
  options.add_options()("json", "print JSON for machines")("h,help", "this help");
  const auto r = parse(options, argc, argv);
  if (r.count("help")) {
    std::cout << options.help() << "\n";
    return 0;
  }
  const auto devices = list_devices();
  if (r.count("json")) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& d : devices)
      out.push_back({{"id", std::to_string(d.platform_index) + ":" + std::to_string(d.device_index)},
                     {"platform", d.platform_name},
                     {"platform_version", d.platform_version},
                     {"name", d.name},
                     {"vendor", d.vendor},
                     {"type", d.type},
                     {"version", d.version},
                     {"driver_version", d.driver_version},
                     {"compute_units", d.compute_units},
                     {"global_memory_bytes", d.global_memory},
                     {"local_memory_bytes", d.local_memory},
                     {"max_alloc_bytes", d.max_alloc},
                     {"max_work_group_size", d.max_work_group_size},
                     {"fp64", d.fp64},
                     {"kernel_shape", d.kernel_shape},
                     {"default", d.is_default}});
    out.push_back({{"id", "reference"},
                   {"name", "scalar double reference (CPU, converged, slow)"},
                   {"type", "reference"},
                   {"fp64", true},
                   {"default", false}});
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  if (devices.empty()) std::cout << "No OpenCL device found (install an ICD such as pocl-opencl-icd).\n";
  int last_platform = -1;
  for (const auto& d : devices) {
    if (d.platform_index != last_platform) {
      std::cout << "Platform " << d.platform_index << ": " << d.platform_name << " (" << d.platform_version << ")\n";
      last_platform = d.platform_index;
    }
    std::cout << "  " << d.platform_index << ":" << d.device_index << (d.is_default ? " * " : "   ") << d.name << "\n"
              << "        type " << d.type << ", " << d.version << ", driver " << d.driver_version << "\n"
              << "        " << d.compute_units << " compute units, " << (d.global_memory >> 20)
              << " MiB global memory, fp64 " << (d.fp64 ? "yes" : "no") << ", kernel shape " << d.kernel_shape << "\n";
  }
  std::cout << "  reference   scalar double reference (--device reference): converged, slow\n";
  if (!devices.empty()) std::cout << "(* the default device; choose with --device or BRDFBAKE_DEVICE)\n";
  return 0;
}

}  // namespace brdfbake::cli
