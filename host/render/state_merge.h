// Adding render states of disjoint passes (issue 23): `caustica merge` and
// the MPI ranks' reduction (host/app/mpi_render.h) add films the same way.
//
// Rules. The film's accumulated sums are 128-bit integers (film.h), so
// films of disjoint pass sets add, word pair by word pair with the carry,
// to exactly the sums of one film holding their union, whatever the order.
// The half buffer is the held passes from P on, P the largest power of two
// at most the last held pass (pass_set.h); a film whose last pass is below
// the union's P holds none of the union's half, and its half (an older
// one) is left out; any other film's half starts at that same P and is
// added. Per-pixel counts, traced rays and the film's counters add.
//
// What cannot be added is refused, naming the file and the reason: states
// of different identities (scene, size, seed, settings: the first
// difference), overlapping pass sets (the first common pass), adaptive
// states (each wave's allocation was planned from the whole film of passes
// [0, N): the parts of one render cannot be planned apart, and two
// adaptive renders both hold pass 0), and states with the photon pass (its
// per-pixel SPPM statistics (N, tau, r^2) shrink each pixel's radius pass
// by pass: they are not sums of passes and do not add).
#pragma once

#include <cstddef>
#include <optional>
#include <cstdint>
#include <string>
#include <vector>

#include "host/image/image.h"
#include "host/render/render_state.h"

namespace caustica {

struct NamedState {
  std::string path;  // for errors
  RenderState state;
};

// Throws caustica::Error when `state` cannot be added (the reasons above),
// or its identity differs from `first`'s.
void check_mergeable(const NamedState& first, const NamedState& state);
// The sum of the states (at least one; check_mergeable each against the
// first, then the pass sets pairwise): a state of the union of their
// passes, with the first's identity.
RenderState merge_render_states(const std::vector<NamedState>& states);

// `into` += `from`: `values` 128-bit sums, two 64-bit words each, low first.
void add_film_sums(uint64_t* into, const uint64_t* from, size_t values);
// Whether a film holding `held` contributes its half buffer to a union
// whose last pass is `union_last` (above).
bool half_is_in_union(const PassSet& held, int union_last);

// The image of a film state: each sum as the nearest float (film_sums.h),
// divided by the pixel's count as Film::mean does (the same bits). Without the photon pass's separate estimate.
ImageF film_state_mean(const FilmState& film, int width, int height);
// Its aux passes' means, as Film::aux_mean (nullopt for a film without them).
std::optional<AuxImages> film_state_aux_mean(const FilmState& film, int width, int height);
// The identity's value of `name` (throws naming `path` when it is absent).
std::string identity_value(const std::string& path, const StateIdentity& identity, const std::string& name);

}  // namespace caustica
