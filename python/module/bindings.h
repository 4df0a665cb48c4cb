// The native module's parts (module.cpp says the rules): one file each.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "host/app/cli.h"
#include "host/image/image.h"
#include "host/scene/scene.h"

namespace caustica::python {

namespace py = pybind11;

// errors.cpp: caustica.Error (a ValueError), SceneError, DeviceError, and
// the translation of every C++ exception the core throws.
void bind_errors(py::module_& m);
// Runs `work` and raises the Python exception for what it threw: a
// caustica::Error as `scene_error` says (SceneError or Error), a CLI11
// parse error as Error, an OpenCL error as DeviceError, bad_alloc as
// MemoryError. Never lets a C++ exception reach pybind11's RuntimeError.
enum class ErrorKind { Scene, Option };
void translate_errors(ErrorKind kind, const std::function<void()>& work);

// scene.cpp: Scene, load, load_dict.
void bind_scene(py::module_& m);
// The loaded scene a Python Scene holds.
struct PyScene {
  std::shared_ptr<const Scene> scene;
  std::vector<std::string> warnings;
};

// render.cpp: render, Render, State.
void bind_render(py::module_& m);

// tools.cpp: devices, diff, sky.
void bind_tools(py::module_& m);

// An image as a new H x W x 3 float32 array, and back (a C-contiguous
// float32 copy of any H x W x 3 array; `what` names it in errors).
py::array_t<float> to_numpy(const ImageF& image);
ImageF image_from_numpy(const py::handle& array, const std::string& what);

// Parses `args` (the command line after "caustica") with the CLI's parser;
// a parse error raises caustica.Error with CLI11's message.
std::unique_ptr<Cli> parse_command(const std::vector<std::string>& args);

}  // namespace caustica::python
