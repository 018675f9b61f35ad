// The backends an identity test body runs on (tests/identities/*.hpp): the scalar double reference
// and the OpenCL kernels in fp32 and fp64. Each test executable instantiates a body on the backends
// it links: test_reference on the reference, test_device on both OpenCL precisions (the model is
// OpenMM's tests/Test*.h, included once per platform).
#pragma once

#include <string>

namespace brdfbake::test {

enum class Backend { Reference, Fp32, Fp64 };

inline const char* backend_name(Backend b) {
  return b == Backend::Reference ? "reference" : b == Backend::Fp32 ? "fp32" : "fp64";
}

// For INSTANTIATE_TEST_SUITE_P: the test's name suffix.
struct BackendName {
  template <class ParamInfo>
  std::string operator()(const ParamInfo& info) const {
    return backend_name(info.param);
  }
};

}  // namespace brdfbake::test
