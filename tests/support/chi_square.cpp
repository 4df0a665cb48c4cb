#include "tests/support/chi_square.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace caustica::test {
namespace {

constexpr double kPi = 3.14159265358979323846;
cl_float4 f4(double x, double y, double z, double w = 0.0) {
  return {{float(x), float(y), float(z), float(w)}};
}
glm::dvec3 d3(const cl_float4& v) { return glm::dvec3(v.s[0], v.s[1], v.s[2]); }
using glm::dvec3;

}  // namespace


// Regularised upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a):
// the series for P when x < a + 1, Lentz's continued fraction for Q otherwise
// (Numerical Recipes 6.2).
double gamma_q(double a, double x) {
  if (x <= 0.0) return 1.0;
  if (!std::isfinite(x)) return 0.0;
  const double log_prefactor = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 100000; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-15) break;
    }
    return std::max(0.0, 1.0 - sum * std::exp(log_prefactor));
  }
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 100000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-15) break;
  }
  return std::exp(log_prefactor) * h;
}

double chi_square_p_value(double chi2, int dof) { return dof <= 0 ? 1.0 : gamma_q(0.5 * dof, 0.5 * chi2); }

// The threshold each of k tests in one TEST must pass for the whole to have
// significance kChiSquareAlpha (Sidak).
double sidak(int k) { return 1.0 - std::pow(1.0 - kChiSquareAlpha, 1.0 / k); }

std::string ChiSquare::describe() const {
  std::ostringstream s;
  s << "chi2 " << chi2 << " dof " << dof << " p " << p << " integral " << integral << " outside " << outside;
  return s.str();
}

