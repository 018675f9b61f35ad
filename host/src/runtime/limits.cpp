// Device limits checked before a bake allocates or launches (docs/RELIABILITY.md, "Device limits").
#include <cstdio>

#include "runtime/launch.hpp"

namespace brdfbake::detail {

namespace {
std::string mib(double bytes) {
  char b[48];
  std::snprintf(b, sizeof b, "%.0f MiB", bytes / double(1 << 20));
  return b;
}
}  // namespace

void check_device_memory(const Device::Impl& dev, double bytes, double total, const std::string& what) {
  const DeviceInfo& d = dev.info;
  if (d.max_alloc > 0 && bytes > double(d.max_alloc))
    throw RuntimeFailure(what + " needs " + mib(bytes) + " in one buffer; device '" + d.name + "' allows at most " +
                         mib(double(d.max_alloc)) +
                         " (CL_DEVICE_MAX_MEM_ALLOC_SIZE): choose a smaller size or another device");
  if (d.global_memory > 0 && total > double(d.global_memory))
    throw RuntimeFailure(what + " needs " + mib(total) + " of device memory; device '" + d.name + "' has " +
                         mib(double(d.global_memory)) +
                         " (CL_DEVICE_GLOBAL_MEM_SIZE): choose a smaller size or another device");
}

void check_work_group(const Device::Impl& dev, const cl::Kernel& kernel, size_t local, const std::string& what) {
  size_t most = dev.info.max_work_group_size;
  try {
    most = std::min(most, kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(dev.device));
  } catch (const cl::Error&) {
    // the query is optional: the launch reports the error itself
  }
  if (most > 0 && local > most)
    throw RuntimeFailure(what + " needs work-groups of " + std::to_string(local) + " items; device '" + dev.info.name +
                         "' runs at most " + std::to_string(most) + " (CL_KERNEL_WORK_GROUP_SIZE)");
}

}  // namespace brdfbake::detail
