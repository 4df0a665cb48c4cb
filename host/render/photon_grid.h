// The photon hash grid on the device (issue 13, SPPM): the photons of a pass
// sorted into hash buckets of cubic cells, for the gather to query
// (kernels/lib/photon_grid.h).
//
// Rules: the grid is built on the device by the stages of photon_grid.cl,
// launched through the render's StageLauncher; the host reads at most one
// value per build (the photon counter) and never a photon. Buffers are
// allocated on the first build and grow only when a pass has more photons
// (or buckets) than any before, so a scene without caustics, which never
// creates a PhotonGrid, allocates nothing. The build is deterministic: a
// bucket's photons are ordered by their index in the unsorted array, so the
// grid, and whatever a gather sums in query order, are the same bits for
// any thread count or work-group size.
#pragma once

#include <CL/opencl.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "kernels/shared/photon.h"

namespace caustica {

class KernelArgs;
class Runtime;
class StageLauncher;
struct RenderStats;
struct StageKernel;

// In-place exclusive prefix sum of a device buffer of uints (the grid's
// bucket starts; kernels/photon/scan_bucket_counts.cl): any length, any
// work-group size, the same answer on every device.
class ExclusiveScan {
 public:
  explicit ExclusiveScan(const cl::Program& program);  // a program holding scan_bucket_counts.cl
  ~ExclusiveScan();
  // values[i] <- values[0] + ... + values[i - 1] for i < count.
  void run(StageLauncher& launcher, const cl::Buffer& values, size_t count, RenderStats* stats = nullptr);

 private:
  void scan_level(StageLauncher& launcher, const cl::Buffer& values, size_t count, size_t level,
                  RenderStats* stats);

  std::unique_ptr<StageKernel> sum_blocks_, scan_blocks_;
  std::vector<cl::Buffer> block_sums_;  // one per level below the values, grown as needed
  std::vector<size_t> block_sums_capacity_;
};

// Where the grid lies and how fine it is.
struct PhotonGridShape {
  std::array<float, 3> origin{};  // the camera position (any point works; cells near it stay small)
  float cell_size = 1.0f;         // SPPM: about the initial gather radius
  // Buckets, a power of two; 0: photon_grid_table_size(photon count). Tests
  // force tiny tables to exercise hash collisions.
  uint32_t table_size = 0;
};

// Buckets for a pass of `photon_count` photons: the least power of two
// >= 2 x photon_count (so a bucket holds about half a cell's photons when
// cells hold one each), at least 64 and at most 2^22 (16 MiB of starts;
// beyond 2M photons buckets just hold more).
uint32_t photon_grid_table_size(size_t photon_count);

class PhotonGrid {
 public:
  // `program`: photon_grid.cl (or a program including its grid stages).
  // Allocates nothing yet.
  PhotonGrid(Runtime& runtime, const cl::Program& program);
  ~PhotonGrid();

  // Builds the grid over photons[0, photon_count).
  void build(StageLauncher& launcher, const cl::Buffer& photons, size_t photon_count, const PhotonGridShape& shape,
             RenderStats* stats = nullptr);
  // The same over the photons a device counter says were stored: reads the
  // counter once (one blocking transfer) and uses at most `capacity`
  // photons. Returns the counter's value, which exceeds `capacity` when the
  // photon buffer overflowed (the caller reports that).
  uint32_t build(StageLauncher& launcher, const cl::Buffer& photons, const cl::Buffer& photon_counter,
                 size_t capacity, const PhotonGridShape& shape, RenderStats* stats = nullptr);

  // PHOTON_GRID_PARAMS of kernels/lib/photon_grid.h: "grid",
  // "grid_bucket_start", "grid_photons".
  KernelArgs& bind(KernelArgs& args) const;

  const PhotonGridParams& params() const { return params_; }
  // table_size + 1 uints: bucket b's photons are slots [start[b], start[b + 1]).
  const cl::Buffer& bucket_start() const { return bucket_start_; }
  const cl::Buffer& photons() const { return photons_; }  // photon_count Photons in bucket order
  // photon_count uints: the unsorted index of each slot's photon.
  const cl::Buffer& photon_index() const { return photon_index_; }

 private:
  Runtime& runtime_;
  PhotonGridParams params_{};
  std::unique_ptr<StageKernel> count_, scatter_, sort_, copy_;
  ExclusiveScan scan_;
  size_t photon_capacity_ = 0, bucket_capacity_ = 0;  // allocated so far
  cl::Buffer bucket_start_, photon_rank_, photon_index_, photons_;
};

}  // namespace caustica
