#include "backends.hpp"

#include <map>
#include <mutex>

namespace brdfbake::python {

namespace {

// Serialises every call into one backend: every family kernel's call (Backend::create_kernel and the
// call itself) and every batch of an evaluator it made hold this lock. Each is one call into one
// backend, so a lock is never held across two backends (no ordering between devices, no deadlock).
class LockedBackend final : public Backend {
 public:
  explicit LockedBackend(std::shared_ptr<Backend> inner) : inner_(std::move(inner)) {}

  bool is_reference() const override { return inner_->is_reference(); }
  std::string name() const override { return inner_->name(); }
  Device* device() override { return inner_->device(); }
  Precision result_precision(Precision requested) const override { return inner_->result_precision(requested); }

  std::unique_lock<std::mutex> lock_calls() override { return std::unique_lock<std::mutex>(*mutex_); }

 private:
  std::shared_ptr<Backend> inner_;
  std::shared_ptr<std::mutex> mutex_ = std::make_shared<std::mutex>();
};

std::mutex cache_mutex;
// Keyed by the device a selector resolves to ("P:D"), or "reference". Never destroyed: a device's
// OpenCL context must not be released after the ICD loader has unloaded at interpreter exit.
auto* cache = new std::map<std::string, std::shared_ptr<Backend>>();

}  // namespace

std::shared_ptr<Backend> shared_backend(const std::string& selector) {
  std::string key = "reference";
  DeviceInfo info;
  if (selector != "reference") {
    info = select_device(selector);
    key = std::to_string(info.platform_index) + ":" + std::to_string(info.device_index);
  }
  std::lock_guard<std::mutex> lock(cache_mutex);
  auto it = cache->find(key);
  if (it == cache->end()) {
    std::shared_ptr<Backend> inner =
        selector == "reference" ? Backend::open(std::string("reference")) : Backend::open(Device::open(info));
    it = cache->emplace(key, std::make_shared<LockedBackend>(std::move(inner))).first;
  }
  return it->second;
}

int opened_backends() {
  std::lock_guard<std::mutex> lock(cache_mutex);
  return static_cast<int>(cache->size());
}

}  // namespace brdfbake::python
