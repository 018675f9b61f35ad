#include "brdfbake/device.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <mutex>
#include <sstream>

#include "enum_names.hpp"
#include "runtime/cache_dirs.hpp"
#include "runtime/device_impl.hpp"

namespace brdfbake {

namespace {
constexpr detail::EnumName<Precision> kPrecisionNames[] = {{Precision::Fp32, "fp32"}, {Precision::Fp64, "fp64"}};
}  // namespace

Precision precision_from_name(const std::string& name) {
  return detail::enum_from_name(kPrecisionNames, name, "precision");
}

const char* precision_name(Precision p) { return detail::enum_name(kPrecisionNames, p); }

namespace {

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\0' || std::isspace(static_cast<unsigned char>(s.back())))) s.pop_back();
  size_t start = 0;
  while (start < s.size() && std::isspace(static_cast<unsigned char>(s[start]))) ++start;
  return s.substr(start);
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

const char* type_name(cl_device_type t) {
  if (t & CL_DEVICE_TYPE_GPU) return "gpu";
  if (t & CL_DEVICE_TYPE_CPU) return "cpu";
  if (t & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
  return "other";
}

// A device as enumeration finds it: its handles and type only. Opening a device asks no more than
// this of the others (clGetPlatformIDs, clGetDeviceIDs, CL_DEVICE_TYPE); the full DeviceInfo is
// queried for the chosen device alone (and for every device by list_devices).
struct Found {
  int platform_index = -1, device_index = -1;
  cl::Platform platform;
  cl::Device device;
  std::string type;  // type_name()
  bool is_default = false;
};

// Test switch: BRDFBAKE_DEVICE_LIMITS="max_alloc=1048576,global_memory=...,max_work_group_size=16,fp64=0"
// makes every device report these limits, so that the refusals of docs/RELIABILITY.md ("Device
// limits") can be tested on any device.
void apply_test_limits(DeviceInfo& info) {
  const char* text = std::getenv("BRDFBAKE_DEVICE_LIMITS");
  if (!text) return;
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, ',')) {
    const auto eq = item.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = item.substr(0, eq);
    const unsigned long long v = std::strtoull(item.c_str() + eq + 1, nullptr, 10);
    if (key == "max_alloc")
      info.max_alloc = v;
    else if (key == "global_memory")
      info.global_memory = v;
    else if (key == "max_work_group_size")
      info.max_work_group_size = static_cast<size_t>(v);
    else if (key == "fp64")
      info.fp64 = v != 0;
  }
}

// Finding and opening devices is serialised: the OpenCL ICD loader and PoCL initialise on the first
// call, which is not safe to make from several threads at once (a crash, or no platform found), and
// the cache check may set POCL_CACHE_DIR. Held by every entry point below (recursive: they nest).
std::recursive_mutex& discovery_mutex() {
  static std::recursive_mutex m;
  return m;
}

std::vector<Found> enumerate() {
  std::lock_guard<std::recursive_mutex> lock(discovery_mutex());
  detail::check_implementation_cache();  // an unwritable PoCL cache would hide every device
  std::vector<Found> out;
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error&) {
    return out;  // no ICD or no platform: an empty list, not an error
  }
  for (size_t p = 0; p < platforms.size(); ++p) {
    std::vector<cl::Device> devices;
    try {
      platforms[p].getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const cl::Error&) {
      continue;  // CL_DEVICE_NOT_FOUND on a platform with no device
    }
    for (size_t d = 0; d < devices.size(); ++d) {
      Found f;
      f.platform_index = static_cast<int>(p);
      f.device_index = static_cast<int>(d);
      f.platform = platforms[p];
      f.device = devices[d];
      f.type = detail::cl_call("querying device information",
                               [&] { return std::string(type_name(devices[d].getInfo<CL_DEVICE_TYPE>())); });
      out.push_back(std::move(f));
    }
  }
  // The default: the first GPU, else the first CPU, else the first device.
  auto pick = [&](const char* type) {
    return std::find_if(out.begin(), out.end(), [&](const Found& f) { return f.type == type; });
  };
  auto it = pick("gpu");
  if (it == out.end()) it = pick("cpu");
  if (it == out.end()) it = out.begin();
  if (it != out.end()) it->is_default = true;
  return out;
}

std::string device_name(const Found& f) {
  return detail::cl_call("querying device information", [&] { return trim(f.device.getInfo<CL_DEVICE_NAME>()); });
}

DeviceInfo full_info(const Found& f) {
  DeviceInfo info;
  info.platform_index = f.platform_index;
  info.device_index = f.device_index;
  info.type = f.type;
  info.is_default = f.is_default;
  const cl::Device& dev = f.device;
  detail::cl_call("querying device information", [&] {
    info.platform_name = trim(f.platform.getInfo<CL_PLATFORM_NAME>());
    info.platform_version = trim(f.platform.getInfo<CL_PLATFORM_VERSION>());
    info.name = trim(dev.getInfo<CL_DEVICE_NAME>());
    info.vendor = trim(dev.getInfo<CL_DEVICE_VENDOR>());
    info.version = trim(dev.getInfo<CL_DEVICE_VERSION>());
    info.driver_version = trim(dev.getInfo<CL_DRIVER_VERSION>());
    info.compute_units = dev.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
    info.global_memory = dev.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>();
    info.local_memory = dev.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>();
    info.max_alloc = dev.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
    info.max_work_group_size = dev.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>();
    const std::string ext = dev.getInfo<CL_DEVICE_EXTENSIONS>();
    info.fp64 = ext.find("cl_khr_fp64") != std::string::npos || dev.getInfo<CL_DEVICE_DOUBLE_FP_CONFIG>() != 0;
    return 0;
  });
  apply_test_limits(info);
  info.kernel_shape = resolve_kernel_shape(kernel_shape_request(), info.type);
  return info;
}

