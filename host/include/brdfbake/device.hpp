// OpenCL devices: enumeration, selection and an opened device (context + profiling queue).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace brdfbake {

enum class Precision { Fp32, Fp64 };
Precision precision_from_name(const std::string& name);  // "fp32" | "fp64"; throws Error otherwise
const char* precision_name(Precision p);

struct DeviceInfo {
  int platform_index = -1;
  int device_index = -1;
  std::string platform_name;
  std::string platform_version;
  std::string name;
  std::string vendor;
  std::string version;         // CL_DEVICE_VERSION
  std::string driver_version;  // CL_DRIVER_VERSION
  std::string type;            // "cpu", "gpu", "accelerator" or "other"
  unsigned compute_units = 0;
  uint64_t global_memory = 0;
  uint64_t local_memory = 0;
  uint64_t max_alloc = 0;
  size_t max_work_group_size = 0;
  bool fp64 = false;
  bool is_default = false;  // the device chosen when nothing is asked for
  // The work shape the kernels take on this device (docs/DEVICES.md, "Kernel shapes"): "cpu" (a
  // work-item walks a block of texels with wide vectors: what PoCL's vectoriser fills) or "gpu" (a
  // work-item a texel, pixel or pair, in work-groups the device's limits allow). What
  // kernel_shape_request() asks for, "auto" being the device's type: "cpu" on a CPU, else "gpu".
  std::string kernel_shape;
};

// The kernel shape asked for in this process: set_kernel_shape's ("auto", "cpu" or "gpu": the
// CLI's --kernel-shape, serve's, Python's), else $BRDFBAKE_KERNEL_SHAPE, else "auto". Devices
// opened afterwards take it. Throws Error naming the choices for any other name.
void set_kernel_shape(const std::string& shape);
std::string kernel_shape_request();
// "cpu" or "gpu": a request ("auto", "cpu", "gpu") for a device of `device_type` (DeviceInfo::type).
std::string resolve_kernel_shape(const std::string& request, const std::string& device_type);

// Every device of every platform; an empty list when there is no OpenCL platform at all.
std::vector<DeviceInfo> list_devices();

// The device a selector names: "" (then $BRDFBAKE_DEVICE, then the default: the first GPU, else
// the first CPU, else the first device), "P:D" indices, "cpu", "gpu", or a case-insensitive
// substring of the device name. Throws Error naming the selector and what exists.
DeviceInfo select_device(const std::string& selector);

// An opened OpenCL device: context, in-order profiling queue, program cache. Cheap to copy.
class Device {
 public:
  static Device open(const std::string& selector = {});
  // The device `info` names (platform and device index), in info.kernel_shape where it is set.
  static Device open(const DeviceInfo& info);

  const DeviceInfo& info() const;

  struct Impl;
  Impl& impl() const { return *impl_; }

 private:
  explicit Device(std::shared_ptr<Impl> impl) : impl_(std::move(impl)) {}
  std::shared_ptr<Impl> impl_;
};

}  // namespace brdfbake
