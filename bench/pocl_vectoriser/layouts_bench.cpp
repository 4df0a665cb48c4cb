// Runs one kernel of layouts.cl over 2^20 paths on the first OpenCL CPU
// device and prints its median time, ns per path and a checksum of its
// outputs (bench/pocl_vectoriser/run.sh compares the layouts).
// Usage: layouts_bench LAYOUTS.cl|LAYOUTS.bc KERNEL
// A .bc file is a SPIR binary (clang -target spir64, see run.sh), loaded
// with clCreateProgramWithBinary. LLVM_OPTION (environment): one LLVM
// command-line option set in this process before the build, through the
// libLLVM PoCL runs in (run.sh turns the SLP vectoriser off with it).
#define CL_HPP_TARGET_OPENCL_VERSION 120
#define CL_HPP_MINIMUM_OPENCL_VERSION 120
#define CL_HPP_ENABLE_EXCEPTIONS
#include <CL/opencl.hpp>
#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s LAYOUTS.cl KERNEL\n", argv[0]);
    return 2;
  }
  std::ifstream file(argv[1]);
  std::stringstream source;
  source << file.rdbuf();
  const std::string kernel_name = argv[2];
  const bool soa = kernel_name.size() > 4 && kernel_name.compare(kernel_name.size() - 4, 4, "_soa") == 0;
  const cl_uint n = 1u << 20, primitives = 1024;

  // Inputs: directions, primitive indices, normals and albedos from a fixed LCG.
  uint32_t state = 12345u;
  auto uniform = [&] { return float((state = state * 1664525u + 1013904223u) >> 8) * 0x1.0p-24f; };
  std::vector<float> dir(4 * n), beta(4 * n), normals(4 * primitives), albedo(4 * primitives);
  std::vector<cl_uint> prim(n);
  for (cl_uint i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) dir[4 * i + k] = 2.0f * uniform() - 1.0f, beta[4 * i + k] = uniform();
    prim[i] = cl_uint(uniform() * primitives) % primitives;
  }
  for (cl_uint p = 0; p < primitives; ++p)
    for (int k = 0; k < 3; ++k) normals[4 * p + k] = 2.0f * uniform() - 1.0f, albedo[4 * p + k] = uniform();
  auto to_layout = [&](const std::vector<float>& v) {  // float4 records, or one array per component
    if (!soa) return v;
    std::vector<float> out(v.size());
    for (cl_uint i = 0; i < n; ++i)
      for (int k = 0; k < 4; ++k) out[k * n + i] = v[4 * i + k];
    return out;
  };

  cl::Context context(CL_DEVICE_TYPE_CPU);
  if (const char* option = std::getenv("LLVM_OPTION")) {  // PoCL has loaded its libLLVM by now
    void* llvm = dlopen("libLLVM-15.so.1", RTLD_NOW | RTLD_NOLOAD);
    auto parse = llvm ? reinterpret_cast<void (*)(int, const char* const*, const char*)>(
                            dlsym(llvm, "LLVMParseCommandLineOptions"))
                      : nullptr;
    if (!parse) {
      std::fprintf(stderr, "LLVM_OPTION: PoCL's libLLVM-15 is not loaded in this process\n");
      return 1;
    }
    const char* args[] = {"layouts_bench", option};
    parse(2, args, "");
  }
  const std::string path = argv[1], text = source.str();
  const bool spir = path.size() > 3 && path.compare(path.size() - 3, 3, ".bc") == 0;
  cl::Program program = spir ? cl::Program(context, context.getInfo<CL_CONTEXT_DEVICES>(),
                                           cl::Program::Binaries{std::vector<unsigned char>(text.begin(), text.end())})
                             : cl::Program(context, text);
  try {
    program.build();
  } catch (const cl::Error&) {
    std::fprintf(stderr, "%s\n", program.getBuildInfo<CL_PROGRAM_BUILD_LOG>()[0].second.c_str());
    return 1;
  }
  cl::CommandQueue queue(context);
  const std::vector<float> dir_in = to_layout(dir), beta_in = to_layout(beta);
  cl::Buffer d_dir(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, dir_in.size() * 4, (void*)dir_in.data());
  cl::Buffer d_prim(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, prim.size() * 4, prim.data());
  cl::Buffer d_normals(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, normals.size() * 4, normals.data());
  cl::Buffer d_albedo(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, albedo.size() * 4, albedo.data());
  cl::Buffer d_out(context, CL_MEM_READ_WRITE, 16ul * n), d_beta(context, CL_MEM_READ_WRITE, 16ul * n);
  cl::Kernel kernel(program, kernel_name.c_str());
  int a = 0;
  for (cl::Buffer* b : {&d_dir, &d_prim, &d_normals, &d_albedo, &d_out, &d_beta}) kernel.setArg(a++, *b);
  kernel.setArg(a, n);

  std::vector<double> ms;
  std::vector<float> out(4 * n), beta_out(4 * n);
  for (int run = 0; run < 8; ++run) {  // the throughput is rescaled in place: reload it each run
    queue.enqueueWriteBuffer(d_beta, CL_TRUE, 0, 16ul * n, beta_in.data());
    const auto t0 = std::chrono::steady_clock::now();
    queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(n), cl::NDRange(64));
    queue.finish();
    const auto t1 = std::chrono::steady_clock::now();
    if (run > 0) ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  queue.enqueueReadBuffer(d_out, CL_TRUE, 0, 16ul * n, out.data());
  queue.enqueueReadBuffer(d_beta, CL_TRUE, 0, 16ul * n, beta_out.data());
  double checksum = 0.0;  // in record order, whatever the layout
  for (cl_uint i = 0; i < n; ++i)
    for (int k = 0; k < 4; ++k)
      checksum += (soa ? out[k * n + i] : out[4 * i + k]) * double(k + 1) + (soa ? beta_out[k * n + i] : beta_out[4 * i + k]);
  std::sort(ms.begin(), ms.end());
  std::printf("%-16s median %7.2f ms  %6.2f ns/path  checksum %.6e\n", kernel_name.c_str(), ms[ms.size() / 2],
              ms[ms.size() / 2] * 1e6 / n, checksum);
}
