// Internal: the open backend's kernel factories (OpenMM's KernelFactory per platform). Each family
// declares its kernel interface in host/src/families/<family>/kernel.hpp (a BackendKernel with a
// static kName and the calls the family needs) and registers one implementation per platform in
// Family::register_kernels; Backend::create_kernel finds the factory by name and platform, so that
// brdfbake/backend.hpp and host/src/backend.cpp never change when a family is added.
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "brdfbake/backend.hpp"

namespace brdfbake::detail {

enum class Platform { OpenCl, Reference };

inline Platform platform_of(const Backend& backend) {
  return backend.is_reference() ? Platform::Reference : Platform::OpenCl;
}

// Makes a kernel for `backend` (an OpenCL implementation opens its device with backend.device()).
using KernelFactory = std::function<std::unique_ptr<BackendKernel>(Backend& backend)>;

class KernelRegistry {
 public:
  // Registers `factory` for kernel K on `platform`; `factory(Backend&)` returns a
  // std::unique_ptr to an implementation of K.
  template <class K, class F>
  void add(Platform platform, F factory) {
    add(K::kName, platform, [f = std::move(factory)](Backend& b) -> std::unique_ptr<BackendKernel> {
      std::unique_ptr<K> k = f(b);
      return k;
    });
  }
  void add(std::string name, Platform platform, KernelFactory factory);
  // The factory of kernel `name` on `platform`, or nullptr.
  const KernelFactory* find(const std::string& name, Platform platform) const;

 private:
  struct Entry {
    std::string name;
    Platform platform;
    KernelFactory factory;
  };
  std::vector<Entry> entries_;
};

// Every family's factories (Family::register_kernels, in the order of families()), made once.
const KernelRegistry& kernel_registry();

// Calls `call(K&)` with `backend`'s implementation of kernel K, under the backend's call lock
// (Backend::lock_calls); returns what `call` returns.
template <class K, class F>
auto run_kernel(Backend& backend, F&& call) -> decltype(call(std::declval<K&>())) {
  const std::unique_lock<std::mutex> lock = backend.lock_calls();
  const std::unique_ptr<BackendKernel> kernel = backend.create_kernel(K::kName);
  return call(static_cast<K&>(*kernel));
}

}  // namespace brdfbake::detail