// Pools cells expecting fewer than 5 (sorted ascending, a pool still below 5
// takes the next cells until it reaches 5, as Mitsuba 3's chi2 test does) and
// returns chi2 and dof; chi2 is infinite when samples fall where nothing is
// expected.
void chi_square_statistic(const std::vector<double>& observed, const std::vector<double>& expected, ChiSquare* r) {
  std::vector<size_t> order(observed.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
  const double min_expected = 5.0;
  double pooled_obs = 0.0, pooled_exp = 0.0, chi2 = 0.0;
  int cells = 0;
  for (size_t i : order) {
    const double o = observed[i], e = expected[i];
    if (e < min_expected || (pooled_exp > 0.0 && pooled_exp < min_expected)) {
      pooled_obs += o;
      pooled_exp += e;
    } else {
      chi2 += (o - e) * (o - e) / e;
      ++cells;
    }
  }
  if (pooled_obs > 0.0 || pooled_exp > 0.0) {
    chi2 += pooled_exp > 0.0 ? (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp
                             : std::numeric_limits<double>::infinity();
    ++cells;
  }
  r->chi2 = chi2;
  r->dof = cells - 1;
  r->p = chi_square_p_value(chi2, r->dof);
}



static const double kGaussNodes[5] = {0.04691007703066802, 0.23076534494715845, 0.5, 0.7692346550528415,
                               0.9530899229693319};
static const double kGaussWeights[5] = {0.11846344252809454, 0.23931433524968324, 0.28444444444444444,
                                 0.23931433524968324, 0.11846344252809454};

namespace {

// A rectangle of the unit square, the cell it belongs to, and its integral.
struct Region {
  double x, y, w, h;
  size_t cell;
  double estimate;
  bool smooth;  // the density is positive at every node and varies < 1.5x
};

// Gauss-Legendre 5 x 5 over every region, the density of all nodes in one
// batch (one kernel launch when the density is the device's).
void integrate_regions(std::vector<Region>& regions, const Domain& dom, const Density& density) {
  std::vector<cl_float4> points;
  std::vector<double> weights;
  points.reserve(regions.size() * 25);
  weights.reserve(regions.size() * 25);
  for (const Region& g : regions)
    for (int a = 0; a < 5; ++a)
      for (int b = 0; b < 5; ++b) {
        double jacobian;
        points.push_back(dom.from_unit(g.x + kGaussNodes[a] * g.w, g.y + kGaussNodes[b] * g.h, &jacobian));
        weights.push_back(kGaussWeights[a] * kGaussWeights[b] * jacobian * g.w * g.h);
      }
  const std::vector<double> pdf = density(points);
  for (size_t k = 0; k < regions.size(); ++k) {
    double sum = 0.0, lo = pdf[k * 25], hi = pdf[k * 25];
    for (size_t n = 0; n < 25; ++n) {
      sum += pdf[k * 25 + n] * weights[k * 25 + n];
      lo = std::min(lo, pdf[k * 25 + n]);
      hi = std::max(hi, pdf[k * 25 + n]);
    }
    regions[k].estimate = sum;
    regions[k].smooth = hi == 0.0 || (lo > 0.0 && hi <= 1.5 * lo);
  }
}

}  // namespace

ChiSquare chi_square_test(const std::vector<cl_float4>& samples, const Domain& dom, const Density& density) {
  ChiSquare r;
  const size_t cells = static_cast<size_t>(dom.n1) * dom.n2;
  std::vector<double> observed(cells, 0.0), expected(cells, 0.0);
  for (const cl_float4& s : samples) {
    if (dom.directions) r.max_norm_error = std::max(r.max_norm_error, std::abs(glm::length(d3(s)) - 1.0));
    double x1, x2;
    if (!dom.to_unit(s, &x1, &x2) || !(x1 >= 0.0 && x1 <= 1.0 && x2 >= 0.0 && x2 <= 1.0)) {
      ++r.outside;
      continue;
    }
    const int i = std::min(static_cast<int>(x1 * dom.n1), dom.n1 - 1);
    const int j = std::min(static_cast<int>(x2 * dom.n2), dom.n2 - 1);
    observed[static_cast<size_t>(i) * dom.n2 + j] += 1.0;
  }
  // Each cell's integral by 5 x 5-point Gauss-Legendre. Where the density
  // is not smooth over a cell (a node where it vanishes next to one where it
  // does not: the horizon step of rough refraction; or a > 1.5x spread: a
  // lobe narrower than the cell), fixed nodes misjudge it, so such regions
  // are split in four and re-integrated until the split changes the
  // estimate by less than 1e-3 of itself and of one expected sample.
  std::vector<Region> regions;
  regions.reserve(cells);
  for (int i = 0; i < dom.n1; ++i)
    for (int j = 0; j < dom.n2; ++j)
      regions.push_back({double(i) / dom.n1, double(j) / dom.n2, 1.0 / dom.n1, 1.0 / dom.n2,
                         static_cast<size_t>(i) * dom.n2 + j, 0.0, false});
  integrate_regions(regions, dom, density);
  const double one_sample = 1.0 / std::max<size_t>(samples.size(), 1);
  std::vector<Region> pending;
  for (const Region& g : regions) {
    if (g.smooth) expected[g.cell] += g.estimate;
    else pending.push_back(g);
  }
  constexpr int kMaxSplits = 6;
  for (int depth = 1; !pending.empty(); ++depth) {
    std::vector<Region> children;
    children.reserve(pending.size() * 4);
    for (const Region& g : pending)
      for (int q = 0; q < 4; ++q)
        children.push_back({g.x + 0.5 * g.w * (q & 1), g.y + 0.5 * g.h * (q >> 1), 0.5 * g.w, 0.5 * g.h, g.cell,
                            0.0, false});
    integrate_regions(children, dom, density);
    std::vector<Region> next;
    for (size_t k = 0; k < pending.size(); ++k) {
      const double fine = children[4 * k].estimate + children[4 * k + 1].estimate + children[4 * k + 2].estimate +
                          children[4 * k + 3].estimate;
      const double tolerance = 1e-3 * std::max(fine, one_sample);
      if (depth == kMaxSplits || std::abs(fine - pending[k].estimate) <= tolerance) {
        expected[pending[k].cell] += fine;
        continue;
      }
      for (int q = 0; q < 4; ++q) {
        const Region& c = children[4 * k + q];
        if (c.smooth) expected[c.cell] += c.estimate;
        else next.push_back(c);
      }
    }
    pending.swap(next);
  }
  for (size_t c = 0; c < cells; ++c) {
    r.integral += expected[c];
    expected[c] *= samples.size();
  }
  chi_square_statistic(observed, expected, &r);
  return r;
}

double wrap_unit_angle(double x, double y) {
  double a = std::atan2(y, x) / (2.0 * kPi);
  if (a < 0.0) a += 1.0;
  return a >= 1.0 ? 0.0 : a;
}

// (cos theta, phi) of the sphere.
Domain sphere_domain() {
  Domain d{32, 64, {}, {}};
  d.to_unit = [](const cl_float4& s, double* x1, double* x2) {
    const dvec3 v = glm::normalize(d3(s));
    *x1 = std::clamp(0.5 * (v.z + 1.0), 0.0, 1.0);
    *x2 = wrap_unit_angle(v.x, v.y);
    return true;
  };
  d.from_unit = [](double x1, double x2, double* jacobian) {
    const double z = 2.0 * x1 - 1.0, r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = 2.0 * kPi * x2;
    *jacobian = 4.0 * kPi;
    return f4(r * std::cos(phi), r * std::sin(phi), z);
  };
  return d;
}


}  // namespace caustica::test
