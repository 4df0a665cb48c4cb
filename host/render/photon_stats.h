// What the photon pass's gathers did (issue 19): counted on the device per
// pass (kernels/shared/photon.h's gather counters), summed on the host, and
// shown by `caustica bench` and `render --verbose`.
#pragma once

#include <array>
#include <cstdint>

#include "kernels/shared/photon.h"

namespace caustica {

// The gathers' work (over the render, or one pass): gathers and photons
// read (visits) at visible points (D1) and at later receivers, and the
// histograms of visits per gather (bins of PHOTON_VISIT_BIN_WIDTH).
struct PhotonGatherStats {
  uint64_t gathers_d1 = 0, visits_d1 = 0, gathers_later = 0, visits_later = 0;
  std::array<uint64_t, PHOTON_VISIT_BINS> histogram_d1{}, histogram_later{};
  void add(const PhotonGatherStats& o);
  // The visits per gather below which `q` (0..1) of the gathers lie: the
  // upper edge of the histogram bin that holds that quantile.
  static double quantile(const std::array<uint64_t, PHOTON_VISIT_BINS>& h, double q);
};

}  // namespace caustica
