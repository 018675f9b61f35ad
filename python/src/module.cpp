// brdfbake._brdfbake: the extension module under the Python package (python/brdfbake/). It binds
// the library's one way in (brdfbake/tables.hpp: schemas, validation, bake_table, write_result; job.hpp:
// run_job), so that Python, the command line and jobs bake through the same calls. The Python layer
// builds the public functions from the schemas exported here and checks NumPy inputs; this file
// converts, releases the GIL around device work, and turns the library's exceptions into the
// package's (brdfbake/_errors.py).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>

#include "backends.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/plan.hpp"
#include "brdfbake/scene.hpp"
#include "brdfbake/version.hpp"
#include "convert.hpp"
#include "results.hpp"

namespace py = pybind11;
using namespace brdfbake;
using namespace brdfbake::python;

namespace {

// ---- Errors ----------------------------------------------------------------------------------------

// The package's exception classes (brdfbake/_errors.py), kept for the life of the process.
struct ErrorClasses {
  PyObject* error = nullptr;          // brdfbake.Error
  PyObject* input = nullptr;          // brdfbake.InputError: the CLI's exit code 2
  PyObject* device = nullptr;         // brdfbake.DeviceError: an OpenCL failure, exit code 1
  PyObject* not_available = nullptr;  // brdfbake.NotAvailableError: exit code 1
};
ErrorClasses error_classes;

void translate(std::exception_ptr p) {
  try {
    if (p) std::rethrow_exception(p);
  } catch (const py::error_already_set&) {
    throw;  // a Python exception (a progress callback's, KeyboardInterrupt) goes on as it is
  } catch (const py::builtin_exception&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;  // MemoryError
  } catch (const NotAvailableError& e) {
    PyErr_SetString(error_classes.not_available, e.what());
  } catch (const ClError& e) {
    PyErr_SetString(error_classes.device, e.what());
  } catch (const Error& e) {
    PyErr_SetString(error_classes.input, e.what());
  } catch (const std::exception& e) {
    PyErr_SetString(error_classes.error, e.what());
  }
}

// ---- Progress and interruption ------------------------------------------------------------------

// A progress callback into Python (or none), called from device work without the GIL: it takes the
// GIL, checks for Ctrl-C (so a long bake stops at its next step), and calls `callback` if given. A
// Python exception it raises ends the bake and is raised from the baking call.
BakeProgress python_progress(const py::object& callback) {
  return [&callback](double fraction, const std::string& step) {
    const py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (!callback.is_none()) callback(fraction, step);
  };
}

// ---- Schemas -------------------------------------------------------------------------------------

const char* type_name(ParamType t) {
  switch (t) {
    case ParamType::Int: return "int";
    case ParamType::Number: return "number";
    case ParamType::Name: return "name";
    case ParamType::Path: return "path";
    case ParamType::Flag: return "flag";
    case ParamType::Color: return "color";
    case ParamType::Range: return "range";
    case ParamType::IntList: return "int_list";
  }
  return "?";
}

py::list schema_of(const std::string& kind) {
  const TableKind k = table_kind_from_name(kind);
  py::list out;
  for (const ParamDef& d : table_schema(k)) {
    py::dict p;
    p["name"] = d.name;
    p["type"] = type_name(d.type);
    p["lo"] = d.lo;
    p["hi"] = d.hi;
    p["lo_open"] = d.lo_open;
    p["choices"] = d.choices;
    p["default"] = d.fallback ? from_param(*d.fallback, &d) : py::none();
    p["default_text"] = d.default_text;
    p["help"] = d.help;
    p["expectation"] = param_expectation(d);
    p["required"] = d.required;
    p["output_only"] = d.output_only;
    p["max_items"] = d.max_items;
    p["cli"] = "--" + d.cli_name();
    out.append(p);
  }
  return out;
}

py::list kinds() {
  py::list out;
  for (TableKind k : table_kinds()) {
    py::dict d;
    std::string why;
    d["name"] = table_kind_name(k);
    d["command"] = table_kind_command(k);
    d["summary"] = table_kind_summary(k);
    d["uses_environment"] = table_kind_uses_environment(k);
    d["available"] = table_kind_available(k, &why);
    d["why_not"] = why;
    out.append(d);
  }
  return out;
}

py::list devices() {
  std::vector<DeviceInfo> list;
  {
    const py::gil_scoped_release release;
    list = list_devices();
  }
  py::list out;
  for (const DeviceInfo& i : list) {
    py::dict d;
    d["selector"] = std::to_string(i.platform_index) + ":" + std::to_string(i.device_index);
    d["name"] = i.name;
    d["type"] = i.type;
    d["vendor"] = i.vendor;
    d["platform"] = i.platform_name;
    d["version"] = i.version;
    d["driver_version"] = i.driver_version;
    d["compute_units"] = i.compute_units;
    d["global_memory"] = i.global_memory;
    d["max_alloc"] = i.max_alloc;
    d["fp64"] = i.fp64;
    d["default"] = i.is_default;
    out.append(d);
  }
  return out;
}

// ---- Environments --------------------------------------------------------------------------------

struct PyEnvironment {
  std::shared_ptr<const EnvImage> image;
};

PyEnvironment load_env(const std::string& spec, bool sanitize) {
  EnvLoadOptions o;
  o.sanitize = sanitize;
  const py::gil_scoped_release release;
  return {std::make_shared<const EnvImage>(load_environment(spec, o))};
}

PyEnvironment env_from_array(const py::array& a, bool sanitize, const std::string& source) {
  // The Python layer has already refused other dtypes and shapes with a message; this is the guard.
  if (!py::isinstance<py::array_t<float>>(a) || a.ndim() != 3 || a.shape(2) != 3)
    throw Error("environment: expected a float32 array of shape (height, width, 3)");
  if (a.shape(0) > (1 << 16) || a.shape(1) > (1 << 17)) throw Error("environment: the array is too large");
  const auto c = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
  const int h = static_cast<int>(a.shape(0)), w = static_cast<int>(a.shape(1));
  std::vector<float> rgb(c.data(), c.data() + c.size());
  EnvLoadOptions o;
  o.sanitize = sanitize;
  const py::gil_scoped_release release;
  return {std::make_shared<const EnvImage>(environment_from_equirect(w, h, std::move(rgb), source, o))};
}

// ---- Baking --------------------------------------------------------------------------------------

py::dict validate(const std::string& kind, const py::list& params, const py::dict& common, const std::string& prefix) {
  return request_dict(make_request(kind, params, common, prefix));
}

std::shared_ptr<PyResult> bake(const std::string& kind, const py::list& params, const py::dict& common,
                               const std::string& prefix, const py::object& environment, const py::object& pairs,
                               const py::object& progress) {
  auto r = std::make_shared<PyResult>();
  r->prefix = prefix;
  r->request = make_request(kind, params, common, prefix);
  const TableRequest& t = r->request;
  const bool write_now = common.contains("output") && !common["output"].is_none();
  if (write_now && !std::filesystem::path(t.output).extension().empty()) check_output_path(t.output);

  BakeInputs inputs;
  std::shared_ptr<const EnvImage> env;
  if (table_kind_uses_environment(t.kind)) {
    if (environment.is_none()) throw Error(prefix + ": needs an environment");
    env = environment.cast<const PyEnvironment&>().image;
    inputs.environment = env.get();
  }
  py::array_t<double> pair_array;
  if (t.kind == TableKind::Eval) {
    pair_array = py::array_t<double, py::array::c_style>::ensure(pairs);
    if (!pair_array || pair_array.ndim() != 2 || pair_array.shape(1) != 6)
      throw Error(prefix + ": expected the pairs as a float64 array of shape (n, 6)");
    inputs.pairs = pair_array.data();
    inputs.pair_count = static_cast<size_t>(pair_array.shape(0));
  }
  const BakeProgress report = python_progress(progress);
  {
    const py::gil_scoped_release release;
    std::shared_ptr<Backend> backend = shared_backend(t.device);
    r->result = bake_table(t, *backend, inputs, report);
    if (write_now) write_result(r->result, t, t.output);
  }
  return r;
}

std::string run(const std::string& job_text, bool is_path, const std::string& origin, const std::string& output_dir,
                bool sanitize, const py::object& progress) {
  Job job = is_path ? read_job(job_text) : parse_job(job_text, origin);
  if (!output_dir.empty()) job.output_dir = output_dir;
  if (sanitize) job.sanitize = true;
  if (job.output_dir.empty()) throw Error(job.source + ": output_dir: missing (give run(job, output_dir))");
  const JobProgress job_progress = [&](const JobEvent& e) {
    const py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (!progress.is_none()) {
      py::dict d;
      d["bake"] = e.bake;
      d["bakes"] = e.bakes;
      d["what"] = e.what;
      d["fraction"] = e.fraction;
      progress(d);
    }
  };
  Manifest m;
  {
    const py::gil_scoped_release release;
    RunHooks hooks;
    hooks.backend = shared_backend;  // the process's devices, opened once and reused
    m = run_job(job, job_progress, hooks);
  }
  return manifest_to_json(m);
}

// The scene planner (`brdfbake bake`): the job that bakes what `scene`'s materials call for (the
// standard set when `scene` is empty), as a job document with its "plan" section. `options` are
// [(name, value), ...] of plan_schema(), checked as the command line and the server check them.
std::string plan(const std::string& scene, const py::list& options, const std::string& environment, bool sanitize,
                 const std::string& pixel, const std::string& precision, const std::string& device) {
  Params params;
  for (const py::handle item : options) {
    const auto pair = item.cast<py::tuple>();
    const std::string name = pair[0].cast<std::string>();
    const ParamDef* d = find_param_def(plan_schema(), name);
    if (!d) {
      std::string names;
      for (const auto& def : plan_schema()) names += (names.empty() ? "" : ", ") + def.name;
      throw Error("bake_scene: " + name.substr(0, 60) + ": unknown option (expected " + names + ")");
    }
    const ParamValue v = to_param(pair[1], "bake_scene." + name);
    check_param(*d, v, "bake_scene." + name);
    params.push_back({name, v});
  }
  PlanOptions o = plan_options_from_params(params, false);
  o.environment = environment;
  o.sanitize = sanitize;
  if (!pixel.empty() && pixel != "f16" && pixel != "f32")
    throw Error("bake_scene.pixel: must be f16 or f32 (got '" + pixel.substr(0, 20) + "')");
  o.pixel = pixel;
  try {
    o.precision = precision_from_name(precision);
  } catch (const Error& e) {
    throw Error("bake_scene.precision: " + std::string(e.what()));
  }
  o.device = device;
  const py::gil_scoped_release release;  // reading a large .glb
  return plan_to_json(scene.empty() ? plan_default(o) : plan_scene(read_scene(scene), o));
}

}  // namespace

