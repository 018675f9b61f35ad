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
#include <cstdint>
#include <filesystem>

#include "backends.hpp"
#include "brdfbake/environment.hpp"
#include "brdfbake/job.hpp"
#include "brdfbake/output_checks.hpp"
#include "brdfbake/plan.hpp"
#include "brdfbake/runner.hpp"
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
    d["kernel_shape"] = i.kernel_shape;
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
  // On the shape, before the array is made contiguous or copied (a broadcast view takes no memory
  // until it is).
  EnvLoadOptions o;
  o.sanitize = sanitize;
  check_environment_size(static_cast<std::uint64_t>(a.shape(1)), static_cast<std::uint64_t>(a.shape(0)), source, o);
  const auto c = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(a);
  const int h = static_cast<int>(a.shape(0)), w = static_cast<int>(a.shape(1));
  std::vector<float> rgb(c.data(), c.data() + c.size());
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
  // Every file it writes (its output and what is written beside it) against what it reads, as the
  // command line checks them (brdfbake/output_checks.hpp).
  if (write_now) check_table_files(t, FieldNaming{prefix, false}, false);

  TableRunOptions o;
  o.delivery = write_now ? TableDelivery::File : TableDelivery::Memory;
  o.open_backend = shared_backend;  // the process's devices, opened once and reused
  std::shared_ptr<const EnvImage> env;
  if (table_kind_uses_environment(t.kind)) {
    if (environment.is_none()) throw Error(prefix + ": needs an environment");
    env = environment.cast<const PyEnvironment&>().image;
    o.inputs.environment = env.get();
  }
  py::array_t<double> pair_array;
  if (t.kind == TableKind::Eval) {
    pair_array = py::array_t<double, py::array::c_style>::ensure(pairs);
    if (!pair_array || pair_array.ndim() != 2 || pair_array.shape(1) != 6)
      throw Error(prefix + ": expected the pairs as a float64 array of shape (n, 6)");
    o.inputs.pairs = pair_array.data();
    o.inputs.pair_count = static_cast<size_t>(pair_array.shape(0));
  }
  o.progress = python_progress(progress);
  TableRun run;
  {
    const py::gil_scoped_release release;
    run = run_table(t, o);
  }
  r->result = std::move(run.result);
  r->warnings = run.warnings;
  if (write_now) r->files.push_back(written_file(t.output, run.delivery));
  return r;
}

// Returns the manifest as JSON and the warnings the writes gave (the package emits each as a
// brdfbake.BakeWarning, as `brdfbake run` prints them).
std::pair<std::string, std::vector<std::string>> run(const std::string& job_text, bool is_path,
                                                     const std::string& origin, const std::string& output_dir,
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
  std::vector<std::string> warnings;
  {
    const py::gil_scoped_release release;
    RunHooks hooks;
    hooks.backend = shared_backend;  // the process's devices, opened once and reused
    hooks.on_warning = [&warnings](const std::string& w) { warnings.push_back(w); };
    m = run_job(job, job_progress, hooks);
  }
  return {manifest_to_json(m), warnings};
}

// The scene planner (`brdfbake bake`): the job that bakes what `scene`'s materials call for (the
// standard set when `scene` is empty), as a job document with its "plan" section. `options` are
// [(name, value), ...] of plan_schema(), checked as the command line and the server check them.
std::string plan(const std::string& scene, const py::list& options, const std::string& environment, bool sanitize,
                 const std::string& pixel, const std::string& precision, const std::string& device) {
  Params given;
  if (!scene.empty()) given.push_back({"scene", scene});
  given.push_back({"environment", environment});
  given.push_back({"sanitize", sanitize});
  if (!pixel.empty()) given.push_back({"pixel", pixel});
  given.push_back({"precision", precision});
  if (!device.empty()) given.push_back({"device", device});
  for (const py::handle item : options) {
    const auto pair = item.cast<py::tuple>();
    const std::string name = pair[0].cast<std::string>();
    given.push_back({name, to_param(pair[1], "bake_scene." + name)});
  }
  OptionNaming naming;
  naming.prefix = "bake_scene";
  naming.dotted = true;
  naming.unknown = "unknown option";
  const BakeOptions o = parse_bake_options(given, naming);
  const py::gil_scoped_release release;  // reading a large .glb
  return plan_to_json(plan_bake(o));
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
  // The schemas as `brdfbake kinds --json` writes them (one serialisation, brdfbake/params.hpp).
  m.def("kinds_json", [] { return table_kinds_json(); });
  m.def("common_fields", [] { return table_common_fields(); });
  m.def("devices", &devices);
  m.def("set_kernel_shape", [](const std::string& shape) { set_kernel_shape(shape); });
  m.def("opened_backends", &opened_backends);
  m.def("open_backend", [](const std::string& selector) {
    const py::gil_scoped_release release;
    return shared_backend(selector)->name();
  });

  py::class_<PyEnvironment>(m, "Environment", "A loaded environment map (see brdfbake.load_environment)")
      .def_static("load", &load_env, py::arg("spec"), py::arg("sanitize") = false)
      .def_static("from_array", &env_from_array, py::arg("array"), py::arg("sanitize") = false,
                  py::arg("source") = "array")
      .def_property_readonly("layout",
                             [](const PyEnvironment& e) {
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

  m.def("default_memory_budget", [] { return default_memory_budget(); });
  m.def("check_environment_size", [](std::uint64_t width, std::uint64_t height, const std::string& source) {
    check_environment_size(width, height, source);
  });
  m.def("validate", &validate, py::arg("kind"), py::arg("params"), py::arg("common"), py::arg("prefix"));
  m.def("bake", &bake, py::arg("kind"), py::arg("params"), py::arg("common"), py::arg("prefix"),
        py::arg("environment") = py::none(), py::arg("pairs") = py::none(), py::arg("progress") = py::none());
  m.def("run", &run, py::arg("job"), py::arg("is_path"), py::arg("origin"), py::arg("output_dir"),
        py::arg("sanitize") = false, py::arg("progress") = py::none());
  m.def("plan", &plan, py::arg("scene"), py::arg("options"), py::arg("environment"), py::arg("sanitize"),
        py::arg("pixel"), py::arg("precision"), py::arg("device"));
  m.def("plan_schema_json", [] { return schema_json(plan_schema()); });
}
