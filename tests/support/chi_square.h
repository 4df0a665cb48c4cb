// A chi-square goodness-of-fit test of sampling routines against their
// densities, in the style of pbrt-v4 and Mitsuba 3 (tests/test_sampling.cpp
// documents the method): histogram the samples over a parametrisation of the
// sample space mapped onto the unit square, integrate the claimed density
// over each cell by 5 x 5-point Gauss-Legendre, split adaptively where the
// density is not smooth over the cell (steps, narrow lobes), pool cells expecting fewer
// than 5, and take the p-value from the regularised upper incomplete gamma
// function. Samples that a routine failed to produce are passed as points
// outside the domain (e.g. the zero vector): they count in the total and
// the density then integrates to the produced share.
#pragma once

#include <CL/opencl.hpp>

#include <functional>
#include <string>
#include <vector>

namespace caustica::test {

constexpr double kChiSquareAlpha = 0.01;  // significance of one chi-square test

double gamma_q(double a, double x);  // regularised upper incomplete gamma Q(a, x)
double chi_square_p_value(double chi2, int dof);
// The threshold each of k tests in one TEST must pass for the whole to have
// significance kChiSquareAlpha (Sidak).
double sidak(int k);

struct ChiSquare {
  double chi2 = 0.0, p = 0.0, integral = 0.0;
  int dof = 0;
  size_t outside = 0;           // samples outside the parametrised domain
  double max_norm_error = 0.0;  // max | |d| - 1 | of direction samples
  std::string describe() const;
};

void chi_square_statistic(const std::vector<double>& observed, const std::vector<double>& expected, ChiSquare* r);

// A parametrisation of the sample space over the unit square.
struct Domain {
  int n1, n2;  // cells along each unit coordinate
  // A sample's unit coordinates; false when it lies outside the domain.
  std::function<bool(const cl_float4&, double*, double*)> to_unit;
  // The point at unit coordinates (x1, x2), and the measure (solid angle or
  // area) per unit of x1 x2 there.
  std::function<cl_float4(double, double, double*)> from_unit;
  bool directions = true;  // samples are unit vectors
};

// The density at a batch of points (the device's pdf, or a host formula).
using Density = std::function<std::vector<double>(const std::vector<cl_float4>&)>;

ChiSquare chi_square_test(const std::vector<cl_float4>& samples, const Domain& dom, const Density& density);

double wrap_unit_angle(double x, double y);
// (cos theta, phi) of the whole sphere, 32 x 64 cells.
Domain sphere_domain();

}  // namespace caustica::test
