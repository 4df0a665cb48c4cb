#include "host/render/kernel_args.h"

#include "host/cl/runtime.h"
#include "host/error.h"

namespace caustica {

#define CAUSTICA_RECORD_FIELD(q, type, name) RecordField{#name, sizeof(type)},

const RecordLayout& path_record_layout() {
  static const RecordLayout layout{"path", {PATH_RECORD_FIELDS(CAUSTICA_RECORD_FIELD, _)}};
  return layout;
}

const RecordLayout& photon_record_layout() {
  static const RecordLayout layout{"photon", {PHOTON_RECORD_FIELDS(CAUSTICA_RECORD_FIELD, _)}};
  return layout;
}

const RecordLayout& shadow_record_layout() {
  static const RecordLayout layout{"shadow", {SHADOW_RECORD_FIELDS(CAUSTICA_RECORD_FIELD, _)}};
  return layout;
}

#undef CAUSTICA_RECORD_FIELD

DeviceQueue::DeviceQueue(cl::Context& context, const RecordLayout& layout, size_t capacity)
    : layout_(&layout), capacity_(capacity) {
  const size_t slots = std::max<size_t>(1, capacity);
  count_ = cl::Buffer(context, CL_MEM_READ_WRITE, sizeof(cl_uint));
  for (const RecordField& f : layout.fields) fields_.emplace_back(context, CL_MEM_READ_WRITE, slots * f.bytes);
}

const cl::Buffer& DeviceQueue::field(const std::string& name) const {
  if (!layout_) throw Error("queue used before it was allocated");
  for (size_t i = 0; i < layout_->fields.size(); ++i)
    if (name == layout_->fields[i].name) return fields_[i];
  throw Error(std::string(layout_->name) + " record has no field \"" + name + "\"");
}

KernelArgs& KernelArgs::queue(const std::string& prefix, const DeviceQueue& q) { return queue(prefix, q, q.count()); }

KernelArgs& KernelArgs::queue(const std::string& prefix, const DeviceQueue& q, const cl::Buffer& count) {
  arg(prefix + "_count", count);
  for (size_t i = 0; i < q.fields().size(); ++i) arg(prefix + "_" + q.layout().fields[i].name, q.fields()[i]);
  return *this;
}

KernelArgs& KernelArgs::ray_view(const std::string& prefix, const DeviceQueue& q) {
  return ray_view(prefix, q, q.count());
}

KernelArgs& KernelArgs::ray_view(const std::string& prefix, const DeviceQueue& q, const cl::Buffer& count) {
  return arg(prefix + "_count", count).arg(prefix + "_origin", q.field("origin")).arg(prefix + "_dir", q.field("dir"));
}

std::vector<std::string> kernel_arg_names(const cl::Kernel& kernel) {
  const cl_uint count = kernel.getInfo<CL_KERNEL_NUM_ARGS>();
  std::vector<std::string> names;
  for (cl_uint i = 0; i < count; ++i) {
    size_t size = 0;
    if (clGetKernelArgInfo(kernel(), i, CL_KERNEL_ARG_NAME, 0, nullptr, &size) != CL_SUCCESS || size == 0) return {};
    std::string name(size, '\0');
    if (clGetKernelArgInfo(kernel(), i, CL_KERNEL_ARG_NAME, size, name.data(), nullptr) != CL_SUCCESS) return {};
    name.resize(name.find('\0') == std::string::npos ? name.size() : name.find('\0'));
    names.push_back(name);
  }
  return names;
}

std::string KernelArgs::declared_kind(cl_uint i) const {
  cl_kernel_arg_address_qualifier qualifier = 0;
  if (clGetKernelArgInfo(stage_.kernel(), i, CL_KERNEL_ARG_ADDRESS_QUALIFIER, sizeof qualifier, &qualifier, nullptr) !=
      CL_SUCCESS)
    return {};
  if (qualifier == CL_KERNEL_ARG_ADDRESS_GLOBAL || qualifier == CL_KERNEL_ARG_ADDRESS_CONSTANT) return "a buffer";
  if (qualifier == CL_KERNEL_ARG_ADDRESS_LOCAL) return "a __local allocation";
  return "a value";
}

void KernelArgs::refuse(const std::string& name, ArgKind kind, const cl::Error& e) const {
  const cl_uint i = cl_uint(names_.size());
  const cl_uint declared = stage_.kernel.getInfo<CL_KERNEL_NUM_ARGS>();
  if (i >= declared)
    throw Error("kernel " + stage_.name + " declares " + std::to_string(declared) + " arguments, the host binds \"" +
                name + "\" as argument " + std::to_string(i));
  const std::string declared_as = declared_kind(i);
  throw Error("kernel " + stage_.name + " argument " + std::to_string(i) + " (\"" + name + "\")" +
              (declared_as.empty() ? "" : " is " + declared_as) + ", the host binds " +
              (kind == ArgKind::Buffer ? "a buffer" : "a value") + " there: " + e.what() + " failed with " +
              cl_error_name(e.err()));
}

void KernelArgs::finish() {
  if (stage_.binding_checked) return;
  const cl_uint declared = stage_.kernel.getInfo<CL_KERNEL_NUM_ARGS>();
  if (declared != names_.size())
    throw Error("kernel " + stage_.name + " declares " + std::to_string(declared) + " arguments, the host binds " +
                std::to_string(names_.size()));
  const std::vector<std::string> names = kernel_arg_names(stage_.kernel);
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] != names_[i])
      throw Error("kernel " + stage_.name + " argument " + std::to_string(i) + " is \"" + names[i] +
                  "\", the host binds \"" + names_[i] + "\" there");
  for (cl_uint i = 0; i < declared; ++i) {
    const std::string kind = declared_kind(i);
    if (kind.empty()) break;  // no argument info from this device: the count is all we can check
    const std::string bound = kinds_[i] == ArgKind::Buffer ? "a buffer" : "a value";
    if (kind != bound)
      throw Error("kernel " + stage_.name + " argument " + std::to_string(i) + " (\"" + names_[i] + "\") is " + kind +
                  ", the host binds " + bound + " there");
  }
  stage_.binding_checked = true;
}

}  // namespace caustica
