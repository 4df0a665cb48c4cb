// A render shared by a group of processes (issues 23 and 40: mpirun's
// ranks, docs/distributed.md): what the render core needs of the group, so
// that it stays free of MPI (host/app/rank_group.h derives from this;
// host/mpi/ implements it).
//
// Rules. Every process runs one process's waves and traces its part of
// each (pass_driver.h's WaveShare): an even wave's pixels by window
// (share_of: contiguous, by rank), an uneven wave's by equal shares of its
// samples (samples_share_of). With the photon pass each process traces its
// share of each photon map's photons (contiguous, by rank); the stored
// photons are gathered to every process in rank order, which is photon
// order, so every process builds the grid one process would, and each
// pixel's SPPM statistics are updated by the one process whose window holds
// it in the map's pass (an even wave). The collectives below are called by
// every process in the same order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace caustica {

class PixelShare {
 public:
  virtual ~PixelShare() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Every process's `mine`, concatenated in rank order, on every process.
  virtual std::string gather_bytes_to_all(const std::string& mine) = 0;
  // On rank 0 every process's `mine`, by rank; elsewhere empty.
  virtual std::vector<std::string> gather_bytes_to_root(const std::string& mine) = 0;
  // Each value's sum over the processes, on every process (integers: exact).
  virtual void sum_to_all(std::vector<uint64_t>& values) = 0;
  // Each 128-bit integer's sum (two words, low first: the film's sums),
  // on every process.
  virtual void sum128_to_all(std::vector<uint64_t>& sums128) = 0;
  // `values` summed over the processes, each process keeping its segment:
  // the values hold one segment a process, in rank order, counts[r] long
  // (every process the same counts); returns this process's, summed.
  // 64-bit integers, or (sum128) 128-bit ones as two words each.
  virtual std::vector<uint64_t> sum_scatter(const std::vector<uint64_t>& values, const std::vector<size_t>& counts) = 0;
  virtual std::vector<uint64_t> sum128_scatter(const std::vector<uint64_t>& values,
                                               const std::vector<size_t>& counts) = 0;
  // Rank 0's `value`, on every process (a decision its clock takes for all).
  virtual int broadcast(int value) = 0;
  // Seconds this process spent in the collectives that move data (those
  // above; waits at a barrier apart), over its life.
  virtual double collective_seconds() const { return 0.0; }
};

// What sharing the photon maps cost a process, over a render: the bytes
// of stored photons gathered to it (every map whole), the seconds waiting
// for the slowest process before each gather (the imbalance of the
// processes' photons and pixels), and the seconds in the gathers.
struct SharedPhotonTraffic {
  uint64_t bytes = 0;
  double wait_seconds = 0.0, gather_seconds = 0.0;
};

// [begin, end) of `count` items that process `rank` of `size` takes:
// contiguous, in rank order, sizes differing by one at most.
inline std::pair<size_t, size_t> share_of(size_t count, int rank, int size) {
  if (size <= 1) return {0, count};
  const auto at = [&](int r) { return size_t((unsigned __int128)count * unsigned(r) / unsigned(size)); };
  return {at(rank), at(rank + 1)};
}

// [begin, end) of the pixels of an uneven wave (`samples` a pixel) that
// process `rank` of `size` traces: contiguous, in rank order, cut at the
// pixel boundaries nearest equal shares of the samples (process r's share
// begins at the first pixel whose samples before it reach r / size of the
// whole), so the processes' work differs by about one pixel's samples
// however unevenly the samples lie in the image.
inline std::pair<size_t, size_t> samples_share_of(const std::vector<uint32_t>& samples, int rank, int size) {
  if (size <= 1) return {0, samples.size()};
  uint64_t total = 0;
  for (uint32_t k : samples) total += k;
  // (the wave's samples fit 32 bits: Film::plan_wave; times the ranks, 64)
  const auto cut = [&](int r) {
    if (r <= 0) return size_t(0);
    if (r >= size) return samples.size();
    const uint64_t share = total * uint64_t(r);  // compared as before * size >= share
    uint64_t before = 0;
    size_t p = 0;
    while (p < samples.size() && before * uint64_t(size) < share) before += samples[p++];
    return p;
  };
  return {cut(rank), cut(rank + 1)};
}

}  // namespace caustica
