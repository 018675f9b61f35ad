// Internal: what an opened Device holds.
#pragma once

#include <map>
#include <mutex>
#include <string>

#include "brdfbake/device.hpp"
#include "runtime/cl.hpp"

namespace brdfbake {

struct Device::Impl {
  DeviceInfo info;
  cl::Platform platform;
  cl::Device device;
  cl::Context context;
  cl::CommandQueue queue;  // in order, with profiling
  std::mutex programs_mutex;
  std::map<std::string, cl::Program> programs;  // built programs by cache key
};

}  // namespace brdfbake
