// The Python package's backends: one per device per process, opened on first use and reused by every
// later call (tables, evaluations, jobs), each behind a lock so that Python threads, which release
// the GIL during device work, never use one device's queue and buffers at the same time.
#pragma once

#include <memory>
#include <string>

#include "brdfbake/backend.hpp"

namespace brdfbake::python {

// The backend a selector names ("" = $BRDFBAKE_DEVICE, else the default device; "reference"; "P:D",
// "cpu", "gpu", a name): selectors naming the same device share one backend. Call without the GIL.
std::shared_ptr<Backend> shared_backend(const std::string& selector);

// How many backends this process has opened (tests check that devices are reused).
int opened_backends();

}  // namespace brdfbake::python
