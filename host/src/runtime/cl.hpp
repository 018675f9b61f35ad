// The one place that includes the OpenCL C++ bindings, with the settings the project uses.
#pragma once

#ifndef CL_HPP_ENABLE_EXCEPTIONS
#define CL_HPP_ENABLE_EXCEPTIONS
#endif
#define CL_HPP_TARGET_OPENCL_VERSION 120
#define CL_HPP_MINIMUM_OPENCL_VERSION 120
#if defined(__GNUC__)
#pragma GCC system_header  // the bindings are not -Wconversion clean
#endif
#include <CL/opencl.hpp>
#include <string>
#include <utility>

#include "brdfbake/error.hpp"

namespace brdfbake::detail {

// Runs f(); an OpenCL exception becomes a ClError naming the call, `what_for` and the error name.
template <class F>
auto cl_call(const std::string& what_for, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const cl::Error& e) {
    throw ClError(e.what(), e.err(), what_for);
  }
}

}  // namespace brdfbake::detail
