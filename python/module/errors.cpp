// The exceptions Python sees. Every error caustica reports is a
// caustica.Error, a ValueError, carrying the core's message unchanged (the
// file, JSON pointer or option and what was expected); the scene loader's
// are caustica.SceneError, OpenCL's caustica.DeviceError.
#include <CL/opencl.hpp>

#include <new>

#include <CLI/CLI.hpp>

#include "host/cl/runtime.h"
#include "host/error.h"
#include "python/module/bindings.h"

namespace caustica::python {
namespace {

PyObject* error_type = nullptr;
PyObject* scene_error_type = nullptr;
PyObject* device_error_type = nullptr;

PyObject* new_exception(py::module_& m, const char* name, PyObject* bases, const char* doc) {
  const std::string qualified = std::string("caustica.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases, nullptr);
  if (!type) throw py::error_already_set();
  m.add_object(name, py::handle(type));
  return type;
}

}  // namespace

void bind_errors(py::module_& m) {
  error_type = new_exception(m, "Error", PyExc_ValueError,
                             "An error caustica reports: a bad option, file or value, with the CLI's message.");
  py::tuple scene_bases = py::make_tuple(py::handle(error_type));
  scene_error_type = new_exception(m, "SceneError", scene_bases.ptr(),
                                   "A scene that cannot be loaded: the message names the file and the JSON pointer.");
  device_error_type = new_exception(m, "DeviceError", scene_bases.ptr(),
                                    "An OpenCL device that failed: the call and the OpenCL error's name.");
}

void translate_errors(ErrorKind kind, const std::function<void()>& work) {
  try {
    work();
  } catch (const py::error_already_set&) {
    throw;
  } catch (const Error& e) {
    PyErr_SetString(kind == ErrorKind::Scene ? scene_error_type : error_type, e.what());
    throw py::error_already_set();
  } catch (const CLI::ParseError& e) {
    PyErr_SetString(error_type, e.what());
    throw py::error_already_set();
  } catch (const cl::Error& e) {
    const std::string message = std::string("OpenCL error: ") + e.what() + " (" + cl_error_name(e.err()) + ")";
    PyErr_SetString(device_error_type, message.c_str());
    throw py::error_already_set();
  } catch (const std::bad_alloc&) {
    PyErr_SetString(PyExc_MemoryError, "out of memory: this machine cannot hold the request");
    throw py::error_already_set();
  } catch (const std::exception& e) {
    PyErr_SetString(error_type, e.what());
    throw py::error_already_set();
  }
}

std::unique_ptr<Cli> parse_command(const std::vector<std::string>& args) {
  std::unique_ptr<Cli> cli = make_cli();
  std::vector<const char*> argv{"caustica"};
  for (const std::string& a : args) argv.push_back(a.c_str());
  translate_errors(ErrorKind::Option, [&] { cli->app.parse(int(argv.size()), argv.data()); });
  return cli;
}

py::array_t<float> to_numpy(const ImageF& image) {
  py::array_t<float> array({py::ssize_t(image.height), py::ssize_t(image.width), py::ssize_t(3)});
  std::copy(image.rgb.begin(), image.rgb.end(), array.mutable_data());
  return array;
}

ImageF image_from_numpy(const py::handle& object, const std::string& what) {
  py::array_t<float, py::array::c_style | py::array::forcecast> array;
  try {
    array = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(object);
  } catch (const py::error_already_set&) {
    array = {};
  }
  if (!array || array.ndim() != 3 || array.shape(2) != 3 || array.shape(0) < 1 || array.shape(1) < 1) {
    const std::string got = array ? "an array of shape " + std::string(py::str(object.attr("shape"))) : "a " + std::string(py::str(object.get_type().attr("__name__")));
    PyErr_SetString(error_type, (what + ": expected an H x W x 3 array of linear RGB, got " + got).c_str());
    throw py::error_already_set();
  }
  ImageF image(int(array.shape(1)), int(array.shape(0)));
  std::copy(array.data(), array.data() + image.rgb.size(), image.rgb.begin());
  return image;
}

}  // namespace caustica::python