std::string describe(const std::vector<Found>& all) {
  if (all.empty()) return "no OpenCL device is available (is an ICD such as pocl-opencl-icd installed?)";
  std::ostringstream s;
  s << "available:";
  for (const auto& f : all)
    s << " " << f.platform_index << ":" << f.device_index << " '" << device_name(f) << "' (" << f.type << ")";
  return s.str();
}

Found find(const std::string& selector_in) {
  std::lock_guard<std::recursive_mutex> lock(discovery_mutex());
  std::string selector = selector_in;
  if (selector.empty()) {
    if (const char* env = std::getenv("BRDFBAKE_DEVICE")) selector = env;
  }
  const auto all = enumerate();
  if (all.empty()) throw RuntimeFailure(describe(all));  // the machine's set-up, not the request
  if (selector.empty() || selector == "default") {
    for (const auto& f : all)
      if (f.is_default) return f;
  }
  // "P:D"
  const auto colon = selector.find(':');
  if (colon != std::string::npos) {
    const std::string a = selector.substr(0, colon), b = selector.substr(colon + 1);
    const bool digits = !a.empty() && !b.empty() && std::all_of(a.begin(), a.end(), ::isdigit) &&
                        std::all_of(b.begin(), b.end(), ::isdigit);
    if (digits) {
      const int p = std::stoi(a), d = std::stoi(b);
      for (const auto& f : all)
        if (f.platform_index == p && f.device_index == d) return f;
      throw Error("no OpenCL device " + selector + "; " + describe(all));
    }
  }
  const std::string want = lower(selector);
  if (want == "cpu" || want == "gpu" || want == "accelerator") {
    for (const auto& f : all)
      if (f.type == want) return f;
    throw Error("no OpenCL " + want + " device; " + describe(all));
  }
  for (const auto& f : all)
    if (lower(device_name(f)).find(want) != std::string::npos) return f;
  throw Error("no OpenCL device matches '" + selector + "'; " + describe(all));
}

}  // namespace

namespace {
std::mutex& shape_mutex() {
  static std::mutex m;
  return m;
}
std::string& shape_set() {
  static std::string s;  // empty: not set
  return s;
}
std::string checked_shape(const std::string& shape, const char* from) {
  const std::string s = lower(trim(shape));
  if (s != "auto" && s != "cpu" && s != "gpu")
    throw Error(std::string(from) + " must be auto, cpu or gpu (got '" + shape + "')");
  return s;
}
}  // namespace

void set_kernel_shape(const std::string& shape) {
  const std::string s = checked_shape(shape, "the kernel shape");
  std::lock_guard<std::mutex> lock(shape_mutex());
  shape_set() = s;
}

std::string kernel_shape_request() {
  {
    std::lock_guard<std::mutex> lock(shape_mutex());
    if (!shape_set().empty()) return shape_set();
  }
  const char* env = std::getenv("BRDFBAKE_KERNEL_SHAPE");
  if (!env || !*env) return "auto";
  return checked_shape(env, "BRDFBAKE_KERNEL_SHAPE");
}

std::string resolve_kernel_shape(const std::string& request, const std::string& device_type) {
  const std::string s = checked_shape(request, "the kernel shape");
  if (s != "auto") return s;
  return device_type == "cpu" ? "cpu" : "gpu";
}

std::vector<DeviceInfo> list_devices() {
  std::lock_guard<std::recursive_mutex> lock(discovery_mutex());
  std::vector<DeviceInfo> out;
  for (auto& f : enumerate()) out.push_back(full_info(f));
  return out;
}

DeviceInfo select_device(const std::string& selector) {
  std::lock_guard<std::recursive_mutex> lock(discovery_mutex());
  return full_info(find(selector));
}

Device Device::open(const std::string& selector) {
  std::lock_guard<std::recursive_mutex> lock(discovery_mutex());
  Found f = find(selector);
  auto impl = std::make_shared<Impl>();
  impl->info = full_info(f);
  impl->platform = f.platform;
  impl->device = f.device;
  detail::cl_call("opening device '" + impl->info.name + "'", [&] {
    impl->context = cl::Context(f.device);
    impl->queue = cl::CommandQueue(impl->context, f.device, CL_QUEUE_PROFILING_ENABLE);
    return 0;
  });
  return Device(std::move(impl));
}

Device Device::open(const DeviceInfo& info) {
  Device d = open(std::to_string(info.platform_index) + ":" + std::to_string(info.device_index));
  if (!info.kernel_shape.empty()) d.impl_->info.kernel_shape = resolve_kernel_shape(info.kernel_shape, info.type);
  return d;
}

const DeviceInfo& Device::info() const { return impl_->info; }

}  // namespace brdfbake
