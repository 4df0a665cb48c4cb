// The processes of a distributed render (MPI ranks: host/mpi/mpi_ranks.h,
// built only where CMake finds MPI), as the render needs them: the core
// library stays free of MPI, and the single-process binary never starts it.
//
// Rules. Every call but rank(), size() and abort() is collective: every
// rank makes it, in the same order, or the group waits forever; rank 0 is
// the root that decides (stops, target errors) and receives the sums. The
// sums are integers (the film's 128-bit fixed point), so the result does
// not depend on how the ranks' values were combined.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "host/render/pixel_share.h"

namespace caustica {

// The pixel-sharing collectives (PixelShare: the photon pass under ranks)
// are the render core's view of the same group.
class RankGroup : public PixelShare {
 public:
  ~RankGroup() override = default;
  virtual int local_rank() const = 0;  // among the ranks on this machine (picks a device)
  // Returns once every rank has called it.
  virtual void barrier() = 0;
  // On rank 0 the sum over ranks; elsewhere unchanged. `sums128` holds
  // 128-bit integers as two words each, low first.
  virtual void sum128_to_root(std::vector<uint64_t>& sums128) = 0;
  virtual void sum_to_root(std::vector<uint64_t>& values) = 0;
  virtual void sum_to_root(std::vector<uint32_t>& values) = 0;
  // On rank 0 every rank's `values`, by rank; elsewhere empty.
  virtual std::vector<std::vector<int32_t>> gather_to_root(const std::vector<int32_t>& values) = 0;
  // Ends every rank now (after this rank printed why), with `code`.
  [[noreturn]] virtual void abort(int code) = 0;
};

}  // namespace caustica
