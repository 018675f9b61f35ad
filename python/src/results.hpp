// A baked result as the Python package sees it: the library's BakeResult, the request it was baked
// from, and NumPy views of its float buffers that keep the result alive (no copy where the layout
// allows: tables and cube levels; MERL tables and evaluations are float64 and are converted once).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <mutex>
#include <string>
#include <vector>

#include "brdfbake/tables.hpp"

namespace brdfbake::python {

namespace py = pybind11;

struct PyResult {
  BakeResult result;
  TableRequest request;
  std::string prefix;  // how messages name the call ("lut", "tabulate", ...)

  // float32 copies of float64 artifacts (MERL, eval), made on first use.
  std::once_flag converted_once;
  std::vector<float> converted;
};

// Adds class Result to the module.
void bind_results(py::module_& m);

}  // namespace brdfbake::python
