// caustica.load and caustica.load_dict: a scene read by the CLI's loader
// (host/scene/load_scene.h), from a file or from a Python dict with the
// file's structure (Mitsuba's load_dict habit). Inline meshes take NumPy
// arrays ("vertices", "indices", "normals", "uvs"; scenes/FORMAT.md).
// Loader warnings become Python warnings (caustica.SceneWarning).
#include <nlohmann/json.hpp>
#include <pybind11/stl.h>

#include <filesystem>
#include <optional>

#include "host/scene/load_scene.h"
#include "python/module/bindings.h"

namespace caustica::python {
namespace {

using json = nlohmann::json;

// A dict, list, tuple, str, bool, int, float, None, NumPy array or NumPy
// scalar as JSON; anything else raises SceneError naming its pointer.
json to_json(const py::handle& v, const std::string& pointer, const std::string& name) {
  if (v.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
  if (py::isinstance<py::int_>(v)) {
    // Beyond 64 bits no scene value is meant: the loader's range check
    // names it (as a double).
    try {
      return v.cast<long long>();
    } catch (const py::cast_error&) {
      return v.cast<double>();
    }
  }
  if (py::isinstance<py::float_>(v)) return v.cast<double>();
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::isinstance<py::dict>(v)) {
    json object = json::object();
    for (const auto& [key, value] : v.cast<py::dict>()) {
      if (!py::isinstance<py::str>(key))
        throw Error(name + ": " + (pointer.empty() ? "/" : pointer) + ": expected string keys, got the key " +
                    std::string(py::repr(key)));
      const std::string k = key.cast<std::string>();
      object[k] = to_json(value, pointer + "/" + k, name);
    }
    return object;
  }
  if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) {
    json array = json::array();
    size_t i = 0;
    for (const py::handle item : v) array.push_back(to_json(item, pointer + "/" + std::to_string(i++), name));
    return array;
  }
  // NumPy arrays and scalars (and anything else with .tolist(): their
  // values as Python numbers, which the loader checks like any other).
  if (py::isinstance<py::array>(v) || py::hasattr(v, "tolist")) return to_json(v.attr("tolist")(), pointer, name);
  throw Error(name + ": " + (pointer.empty() ? "/" : pointer) +
              ": expected a dict, list, tuple, str, bool, int, float, None or NumPy array, got a " +
              std::string(py::str(v.get_type().attr("__name__"))));
}

void warn(const std::vector<std::string>& warnings) {
  const py::object category = py::module_::import("caustica._caustica").attr("SceneWarning");
  for (const std::string& w : warnings)
    if (PyErr_WarnEx(category.ptr(), w.c_str(), 2) != 0) throw py::error_already_set();  // warnings as errors
}

PyScene load_path(const std::string& path, bool strict, std::optional<int> camera) {
  PyScene out;
  LoadOptions options;
  options.strict = strict;
  options.gltf_camera = camera;
  options.warnings = &out.warnings;
  translate_errors(ErrorKind::Scene, [&] {
    if (camera && *camera < 0) throw Error("camera=" + std::to_string(*camera) + ": expected a glTF camera index >= 0");
    out.scene = std::make_shared<const Scene>(load_scene(path, options));
  });
  warn(out.warnings);
  return out;
}

PyScene load_dict(const py::dict& d, const std::string& base_dir, const std::string& name, bool strict) {
  PyScene out;
  LoadOptions options;
  options.strict = strict;
  options.warnings = &out.warnings;
  translate_errors(ErrorKind::Scene, [&] {
    const json document = to_json(d, "", name);
    out.scene = std::make_shared<const Scene>(load_scene_document(document, name, base_dir, options));
  });
  warn(out.warnings);
  return out;
}

}  // namespace

void bind_scene(py::module_& m) {
  PyObject* warning = PyErr_NewExceptionWithDoc("caustica.SceneWarning",
                                                "What the scene loader warns about (an unknown key, a missing "
                                                "texture drawn as a checker).",
                                                PyExc_UserWarning, nullptr);
  m.add_object("SceneWarning", py::handle(warning));
  py::class_<PyScene>(m, "Scene", "A loaded scene (caustica.load or caustica.load_dict).")
      .def_property_readonly("path", [](const PyScene& s) { return s.scene->source_path; },
                             "The file it came from (or the name given to load_dict).")
      .def_property_readonly("mode", [](const PyScene& s) { return std::string(render_mode_name(s.scene->mode)); },
                             "The scene's own rendermode: binary, phong or path.")
      .def_property_readonly("width", [](const PyScene& s) { return s.scene->camera.width; })
      .def_property_readonly("height", [](const PyScene& s) { return s.scene->camera.height; })
      .def_property_readonly("warnings", [](const PyScene& s) { return s.warnings; },
                             "The loader's warnings (also issued as caustica.SceneWarning).")
      .def_property_readonly("counts",
                             [](const PyScene& s) {
                               py::dict d;
                               d["spheres"] = s.scene->spheres.size();
                               d["cylinders"] = s.scene->cylinders.size();
                               d["triangles"] = s.scene->triangles.size();
                               d["lights"] = s.scene->light_count();
                               d["materials"] = s.scene->materials.size();
                               return d;
                             },
                             "How many spheres, cylinders, triangles, lights and materials it has.")
      .def("__repr__", [](const PyScene& s) {
        return "<caustica.Scene '" + s.scene->source_path + "' " + std::to_string(s.scene->camera.width) + "x" +
               std::to_string(s.scene->camera.height) + ", " + std::to_string(s.scene->primitive_count()) +
               " primitives, " + std::to_string(s.scene->light_count()) + " lights>";
      });
  m.def("load", &load_path, py::arg("path"), py::arg("strict") = false, py::arg("camera") = py::none());
  m.def("load_dict", &load_dict, py::arg("d"), py::arg("base_dir") = ".", py::arg("name") = "<dict>",
        py::arg("strict") = false);
}

}  // namespace caustica::python
