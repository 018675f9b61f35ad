// The two backends behind brdfbake::Backend: an OpenCL device and the scalar double reference. A
// moved family's kernels are made by the factories it registered (families/kernels.hpp); each entry
// left here forwards to a family's device code or to its reference code; nothing else in the product
// chooses between them.
#include "brdfbake/backend.hpp"

// AddressSanitizer cannot free the thread-local storage of the libraries a thread loaded when that
// thread ends ("failed to deallocate ... unable to unmap" at the end of the std::async thread that
// loaded PoCL and LLVM): ASan builds (BRDFBAKE_ASAN) open the device on first use, on the calling
// thread.

#include <cmath>
#include <future>
#include <optional>

#include "brdfbake/error.hpp"

namespace brdfbake {

namespace {

// The device is opened on first use: work that needs none (SH of an environment, which is computed
// on the host) opens no OpenCL platform at all.
class OpenClBackend final : public Backend {
 public:
  explicit OpenClBackend(std::string selector) : selector_(std::move(selector)) {}
  explicit OpenClBackend(Device device) : device_(std::move(device)) {}
  bool is_reference() const override { return false; }
  // The device's name once it was used; work that needed none ran on the host.
  std::string name() const override { return device_ ? device_->info().name : std::string("host (no device used)"); }
  Device* device() override { return &opened(); }
  void prepare() override {
#ifndef BRDFBAKE_ASAN
    if (!device_ && !opening_.valid())
      opening_ = std::async(std::launch::async, [selector = selector_] { return Device::open(selector); });
#endif
  }
  Precision result_precision(Precision requested) const override { return requested; }

 private:
  Device& opened() {
    if (!device_) device_ = opening_.valid() ? opening_.get() : Device::open(selector_);
    return *device_;
  }
  std::string selector_;
  std::optional<Device> device_;
  std::future<Device> opening_;  // prepare()'s
};

class ReferenceBackend final : public Backend {
 public:
  bool is_reference() const override { return true; }
  std::string name() const override { return "reference"; }
  Device* device() override { return nullptr; }
  Precision result_precision(Precision) const override { return Precision::Fp64; }
};

}  // namespace

std::shared_ptr<Backend> Backend::open(const std::string& selector) {
  if (selector == "reference") return std::make_shared<ReferenceBackend>();
  return std::make_shared<OpenClBackend>(selector);
}

std::shared_ptr<Backend> Backend::open(const Device& device) { return std::make_shared<OpenClBackend>(device); }

}  // namespace brdfbake
