// Backends: where a family's numbers are computed. Two platforms: an OpenCL device (the product's
// engine) and the scalar double reference (the oracle, slow but converged). Backend::open() is the
// one factory that turns a selector into either. The backend knows no family (model: OpenMM's
// platforms and kernel factories, openmmapi/include/openmm/Kernel.h): each family declares the
// interface of its kernel and registers an implementation per platform from its own folder
// (host/src/families/<family>/); the backend creates them by name (create_kernel), and the family's
// public header bakes on any backend (e.g. bake_lut(Backend&, ...), brdfbake/dfg_lut.hpp).
#pragma once

#include <cstddef>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "brdfbake/device.hpp"

namespace brdfbake {

// One family's calculation on one platform (OpenMM's KernelImpl): the family declares the
// interface (host/src/families/<family>/kernel.hpp) and registers its implementations.
class BackendKernel {
 public:
  virtual ~BackendKernel() = default;
};

class Backend {
 public:
  virtual ~Backend() = default;

  // "reference": the scalar double reference; anything else selects an OpenCL device as
  // select_device() does ("" = $BRDFBAKE_DEVICE, else the default device), opened on first use
  // (work without a device, such as SH alone, opens none); a bad selector throws Error, naming
  // the devices there are, at that first use.
  static std::shared_ptr<Backend> open(const std::string& selector);
  static std::shared_ptr<Backend> open(const Device& device);

  virtual bool is_reference() const = 0;
  // The device's name, "reference", or "host (no device used)" when nothing has needed the device
  // yet (SH alone).
  virtual std::string name() const = 0;
  // The OpenCL device, or nullptr for the reference.
  virtual Device* device() = 0;
  // Starts opening the OpenCL device on a second thread, so that loading the platform (PoCL loads
  // LLVM: ~20 ms) overlaps the caller's reading of its inputs; the first use waits for it and sees
  // its errors. Nothing for the reference or a device already open. Front ends call it only for
  // work that will use the device (table_needs_device).
  virtual void prepare() {}
  // The precision results carry (the reference computes in double whatever is asked).
  virtual Precision result_precision(Precision requested) const = 0;

  // The kernel of `family` ("dfg_lut") on this backend's platform, made by the factory the family
  // registered for it. Throws Error when the family registered none.
  std::unique_ptr<BackendKernel> create_kernel(const std::string& family);
  // Held around every call into a kernel of this backend, and every batch of an evaluator it made:
  // nothing by default. A backend that threads share returns a held lock, so that calls into one
  // device never overlap (the Python package's backends).
  virtual std::unique_lock<std::mutex> lock_calls() { return {}; }
};

}  // namespace brdfbake
