// kernels/shared/compat.h against a real OpenCL: the same function
// (kernels/checks/compat_check.h) compiled by the device's compiler and, as
// C++, for the host, on the same inputs. The exact outputs (masks, select,
// clamp, fma, fmin/fmax, bit casts, conversions, shuffle, byte narrowing,
// IEEE arithmetic) must be equal; the rest (mix, dot, cross, length,
// normalize), whose operation order is the implementation's, within 8 ulps.
// Kernel-level: it runs on whatever device the tests use (PoCL, Oclgrind
// and an NVIDIA H100 pass it).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "checks/compat_check.h"
#include "host/render/kernel_args.h"
#include "tests/support/test_support.h"

namespace caustica {
namespace {

TEST(Compat, HostMappingAgreesWithTheDevice) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> any(-2.0f, 2.0f);
  const float specials[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, 1e-30f, -3e-20f, 1.5f};
  std::vector<float4> a, b;
  for (float s : specials)
    for (float t : specials) {
      a.push_back(make_float4(s, t, -s, t * 0.5f));
      b.push_back(make_float4(t, s, s, -t));
    }
  while (a.size() < 4096) {
    a.push_back(make_float4(any(rng), any(rng), any(rng), any(rng)));
    b.push_back(make_float4(any(rng), any(rng), any(rng), any(rng)));
  }
  const size_t n = a.size();
  Runtime& rt = test::runtime();
  const BuiltProgram built = rt.build_file("checks/compat_check.cl", "");
  cl::Kernel k(built.program, "compat_check");
  cl::Buffer ab(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(float4), a.data());
  cl::Buffer bb(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(float4), b.data());
  cl::Buffer out(rt.context(), CL_MEM_WRITE_ONLY, n * COMPAT_CHECK_OUTPUTS * sizeof(float));
  k.setArg(0, ab);
  k.setArg(1, bb);
  k.setArg(2, cl_uint(n));
  k.setArg(3, out);
  rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(round_up(n, 64)), cl::NDRange(64));
  std::vector<float> device(n * COMPAT_CHECK_OUTPUTS);
  rt.queue().enqueueReadBuffer(out, CL_TRUE, 0, device.size() * sizeof(float), device.data());

  int exact_differ = 0, approximate_differ = 0;
  for (size_t i = 0; i < n; ++i) {
    float host[COMPAT_CHECK_OUTPUTS];
    compat_check_values(a[i], b[i], host);
    for (int o = 0; o < COMPAT_CHECK_OUTPUTS; ++o) {
      const float d = device[COMPAT_CHECK_OUTPUTS * i + o], h = host[o];
      if (o < COMPAT_CHECK_APPROXIMATE_FIRST) {
        // Equal values (fmin and fmax of -0 and +0 may return either zero:
        // PoCL gives the host's, Oclgrind the other).
        if (!(d == h) && ++exact_differ <= 5)
          ADD_FAILURE() << "output " << o << " of input " << i << ": device " << d << ", host " << h;
      } else if (!(std::fabs(d - h) <= 1e-6f * std::max(1.0f, std::fabs(h))) && ++approximate_differ <= 5) {
        // Within 8 ulps: NVIDIA's normalize (not correctly rounded, nor
        // required to be) puts |u|^2 2 ulps either side of 1 where the host
        // and PoCL give 1 - 1 ulp.
        ADD_FAILURE() << "output " << o << " of input " << i << ": device " << d << ", host " << h;
      }
    }
  }
  EXPECT_EQ(exact_differ, 0);
  EXPECT_EQ(approximate_differ, 0);
}

}  // namespace
}  // namespace caustica
