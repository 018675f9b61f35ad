// The backends an identity test body runs on (tests/identities/*.hpp): the scalar double reference
// itself, the OpenCL kernels in fp32 and fp64, and the product's reference backend (the same oracle
// behind brdfbake::Backend, results stored as float32). Each test executable instantiates a body on
// the backends it links: test_reference on the reference, test_device on the OpenCL precisions and
// the reference backend, both through brdfbake::Backend (the model is OpenMM's tests/Test*.h,
// included once per platform).
#pragma once

#include <string>

namespace brdfbake::test {

enum class Backend { Reference, Fp32, Fp64, ReferenceBackend };

inline const char* backend_name(Backend b) {
  switch (b) {
    case Backend::Reference:
      return "reference";
    case Backend::Fp32:
      return "fp32";
    case Backend::Fp64:
      return "fp64";
    case Backend::ReferenceBackend:
      return "reference_backend";
  }
  return "?";
}

// For INSTANTIATE_TEST_SUITE_P: the test's name suffix.
struct BackendName {
  template <class ParamInfo>
  std::string operator()(const ParamInfo& info) const {
    return backend_name(info.param);
  }
};

}  // namespace brdfbake::test
