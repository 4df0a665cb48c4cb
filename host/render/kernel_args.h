// Device queues of the records in kernels/shared/records.h, and the named
// binding of kernel arguments.
//
// Rules: a queue's buffers come from the same field list as the kernels'
// parameter lists (PATH_RECORD_FIELDS, PHOTON_RECORD_FIELDS, ...), so allocation cannot miss a
// field. Arguments are bound in declaration order under the kernel's own
// parameter names ("in_count", "in_origin", ...); KernelArgs::finish checks
// the count always and every name wherever the device reports argument
// names (programs are built with -cl-kernel-arg-info), so a host that binds
// in a different order than the kernel declares fails with a message naming
// the kernel, the position and both names instead of rendering garbage.
#pragma once

#include <CL/opencl.hpp>

#include <string>
#include <type_traits>
#include <vector>

#include "kernels/shared/records.h"

namespace caustica {

struct RecordField {
  const char* name;
  size_t bytes;  // one element
};

struct RecordLayout {
  const char* name;  // for messages
  std::vector<RecordField> fields;
};

const RecordLayout& path_record_layout();
const RecordLayout& photon_record_layout();
const RecordLayout& shadow_record_layout();

// A structure-of-arrays queue: one buffer per field, one atomic counter.
class DeviceQueue {
 public:
  DeviceQueue() = default;
  DeviceQueue(cl::Context& context, const RecordLayout& layout, size_t capacity);

  bool allocated() const { return layout_ != nullptr; }
  size_t capacity() const { return capacity_; }
  const RecordLayout& layout() const { return *layout_; }
  const cl::Buffer& count() const { return count_; }
  // Throws caustica::Error for a name the record does not have.
  const cl::Buffer& field(const std::string& name) const;
  const std::vector<cl::Buffer>& fields() const { return fields_; }

 private:
  const RecordLayout* layout_ = nullptr;
  size_t capacity_ = 0;
  cl::Buffer count_;
  std::vector<cl::Buffer> fields_;
};

// A stage's kernel, with whether its binding has been checked yet (once is
// enough: a stage is always bound by the same code).
struct StageKernel {
  StageKernel() = default;
  StageKernel(const cl::Program& program, const std::string& kernel_name)
      : kernel(program, kernel_name.c_str()), name(kernel_name) {}
  cl::Kernel kernel;
  std::string name;
  bool binding_checked = false;
};

class KernelArgs {
 public:
  explicit KernelArgs(StageKernel& stage) : stage_(stage) {}

  template <typename T>
  KernelArgs& arg(const std::string& name, const T& value) {
    const ArgKind kind = std::is_base_of_v<cl::Memory, T> ? ArgKind::Buffer : ArgKind::Value;
    try {
      stage_.kernel.setArg(cl_uint(names_.size()), value);
    } catch (const cl::Error& e) {
      refuse(name, kind, e);
    }
    names_.push_back(name);
    kinds_.push_back(kind);
    return *this;
  }
  // The whole queue: prefix_count, then prefix_<field> for every field.
  KernelArgs& queue(const std::string& prefix, const DeviceQueue& q);
  // The same with another counter than the queue's own (the path tracer's
  // rotating counts).
  KernelArgs& queue(const std::string& prefix, const DeviceQueue& q, const cl::Buffer& count);
  // The ray view of a queue (RAY_VIEW_PARAMS): prefix_count, _origin, _dir.
  KernelArgs& ray_view(const std::string& prefix, const DeviceQueue& q);
  KernelArgs& ray_view(const std::string& prefix, const DeviceQueue& q, const cl::Buffer& count);
  // On the stage's first binding: throws caustica::Error when the count,
  // or (where the device reports them) a name or a kind differs from the
  // kernel's declaration: a buffer bound where the kernel takes a value, or
  // a value where it takes a __global or __constant pointer.
  void finish();

 private:
  enum class ArgKind { Buffer, Value };
  // What the kernel declares at position i ("a buffer", "a value", "a
  // __local allocation"), "" where the device does not say.
  std::string declared_kind(cl_uint i) const;
  // The device refused an argument (its size or kind): an error naming it.
  [[noreturn]] void refuse(const std::string& name, ArgKind kind, const cl::Error& e) const;
  StageKernel& stage_;
  std::vector<std::string> names_;
  std::vector<ArgKind> kinds_;
};

// The kernel's parameter names, or an empty list where the device does not
// report them (a program without -cl-kernel-arg-info).
std::vector<std::string> kernel_arg_names(const cl::Kernel& kernel);

}  // namespace caustica
