// caustica.devices, caustica.diff and caustica.sky: the CLI's `devices`,
// `diff` and `sky`, returning values instead of printing or writing.
#include <pybind11/stl.h>

#include "host/app/diff.h"
#include "host/cl/runtime.h"
#include "host/error.h"
#include "host/image/image_io.h"
#include "host/image/metrics.h"
#include "host/scene/sky_model.h"
#include "python/module/bindings.h"

namespace caustica::python {
namespace {

py::list devices() {
  py::list out;
  translate_errors(ErrorKind::Option, [&] {
    const std::vector<DeviceInfo> all = list_devices();
    const int chosen = all.empty() ? -1 : select_device("").index;
    for (const DeviceInfo& d : all) {
      py::dict e;
      e["index"] = d.index;
      e["type"] = d.type;
      e["name"] = d.name;
      e["platform"] = d.platform_name;
      e["compute_units"] = d.compute_units;
      e["version"] = d.device_version;
      e["memory_bytes"] = d.global_mem_bytes;
      e["default"] = d.index == chosen;
      out.append(e);
    }
  });
  return out;
}

// A path (read as `caustica diff` reads it) or an H x W x 3 array.
ImageF diff_input(const py::handle& v, const char* what) {
  if (py::isinstance<py::str>(v) || py::hasattr(v, "__fspath__")) {
    const std::string path = py::str(py::module_::import("os").attr("fspath")(v));
    ImageF image;
    translate_errors(ErrorKind::Option, [&] { image = read_image_for_diff(path).image; });
    return image;
  }
  return image_from_numpy(v, what);
}

py::object diff(const py::handle& a, const py::handle& b, const std::string& metric, bool per_pixel) {
  const ImageF image = diff_input(a, "diff: the image"), reference = diff_input(b, "diff: the reference");
  py::object out;
  translate_errors(ErrorKind::Option, [&] {
    ErrorMetric m;
    try {
      m = parse_error_metric(metric);
    } catch (const Error& e) {
      throw Error("diff: metric='" + metric + "': " + e.what());
    }
    if (image.width != reference.width || image.height != reference.height)
      throw Error("diff: the image is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                  " but the reference is " + std::to_string(reference.width) + "x" +
                  std::to_string(reference.height) + " (images are never resampled)");
    if (!per_pixel) {
      out = py::float_(mean_error(image, reference, m));
      return;
    }
    const std::vector<double> values = per_pixel_error(image, reference, m);
    py::array_t<double> map({py::ssize_t(image.height), py::ssize_t(image.width)});
    std::copy(values.begin(), values.end(), map.mutable_data());
    out = map;
  });
  return out;
}

py::array_t<float> sky(const std::vector<std::string>& options, bool write) {
  std::vector<std::string> args{"sky"};
  args.insert(args.end(), options.begin(), options.end());
  std::unique_ptr<Cli> cli = parse_command(args);
  ImageF image;
  translate_errors(ErrorKind::Option, [&] {
    check_command_options(*cli);
    image = preetham_sky(cli->sky.params);
    if (write) write_image(cli->sky.output, image, DisplaySettings{});
  });
  return to_numpy(image);
}

}  // namespace

void bind_tools(py::module_& m) {
  m.def("devices", &devices);
  m.def("diff", &diff, py::arg("image"), py::arg("reference"), py::arg("metric") = "relmse",
        py::arg("per_pixel") = false);
  m.def("sky", &sky, py::arg("options"), py::arg("write"));
}

}  // namespace caustica::python
