// Opening the OpenCL device for device tests. A test that needs a device and finds none fails
// with a clear message, unless BRDFBAKE_ALLOW_NO_DEVICE=1, when it skips.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>

#include "brdfbake/device.hpp"
#include "brdfbake/error.hpp"

namespace brdfbake::test {

inline bool allow_no_device() {
  const char* v = std::getenv("BRDFBAKE_ALLOW_NO_DEVICE");
  return v && std::string(v) == "1";
}

// The device under test (BRDFBAKE_DEVICE or the default), opened once per process. It is never
// destroyed: an OpenCL implementation loaded by LD_PRELOAD (Oclgrind) tears its own state down
// before the test's static destructors run, and releasing a context after that corrupts its heap.
inline Device* test_device() {
  static Device* device = nullptr;
  static bool tried = false;
  if (!tried) {
    tried = true;
    try {
      device = new Device(Device::open());
    } catch (const Error&) {
      device = nullptr;
    }
  }
  return device;
}

#define BRDFBAKE_REQUIRE_DEVICE(dev)                                                              \
  ::brdfbake::Device* dev = ::brdfbake::test::test_device();                                      \
  if (!dev) {                                                                                     \
    if (::brdfbake::test::allow_no_device()) GTEST_SKIP() << "no OpenCL device (allowed)";        \
    FAIL() << "this test needs an OpenCL device and found none; install pocl-opencl-icd, or set " \
              "BRDFBAKE_ALLOW_NO_DEVICE=1 to skip";                                               \
  }

#define BRDFBAKE_REQUIRE_FP64(dev) \
  if (!dev->info().fp64) GTEST_SKIP() << "device '" << dev->info().name << "' has no fp64";

}  // namespace brdfbake::test
