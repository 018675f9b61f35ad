// Conversions between Python values and the library's typed parameters, requests and metadata.
#pragma once

#include <pybind11/pybind11.h>

#include <string>

#include "brdfbake/tables.hpp"

namespace brdfbake::python {

namespace py = pybind11;

// A Python value as a parameter value: bool, int or float, str, or a list/tuple of numbers. Anything
// else throws Error naming `field`. (The package's Python layer has already turned NumPy scalars and
// arrays into these.)
ParamValue to_param(const py::handle& value, const std::string& field);
// A parameter value as Python: Int (and IntList) values as int, the rest as they are.
py::object from_param(const ParamValue& value, const ParamDef* def);
// Parameters as an ordered dict of Python values.
py::dict params_dict(const Params& params, TableKind kind);
// Metadata as an ordered dict of str.
py::dict metadata_dict(const Metadata& metadata);

// A request from the Python layer: the kind, [(name, value), ...] and the common fields
// (precision, device, output, format, pixel, environment), validated as a job validates a table,
// fields named "<prefix>.<field>". Throws Error.
TableRequest make_request(const std::string& kind, const py::list& params, const py::dict& common,
                          const std::string& prefix);
// The request as a dict: kind, parameters, precision, device, environment, output, format, pixel.
py::dict request_dict(const TableRequest& request);

}  // namespace brdfbake::python