PYBIND11_MODULE(_brdfbake, m) {
  m.doc() = "brdfbake's extension module: use the brdfbake package, not this.";
  m.attr("version") = kVersion;

  const py::module_ errors = py::module_::import("brdfbake._errors");
  for (auto [slot, name] : {std::pair{&error_classes.error, "Error"}, std::pair{&error_classes.input, "InputError"},
                            std::pair{&error_classes.device, "DeviceError"},
                            std::pair{&error_classes.not_available, "NotAvailableError"}}) {
    *slot = errors.attr(name).ptr();
    Py_INCREF(*slot);  // held for the life of the process
  }
  py::register_exception_translator(&translate);

  m.def("kinds", &kinds);
  m.def("schema", &schema_of, py::arg("kind"));
  m.def("common_fields", [] { return table_common_fields(); });
  m.def("devices", &devices);
  m.def("opened_backends", &opened_backends);
  m.def("open_backend", [](const std::string& selector) {
    const py::gil_scoped_release release;
    return shared_backend(selector)->name();
  });

  py::class_<PyEnvironment>(m, "Environment", "A loaded environment map (see brdfbake.load_environment)")
      .def_static("load", &load_env, py::arg("spec"), py::arg("sanitize") = false)
      .def_static("from_array", &env_from_array, py::arg("array"), py::arg("sanitize") = false,
                  py::arg("source") = "array")
      .def_property_readonly("layout", [](const PyEnvironment& e) {
        return std::string(e.image->layout == EnvImage::Layout::Equirect ? "equirect" : "cube");
      })
      .def_property_readonly("width", [](const PyEnvironment& e) { return e.image->width; })
      .def_property_readonly("height", [](const PyEnvironment& e) { return e.image->height; })
      .def_property_readonly("source", [](const PyEnvironment& e) { return e.image->source; })
      .def_property_readonly("description", [](const PyEnvironment& e) { return e.image->description; })
      .def_property_readonly("sanitized", [](const PyEnvironment& e) {
        py::dict d;
        d["nan"] = e.image->sanitize.nan;
        d["infinite"] = e.image->sanitize.infinite;
        d["negative"] = e.image->sanitize.negative;
        d["replaced"] = e.image->sanitize.replaced;
        return d;
      });

  bind_results(m);

  m.def("validate", &validate, py::arg("kind"), py::arg("params"), py::arg("common"), py::arg("prefix"));
  m.def("bake", &bake, py::arg("kind"), py::arg("params"), py::arg("common"), py::arg("prefix"),
        py::arg("environment") = py::none(), py::arg("pairs") = py::none(), py::arg("progress") = py::none());
  m.def("run", &run, py::arg("job"), py::arg("is_path"), py::arg("origin"), py::arg("output_dir"),
        py::arg("sanitize") = false, py::arg("progress") = py::none());
  m.def("plan", &plan, py::arg("scene"), py::arg("options"), py::arg("environment"), py::arg("sanitize"),
        py::arg("pixel"), py::arg("precision"), py::arg("device"));
  m.def("plan_schema", [] {
    py::list out;
    for (const ParamDef& d : plan_schema()) {
      py::dict p;
      p["name"] = d.name;
      p["type"] = type_name(d.type);
      p["choices"] = d.choices;
      p["default"] = d.fallback ? from_param(*d.fallback, &d) : py::none();
      p["help"] = d.help;
      p["cli"] = "--" + d.cli_name();
      out.append(p);
    }
    return out;
  });
}
