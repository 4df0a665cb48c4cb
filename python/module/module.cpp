// caustica._caustica: the Python module's native part (issue 41,
// docs/python.md). The package python/caustica/ wraps it.
//
// Rules: nothing here renders, loads or measures: every call goes to the
// core library the CLI links (host/), with the CLI's own option parser
// (render and sky take their arguments as the command line's, so the
// defaults, checks and messages are the CLI's). This layer converts:
// Python values to JSON and option lists, images to NumPy arrays, and C++
// errors to Python exceptions (errors.cpp). The GIL is released while a
// render runs and taken back only for the callback between waves.
#include <pybind11/pybind11.h>

#include "python/module/bindings.h"

namespace py = pybind11;

PYBIND11_MODULE(_caustica, m) {
  m.doc() = "caustica's native module: use the caustica package (import caustica), which documents every call.";
  caustica::python::bind_errors(m);
  caustica::python::bind_scene(m);
  caustica::python::bind_render(m);
  caustica::python::bind_tools(m);
}
