// caustica.render's native half: the options (a command line, built by the
// package from the keywords) parsed by the CLI's own parser, the loaded
// scene handed to the session, the render run by HeldRender
// (host/app/held_render.h) with the GIL released, and the result's parts
// as NumPy arrays and dicts. Between waves the GIL is taken back to run
// Python's signal handlers (Ctrl-C) and the callback; either stops the
// render cleanly, keeping its finished waves.
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <exception>
#include <mutex>

#include "host/app/held_render.h"
#include "host/error.h"
#include "python/module/bindings.h"

namespace caustica::python {
namespace {

struct PyState {
  std::shared_ptr<const RenderState> state;
};

struct PyRender {
  std::shared_ptr<HeldRender> held;
};

// One render at a time in a process: the OpenCL runtime and its program
// cache are shared (Runtime::shared). A second thread's render waits, with
// the GIL released.
std::mutex render_mutex;
// Set while this thread renders: a callback that starts another render
// would wait for its own (render_mutex) forever.
thread_local bool rendering = false;

py::array_t<uint32_t> counts_array(const std::vector<uint32_t>& counts, int width, int height) {
  py::array_t<uint32_t> a({py::ssize_t(height), py::ssize_t(width)});
  std::copy(counts.begin(), counts.end(), a.mutable_data());
  return a;
}

template <typename T>
py::array_t<T> plane_array(const std::vector<T>& values, int width, int height) {
  py::array_t<T> a({py::ssize_t(height), py::ssize_t(width)});
  std::copy(values.begin(), values.end(), a.mutable_data());
  return a;
}

py::object optional_number(const std::optional<double>& v) { return v ? py::object(py::float_(*v)) : py::none(); }

py::dict stats_dict(const HeldRender& r) {
  const RenderStats& s = r.stats();
  py::dict d;
  uint64_t samples = 0;
  for (uint32_t n : r.pixel_spp()) samples += n;
  d["spp"] = r.spp();
  d["samples"] = samples;
  d["seconds"] = r.seconds();
  d["render_seconds"] = s.render_ms / 1e3;
  d["rays"] = s.rays();
  d["camera_rays"] = s.camera_rays;
  d["secondary_rays"] = s.secondary_rays;
  d["shadow_rays"] = s.shadow_rays;
  d["photon_rays"] = s.photon_rays;
  d["photon_maps"] = s.photon_maps;
  d["photons_stored"] = s.photons_stored;
  d["photon_seconds"] = s.photon_seconds;
  d["caustics"] = r.args().session.caustics == CausticsMode::Off ? "off"
                  : r.stats().photon_maps > 0                   ? "on"
                                                                : "none";
  d["caustics_decision"] = s.caustics_decision;
  d["film_dropped_nonfinite"] = s.film.nonfinite;
  d["film_dropped_negative"] = s.film.negative;
  d["film_clamped"] = s.film.clamped;
  d["stopped_by_callback"] = r.stopped_by_caller();
  return d;
}

py::list report_rows(const HeldRender& r) {
  py::list rows;
  for (const ErrorReportRow& row : r.report().rows) {
    py::dict d;
    d["seconds"] = row.seconds;
    d["spp"] = row.spp;
    d["est_relmse"] = optional_number(row.est_relmse);
    d["mse"] = optional_number(row.mse);
    d["relmse"] = optional_number(row.relmse);
    d["mae"] = optional_number(row.mae);
    d["denoised_est_relmse"] = optional_number(row.denoised_est_relmse);
    d["denoised_relmse"] = optional_number(row.denoised_relmse);
    d["est_relmse_bound"] = optional_number(row.est_relmse_bound);
    rows.append(d);
  }
  return rows;
}

py::dict aovs(const HeldRender& r) {
  const int w = r.image().width, h = r.image().height;
  py::dict d;
  const HeldPasses p = r.passes();
  if (p.beauty) d["beauty"] = to_numpy(*p.beauty);
  if (p.albedo) d["albedo"] = to_numpy(*p.albedo);
  if (p.normal) d["normal"] = to_numpy(*p.normal);
  if (!p.depth.empty()) d["depth"] = plane_array(p.depth, w, h);
  if (!p.variance.empty()) d["variance"] = plane_array(p.variance, w, h);
  if (p.caustics) d["caustics"] = to_numpy(*p.caustics);
  if (!p.caustics_variance.empty()) d["caustics_variance"] = plane_array(p.caustics_variance, w, h);
  d["spp"] = counts_array(r.pixel_spp(), w, h);
  return d;
}

// Returns (Render, interrupted): the package raises RenderInterrupted for
// a Ctrl-C, with the render attached. An exception the callback raised is
// raised again once the render has stopped.
py::tuple render(const PyScene& scene, const std::vector<std::string>& options, const py::object& callback,
                 const py::object& resume, bool write_output) {
  if (rendering)
    translate_errors(ErrorKind::Option, [] {
      throw Error("render: called from a render's callback; renders in one process run one at a time (start it "
                  "after this render returns)");
    });
  std::vector<std::string> args{"render", scene.scene->source_path};
  args.insert(args.end(), options.begin(), options.end());
  std::unique_ptr<Cli> cli = parse_command(args);
  RenderArgs a = cli->render;
  a.session.scene = scene.scene;
  a.write_output = write_output;
  if (!resume.is_none()) a.resume_state = resume.cast<const PyState&>().state;
  bool interrupted = false;
  std::optional<py::error_already_set> raised;
  a.on_wave = [&](const WaveDone& wave) {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {
      raised.emplace();  // takes the KeyboardInterrupt (or a handler's exception)
      interrupted = raised->matches(PyExc_KeyboardInterrupt);
      return false;
    }
    if (callback.is_none()) return true;
    try {
      const py::object go_on = callback(wave.spp, wave.seconds, optional_number(wave.error_estimate));
      return go_on.is_none() || py::bool_(go_on);
    } catch (py::error_already_set& e) {
      raised.emplace(std::move(e));
      return false;
    }
  };
  std::shared_ptr<HeldRender> held;
  std::exception_ptr failure;  // translated once the GIL is held again
  {
    py::gil_scoped_release release;
    std::lock_guard<std::mutex> lock(render_mutex);
    rendering = true;
    try {
      held = std::make_shared<HeldRender>(std::move(a));
    } catch (...) {
      failure = std::current_exception();
    }
    rendering = false;
  }
  if (failure) translate_errors(ErrorKind::Option, [&] { std::rethrow_exception(failure); });
  if (raised && !interrupted) throw std::move(*raised);
  return py::make_tuple(PyRender{held}, interrupted);
}

}  // namespace

void bind_render(py::module_& m) {
  py::class_<PyState>(m, "State", "A path-mode render's state (Render.state()): what caustica.resume continues.")
      .def_property_readonly("spp", [](const PyState& s) { return s.state->film.passes; })
      .def("save",
           [](const PyState& s, const std::string& path) {
             translate_errors(ErrorKind::Option, [&] { write_render_state(path, *s.state); });
           },
           py::arg("path"), "Write it as a state file (what --checkpoint writes; `caustica render --resume` reads it).");
  m.def("load_state", [](const std::string& path) {
    PyState s;
    translate_errors(ErrorKind::Option, [&] { s.state = std::make_shared<const RenderState>(read_render_state(path)); });
    return s;
  }, py::arg("path"));

  py::class_<PyRender>(m, "Render")
      .def_property_readonly("image", [](const PyRender& r) { return to_numpy(r.held->image()); })
      .def_property_readonly("spp", [](const PyRender& r) { return r.held->spp(); })
      .def_property_readonly("mode", [](const PyRender& r) { return std::string(render_mode_name(r.held->mode())); })
      .def_property_readonly("aovs", [](const PyRender& r) {
        py::dict d;
        translate_errors(ErrorKind::Option, [&] { d = aovs(*r.held); });
        return d;
      })
      .def_property_readonly("error_estimate", [](const PyRender& r) { return optional_number(r.held->error_estimate()); })
      .def_property_readonly("error_bound", [](const PyRender& r) { return optional_number(r.held->error_bound()); })
      .def_property_readonly("error_map", [](const PyRender& r) -> py::object {
        const std::vector<double>& map = r.held->error_map();
        if (map.empty()) return py::none();
        return plane_array(map, r.held->image().width, r.held->image().height);
      })
      .def_property_readonly("stats", [](const PyRender& r) { return stats_dict(*r.held); })
      .def_property_readonly("report", [](const PyRender& r) { return report_rows(*r.held); })
      .def("save", [](const PyRender& r, const std::string& path) {
        translate_errors(ErrorKind::Option, [&] { r.held->save(path); });
      }, py::arg("path"))
      .def("state", [](const PyRender& r) {
        PyState s;
        translate_errors(ErrorKind::Option, [&] { s.state = std::make_shared<const RenderState>(r.held->state()); });
        return s;
      });
  m.def("render", &render, py::arg("scene"), py::arg("options"), py::arg("callback"), py::arg("resume"),
        py::arg("write_output"));
}

}  // namespace caustica::python
