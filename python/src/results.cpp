#include "results.hpp"

#include <pybind11/stl.h>

#include <filesystem>

#include "brdfbake/error_figures.hpp"
#include "brdfbake/output_checks.hpp"
#include "convert.hpp"

namespace brdfbake::python {

namespace {

// A read-only float32 view of `data` owned by `owner` (the Result): NumPy holds a reference to the
// owner for as long as the array (or any view of it) lives.
py::array view(const py::handle& owner, const float* data, std::vector<py::ssize_t> shape,
               std::vector<py::ssize_t> strides_in_floats) {
  std::vector<py::ssize_t> strides;
  for (py::ssize_t s : strides_in_floats) strides.push_back(s * static_cast<py::ssize_t>(sizeof(float)));
  py::array_t<float> a(shape, strides, data, owner);
  a.attr("flags").attr("writeable") = false;
  return std::move(a);
}

const char* artifact_name(const BakeResult& r) {
  if (r.table()) return "table";
  if (r.cube()) return "cube";
  if (r.irradiance()) return "irradiance";
  if (r.merl()) return "merl";
  if (r.eval()) return "eval";
  if (r.preview()) return "preview";
  return "none";
}

// The levels of a cube as (6, s, s, 3) views of its RGBA texels (alpha, always 1, left out).
py::list cube_views(const py::handle& owner, const CubeLevels& cube) {
  py::list levels;
  for (int l = 0; l < cube.level_count(); ++l) {
    const py::ssize_t s = cube.level_size(l);
    levels.append(view(owner, cube.levels[static_cast<size_t>(l)].data(), {6, s, s, 3}, {s * s * 4, s * 4, 4, 1}));
  }
  return levels;
}

py::array sh_array(const std::vector<double>& values, int order) {
  py::array_t<double> a({static_cast<py::ssize_t>(order) * order, py::ssize_t(3)});
  std::copy(values.begin(), values.end(), a.mutable_data());
  return std::move(a);
}

py::dict error_stats(const PreviewErrorStats& e) {
  py::dict d;
  d["rms"] = e.rms;
  d["p99"] = e.p99;
  d["max"] = e.max;
  return d;
}

py::tuple vec3(const Vec3& v) { return py::make_tuple(v.x, v.y, v.z); }
py::tuple rgb(const Rgb& c) { return py::make_tuple(c.r, c.g, c.b); }

// A preview's renders as (height, width, 3) views, and every number of its JSON.
py::dict preview_dict(const py::handle& owner, const PreviewResult& p) {
  py::dict d;
  const auto image = [&](const PreviewImage& i) -> py::object {
    if (i.rgb.empty()) return py::none();
    const py::ssize_t w = i.width, h = i.height;
    return view(owner, i.rgb.data(), {h, w, 3}, {w * 3, 3, 1});
  };
  d["splitsum"] = image(p.splitsum);
  d["reference"] = image(p.reference);
  py::list spheres;
  for (size_t s = 0; s < p.spheres.size(); ++s) {
    const PreviewSphere& sp = p.spheres[s];
    py::dict e;
    e["name"] = sp.material.name;
    e["base_color"] = rgb(sp.material.base_color);
    e["metallic"] = sp.material.metallic;
    e["roughness"] = sp.material.roughness;
    e["f0"] = rgb(preview_f0(sp.material));
    e["diffuse_color"] = rgb(preview_diffuse_color(sp.material));
    e["row"] = sp.row;
    e["column"] = sp.column;
    e["centre"] = py::make_tuple(sp.centre_x, sp.centre_y);
    e["radius"] = sp.radius;
    if (s < p.stats.size()) {
      const PreviewSphereStats& st = p.stats[s];
      e["pixels"] = st.pixels;
      e["linear"] = error_stats(st.linear);
      e["srgb8"] = error_stats(st.srgb8);
      py::dict b;
      b["rms"] = st.reference_rms_bound;
      b["max"] = st.reference_max_bound;
      b["pixels"] = st.bound_pixels;
      b["refinement"] = st.refinement;
      e["reference_bound"] = b;
      if (!p.ideal.rgb.empty()) {
        e["engine_share"] = error_stats(st.engine_share);
        e["bake_share"] = error_stats(st.bake_share);
      }
    }
    spheres.append(e);
  }
  d["spheres"] = spheres;
  py::dict camera;
  camera["view_direction"] = vec3(p.camera.view_direction);
  camera["up"] = vec3(p.camera.up);
  camera["right"] = vec3(p.camera.right);
  camera["yaw"] = p.camera.yaw;
  camera["pitch"] = p.camera.pitch;
  camera["background_fov"] = p.camera.background_fov;
  d["camera"] = camera;
  d["target"] = std::string(engine_target_name(p.spec.target));
  d["brdf"] = p.brdf;
  d["multiscatter"] = p.multiscatter;
  d["exposure"] = p.exposure;
  d["environment_median"] = p.environment_median;
  d["environment_model"] = p.environment_model;
  d["bound_definition"] = p.bound_definition;
  d["bake"] = metadata_dict(p.bake);
  d["shading"] = metadata_dict(p.shading);
  py::dict t;
  t["bake"] = p.times.bake;
  t["read"] = p.times.read;
  t["splitsum"] = p.times.splitsum;
  t["reference"] = p.times.reference;
  t["reference_device"] = p.times.reference_device;
  t["bound"] = p.times.bound;
  t["total"] = p.times.total;
  t["ideal"] = p.times.ideal;
  d["times"] = t;
  // the error's shares (PreviewSpec::shares): the ideal bake's render, what it holds, the groups
  d["ideal"] = image(p.ideal);
  if (!p.ideal.rgb.empty()) {
    d["ideal_bake"] = metadata_dict(p.ideal_bake);
    py::list groups;
    for (const PreviewShareGroup& g : p.share_groups) {
      py::dict e;
      e["name"] = g.name;
      e["spheres"] = g.spheres;
      const auto pair = [](double median, double worst) {
        py::dict x;
        x["median"] = median;
        x["worst"] = worst;
        return x;
      };
      e["error"] = pair(g.error_median, g.error_worst);
      e["engine_share"] = pair(g.engine_median, g.engine_worst);
      e["bake_share"] = pair(g.bake_median, g.bake_worst);
      groups.append(e);
    }
    d["share_groups"] = groups;
  }
  return d;
}

// The float32 copy of a MERL table (theta_h, theta_d, phi_d, channel) or of eval values (pair, channel).
void convert(PyResult& r) {
  std::call_once(r.converted_once, [&] {
    if (const MerlTable* m = r.result.merl()) {
      r.converted.resize(3 * kMerlBins);
      for (size_t c = 0; c < 3; ++c)
        for (size_t b = 0; b < kMerlBins; ++b)
          r.converted[3 * b + c] = static_cast<float>(m->values[c * kMerlBins + b]);
    } else if (const EvalResult* e = r.result.eval()) {
      r.converted.assign(e->values.begin(), e->values.end());
    }
  });
}

// Writes the result as the runner delivers it; returns the warnings of this write.
std::vector<std::string> save(PyResult& r, const std::string& path, const std::string& format, const std::string& pixel,
                              const py::list& output_params) {
  TableRequest t = r.request;
  const std::string prefix = r.prefix + ".save";
  const FieldNaming naming{prefix, false};
  t.output = path;
  t.format = format;
  if (!pixel.empty()) t.pixel = pixel;
  const auto& schema = table_schema(t.kind);
  for (const py::handle item : output_params) {
    const auto pair = item.cast<py::tuple>();
    const std::string name = pair[0].cast<std::string>();
    const ParamDef* d = find_param_def(schema, name);
    if (!d || !d->output_only) {
      std::string names;
      for (const auto& o : schema)
        if (o.output_only) names += (names.empty() ? "" : ", ") + o.name;
      throw Error(naming.field(t.kind, name) + ": not an output parameter of " + table_kind_name(t.kind) +
                  " (save takes path, format, pixel" + (names.empty() ? "" : ", " + names) +
                  "; parameters of what is baked go to the baking call)");
    }
    const ParamValue v = to_param(pair[1], naming.field(t.kind, name));
    t.set(name, v);
  }
  if (t.kind == TableKind::Eval) {
    // The bytes follow the file name: float32 for .f32 .bin .raw, CSV otherwise.
    std::string ext = std::filesystem::path(path).extension().string();
    for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    t.set("binary", ext == ".f32" || ext == ".bin" || ext == ".raw");
  }
  validate_table(t, naming);
  TableRequest baked = r.request;
  if (t.kind == TableKind::Eval) baked.set("binary", t.flag("binary"));  // how it is written, not what
  if (table_bake_key(t) != table_bake_key(baked)) {
    // The output asks for a different table (an irradiance cube from a result baked as SH only, ...).
    std::string what;
    for (const Param& p : t.params) {
      const ParamValue* before = r.request.find(p.name);
      if (!before || param_value_text(*before) != param_value_text(p.value))
        what += (what.empty() ? "" : ", ") + p.name + "=" + param_value_text(p.value);
    }
    throw Error(prefix + ": '" + path + "' needs a table baked with " + (what.empty() ? "other parameters" : what) +
                "; bake it with them (or save to another format)");
  }
  t.output = path;  // written where asked, even where validation named a default ("" is refused there)
  check_table_files(t, naming, false);  // no output on an input (brdfbake/output_checks.hpp)
  Delivery d;
  {
    const py::gil_scoped_release release;
    d = deliver_result(r.result, t, TableDelivery::File);
  }
  r.files.push_back(written_file(path, d));
  for (const auto& w : d.warnings) r.warnings.push_back(w);
  return d.warnings;
}

py::dict file_dict(const WrittenFile& f) {
  py::dict d;
  d["path"] = f.path;
  d["error"] = f.error_bound ? py::object(py::float_(*f.error_bound)) : py::object(py::none());
  d["storage_error"] = f.storage_error;
  d["encoding"] = f.encoding;
  d["warnings"] = f.warnings;
  return d;
}

}  // namespace

WrittenFile written_file(const std::string& path, const Delivery& delivery) {
  WrittenFile f;
  f.path = path;
  f.error_bound = delivery.error_bound;
  f.storage_error = delivery.report.storage_error;
  f.encoding = delivery.report.encoding;
  f.warnings = delivery.warnings;
  return f;
}

void bind_results(py::module_& module) {
  py::class_<PyResult, std::shared_ptr<PyResult>>(module, "Result", "A baked table (see brdfbake.Result)")
      .def_property_readonly("kind", [](const PyResult& r) { return std::string(table_kind_name(r.result.kind)); })
      .def_property_readonly("artifact", [](const PyResult& r) { return std::string(artifact_name(r.result)); })
      .def_property_readonly("summary", [](const PyResult& r) { return r.result.summary; })
      .def_property_readonly("device", [](const PyResult& r) { return r.result.device; })
      .def_property_readonly("seconds", [](const PyResult& r) { return r.result.seconds; })
      .def_property_readonly("device_seconds", [](const PyResult& r) { return r.result.device_seconds; })
      // the figure error_name names (brdfbake.Result.error; error_bound is its deprecated alias there)
      .def_property_readonly("error",
                             [](const PyResult& r) -> py::object {
                               if (r.result.error_bound) return py::float_(*r.result.error_bound);
                               return py::none();
                             })
      .def_property_readonly("error_measurement", [](const PyResult& r) { return r.result.error_bound_definition; })
      .def_property_readonly("error_name",
                             [](const PyResult& r) { return std::string(error_figure(r.result.kind).name); })
      .def_property_readonly("error_definition",
                             [](const PyResult& r) { return std::string(error_figure(r.result.kind).definition); })
      .def_property_readonly("parameters",
                             [](const PyResult& r) { return params_dict(r.result.parameters, r.result.kind); })
      .def_property_readonly("details", [](const PyResult& r) { return metadata_dict(r.result.details); })
      .def_property_readonly("request", [](const PyResult& r) { return request_dict(r.request); })
      .def_property_readonly("metadata",
                             [](const PyResult& r) -> py::dict {
                               // What the file carries: the artifact's own metadata (irradiance: see sh_json).
                               if (const Table* t = r.result.table()) return metadata_dict(t->metadata);
                               if (const CubeLevels* c = r.result.cube()) return metadata_dict(c->metadata);
                               if (const IrradianceResult* i = r.result.irradiance())
                                 return metadata_dict(i->cube.metadata);
                               if (const MerlTable* m = r.result.merl()) return metadata_dict(m->metadata);
                               if (const EvalResult* e = r.result.eval()) return metadata_dict(e->metadata);
                               return {};
                             })
      .def("table_array",
           [](py::object self) -> py::object {
             const PyResult& r = self.cast<const PyResult&>();
             const Table* t = r.result.table();
             if (!t) return py::none();
             const py::ssize_t c = t->channel_count(), w = t->width, h = t->height;
             return view(self, t->data.data(), {h, w, c}, {w * c, c, 1});
           })
      .def("table_axes",
           [](const PyResult& r) -> py::object {
             const Table* t = r.result.table();
             if (!t) return py::none();
             py::dict d;
             d["channels"] = t->channels;
             d["x_name"] = t->x_name;
             d["y_name"] = t->y_name;
             d["x"] = py::array_t<double>(static_cast<py::ssize_t>(t->x.size()), t->x.data());
             d["y"] = py::array_t<double>(static_cast<py::ssize_t>(t->y.size()), t->y.data());
             return std::move(d);
           })
      .def("cube_levels",
           [](py::object self) -> py::object {
             const PyResult& r = self.cast<const PyResult&>();
             if (const CubeLevels* c = r.result.cube()) return cube_views(self, *c);
             if (const IrradianceResult* i = r.result.irradiance())
               if (i->cube.level_count() > 0) return cube_views(self, i->cube);
             return py::none();
           })
      .def("sh",
           [](const PyResult& r) -> py::object {
             const IrradianceResult* i = r.result.irradiance();
             if (!i) return py::none();
             py::dict d;
             d["order"] = i->sh.order;
             d["radiance"] = sh_array(i->sh.radiance, i->sh.order);
             d["irradiance_over_pi"] = sh_array(i->sh.irradiance_over_pi, i->sh.order);
             d["window"] = sh_window_name(i->sh.window);
             d["window_weights"] = i->sh.window_weights;
             return std::move(d);
           })
      .def("sh_json",
           [](const PyResult& r) -> py::object {
             const IrradianceResult* i = r.result.irradiance();
             if (!i) return py::none();
             Metadata m;
             for (const auto& [k, v] : r.result.details)
               if (k == "source" || k == "source_size") m.push_back({k, v});
             return py::str(sh_to_json(i->sh, m));
           })
      .def("converted_array",
           [](py::object self) -> py::object {
             PyResult& r = self.cast<PyResult&>();
             if (r.result.merl()) {
               {
                 const py::gil_scoped_release release;
                 convert(r);
               }
               return view(self, r.converted.data(), {kMerlThetaH, kMerlThetaD, kMerlPhiD, 3},
                           {kMerlThetaD * kMerlPhiD * 3, kMerlPhiD * 3, 3, 1});
             }
             if (const EvalResult* e = r.result.eval()) {
               convert(r);
               return view(self, r.converted.data(), {static_cast<py::ssize_t>(e->pairs), 3}, {3, 1});
             }
             return py::none();
           })
      .def("preview",
           [](py::object self) -> py::object {
             const PyResult& r = self.cast<const PyResult&>();
             if (const PreviewResult* p = r.result.preview()) return preview_dict(self, *p);
             return py::none();
           })
      .def_property_readonly("warnings", [](const PyResult& r) { return r.warnings; })
      .def_property_readonly("files",
                             [](const PyResult& r) {
                               py::list out;
                               for (const auto& f : r.files) out.append(file_dict(f));
                               return out;
                             })
      .def("save", &save, py::arg("path"), py::arg("format") = "", py::arg("pixel") = "",
           py::arg("output_params") = py::list());
}

}  // namespace brdfbake::python
