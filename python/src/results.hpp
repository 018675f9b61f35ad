// A baked result as the Python package sees it: the library's BakeResult, the request it was baked
// from, and NumPy views of its float buffers that keep the result alive (no copy where the layout
// allows: tables and cube levels; MERL tables and evaluations are float64 and are converted once).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "brdfbake/runner.hpp"
#include "brdfbake/tables.hpp"

namespace brdfbake::python {

namespace py = pybind11;

// A file written from a result (output= of the baking call, or save()): what the runner delivered.
struct WrittenFile {
  std::string path;
  std::optional<double> error_bound;  // what the file records
  double storage_error = 0.0;
  std::string encoding;
  std::vector<std::string> warnings;
};
WrittenFile written_file(const std::string& path, const Delivery& delivery);

struct PyResult {
  BakeResult result;
  TableRequest request;
  std::string prefix;  // how messages name the call ("lut", "tabulate", ...)
  // What the run and every write of this result warned about, in order (the package also emits
  // each as a brdfbake.BakeWarning), and the files written.
  std::vector<std::string> warnings;
  std::vector<WrittenFile> files;

  // float32 copies of float64 artifacts (MERL, eval), made on first use.
  std::once_flag converted_once;
  std::vector<float> converted;
};

// Adds class Result to the module.
void bind_results(py::module_& m);

}  // namespace brdfbake::python
