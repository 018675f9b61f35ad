// The kernel factories of every family (families/kernels.hpp) and Backend::create_kernel, which
// finds one by name and platform.
#include "families/kernels.hpp"

#include "brdfbake/error.hpp"
#include "families/family.hpp"

namespace brdfbake {

namespace detail {

void KernelRegistry::add(std::string name, Platform platform, KernelFactory factory) {
  for (const Entry& e : entries_)
    if (e.name == name && e.platform == platform) throw Error("kernel '" + name + "' registered twice for a platform");
  entries_.push_back({std::move(name), platform, std::move(factory)});
}

const KernelFactory* KernelRegistry::find(const std::string& name, Platform platform) const {
  for (const Entry& e : entries_)
    if (e.name == name && e.platform == platform) return &e.factory;
  return nullptr;
}

const KernelRegistry& kernel_registry() {
  static const KernelRegistry registry = [] {
    KernelRegistry r;
    for (const Family* f : families()) f->register_kernels(r);
    return r;
  }();
  return registry;
}

}  // namespace detail

std::unique_ptr<BackendKernel> Backend::create_kernel(const std::string& family) {
  const detail::KernelFactory* factory = detail::kernel_registry().find(family, detail::platform_of(*this));
  if (!factory)
    throw Error("no family registered a kernel '" + family + "' for the " + (is_reference() ? "reference" : "OpenCL") +
                " backend");
  return (*factory)(*this);
}

}  // namespace brdfbake
