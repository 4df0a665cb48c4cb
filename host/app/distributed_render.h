// `mpirun -np N caustica render ...` (issues 23 and 40): the work split
// across ranks, the films summed on rank 0.
//
// Rules. Path mode shares every wave (host/render/pass_driver.h's
// WaveShare): every rank runs one process's pass driver with the same stop
// conditions, so it plans the waves one process would (adaptive sampling,
// the photon pass's schedule and `auto`'s decisions included), and traces
// its part of each: an even wave's pixels by equal windows, an uneven
// wave's by equal shares of its samples. A rank's film counts every
// pixel's samples (so sample indices and half-buffer restarts are one
// process's) but sums only what it traced; the films summed as 128-bit
// integers are one process's film, bit for bit. Rank 0 decides what one
// process decides from its clock (a wave cut to a time limit, whether to
// go on: broadcast after every wave when there is anything to decide);
// where the adaptive sampler refreshes its weights (O(log passes) times)
// every rank computes them from the films' colour sums and ray counts
// summed on all (Film::summed_means). With the photon pass each rank traces its slice of each
// photon map, the maps gathered whole to every rank, and each pixel's SPPM
// statistics live with the rank whose window holds it (a photon map's pass
// is an even wave; pixel_share.h; docs/distributed.md).
// Binary and phong (one pass each) split passes in rounds instead: round j
// covers global passes [g, g + N b) and rank r traces [g + r b, g + (r + 1)
// b), its passes keeping their absolute indices (pass_set.h).
// Rank 0 alone reads a resumed state (by waves it sends it to every rank,
// whose sums start at zero), measures the error of the summed film, and
// writes checkpoints and progressive images of it. Progress comes from rank
// 0 only.
#pragma once

#include <functional>
#include <memory>

#include "host/app/error_monitor.h"
#include "host/app/rank_group.h"
#include "host/app/session.h"
#include "host/render/renderer.h"

namespace caustica {

struct DistributedResult {
  ImageF image;                      // rank 0: the summed film's mean; elsewhere empty
  std::unique_ptr<Renderer> summed;  // rank 0: a renderer holding the summed film
  double seconds = 0.0;              // render time (rank 0's)
  int reductions = 0;                // film reductions to rank 0
  double reduction_seconds = 0.0;    // rank 0's time in them: film reads, MPI and restore together
  // ... and apart: reading the film, waiting for the slowest rank, the
  // MPI calls, restoring the sum on rank 0.
  double read_seconds = 0.0, wait_seconds = 0.0, mpi_seconds = 0.0, restore_seconds = 0.0;
  // Rank 0's error measurements on the summed film (the other ranks wait
  // for its decision meanwhile). The film reads include waiting for the
  // device to finish the round's queued work.
  double measure_seconds = 0.0;
  // By waves: the adaptive sampler's weight refreshes (the colour sums and
  // ray counts summed on every rank, which computes the weights itself) and
  // their time on rank 0 (apart: waiting for the slowest rank before each); what gathering the photon maps cost rank 0
  // (pixel_share.h).
  bool by_waves = false;
  int weight_refreshes = 0;
  // The refreshes (of which in MPI's collectives), and waiting for the
  // slowest rank before them.
  double weight_seconds = 0.0, weight_mpi_seconds = 0.0, weight_wait_seconds = 0.0;
  SharedPhotonTraffic photon_traffic;
};

// Rank 0's outputs while rendering, each of the summed film (the ranks'
// films are summed for it, after a wave or round): `checkpoint` every
// `checkpoint_every_s` seconds, `write` (--write-every: the images) every
// `write_every_s` seconds, given the render's seconds.
struct DistributedOutputs {
  double checkpoint_every_s = 0.0;
  std::function<void(const Renderer&)> checkpoint;  // empty: none
  double write_every_s = 0.0;
  std::function<void(const Renderer&, double seconds)> write;  // empty: none
};

// `monitor`, `progress`, `resume` and `outputs` are rank 0's (nullptr /
// empty elsewhere). A resumed state (passes [0, N) only) is rank 0's film
// at the start; the rounds go on from N.
DistributedResult render_distributed(Session& session, RankGroup& ranks, RenderStats* stats,
                                     const ProgressCallback& progress, ErrorMonitor* monitor,
                                     const RenderState* resume = nullptr,
                                     const DistributedOutputs& outputs = {});

// Every rank's film, summed on rank 0 (the union of their passes; on
// other ranks the returned state is their own, unchanged in meaning).
// Collective.
// `by_waves`: the ranks shared every wave (each holding the same passes,
// counting every pixel's samples, summing its own): the pass sets must be
// equal, and rank 0's per-pixel counts and half starts are the image's.
FilmState reduce_film_to_root(RankGroup& ranks, FilmState mine, bool by_waves = false);

}  // namespace caustica
