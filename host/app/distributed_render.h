// `mpirun -np N caustica render ...` (issue 23): the passes split across
// ranks, the films summed on rank 0.
//
// Rules. Passes are traced in rounds: round j covers global passes
// [g, g + N b) and rank r traces [g + r b, g + (r + 1) b) (b grows with the
// passes done, as a single render's waves do, up to the integrator's wave
// size), so every rank works to the end and, after any whole round, the
// ranks together hold passes [0, g). Each rank's passes keep their absolute
// indices (pass_set.h), so its samples are those a one-rank render takes;
// the films are summed on rank 0 as 128-bit integers (state_merge.h's
// rules for the half buffer), so the image is bit-identical to a one-rank
// render of the same passes. With --spp the ranks talk once, at the end.
// With --time, --target-error, --report, --reference or --checkpoint
// rank 0 decides
// after each round whether to go on and broadcasts it (the time limit's
// prediction uses the latest round's duration), and the error estimate is
// taken from the ranks' summed film (reduced when the error monitor
// measures: after 1, 2, 4, ... passes and where the target is projected);
// rank 0 alone reads a resumed state and writes checkpoints, of the
// summed film (passes [0, g) after a whole round: a state like any).
// Path mode's photon pass (--caustics on) is shared by pixels instead:
// every rank traces every pass over its window of pixels and its slice of
// each photon map, the maps gathered whole to every rank, each pixel's SPPM
// statistics updated by the rank that owns it and gathered to rank 0 at
// each reduction (pixel_share.h; docs/distributed.md). Adaptive sampling
// and the photon pass's `auto` are refused before this is called
// (render_command.cpp says why). Progress comes from rank 0 only.
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
  // Shared by pixels (the photon pass): what gathering the photon maps cost
  // rank 0 (pixel_share.h).
  bool by_pixels = false;
  SharedPhotonTraffic photon_traffic;
};

// Rank 0's checkpoints: `write` gets the summed film's renderer every
// `every_s` seconds (after a round; the ranks' films are summed for it).
struct DistributedCheckpoint {
  double every_s = 0.0;
  std::function<void(const Renderer&)> write;  // empty: none
};

// `monitor`, `progress`, `resume` and `checkpoint` are rank 0's (nullptr /
// empty elsewhere). A resumed state (passes [0, N) only) is rank 0's film
// at the start; the rounds go on from N.
DistributedResult render_distributed(Session& session, RankGroup& ranks, RenderStats* stats,
                                     const ProgressCallback& progress, ErrorMonitor* monitor,
                                     const RenderState* resume = nullptr,
                                     const DistributedCheckpoint& checkpoint = {});

// Every rank's film, summed on rank 0 (the union of their passes; on
// other ranks the returned state is their own, unchanged in meaning).
// Collective.
// `by_pixels`: the ranks shared the render by pixels, each holding the same
// passes of its own pixels (and zeros elsewhere): the pass sets must be
// equal, and rank 0's per-pixel counts are the image's.
FilmState reduce_film_to_root(RankGroup& ranks, FilmState mine, bool by_pixels = false);

}  // namespace caustica
