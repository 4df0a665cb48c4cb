// Render state files (issue 23, its first step): a render saved at a wave
// boundary and resumed from there, in one process at a time.
//
// Rules. A state holds everything a path, phong or binary render needs to
// go on after an accumulated wave: the film's sums, half buffer, per-pixel
// counts, half starts and ray counts and its counters (FilmState), the
// adaptive sampler's cached weights (AdaptiveSamplerState), and the
// integrator's state (Integrator::state: with the photon pass, every
// pixel's SPPM statistics and visible point, the latest photon map, the
// gather counters and the schedule `auto` decided). The waves of a render
// with --spp depend on the film's pass count only (pass_driver.h), the
// photon pass's decisions on counts only, and the film adds passes in
// order, so a render resumed from a state ends with the same bits as one
// never interrupted, for the same seed and spp. Nothing that happens
// within a wave is saved: a state is taken only between waves.
//
// A state also records what it is a state of: its identity, a list of
// (name, value) pairs, the scene's hash first (scene_hash: the scene
// file's bytes, the mesh files' bytes and the decoded texels), then every
// setting that changes the image's bits (render_identity). A state whose
// identity differs from the render's is refused, naming the first
// difference; so is a file that is not a state, is truncated, has a bad
// checksum or another format version. Errors are caustica::Error reading
// "<path>: <what>". The file layout is docs/state_files.md; states are
// written atomically (a temporary file, flushed, renamed over the old one),
// so a render killed at any moment leaves the latest complete state.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "host/render/adaptive_sampling.h"
#include "host/render/film.h"
#include "host/scene/scene.h"

namespace caustica {

struct RenderSettings;

// (name, value) pairs, compared in order; names are fixed by the format
// version.
using StateIdentity = std::vector<std::pair<std::string, std::string>>;

struct RenderState {
  StateIdentity identity;
  FilmState film;
  std::optional<AdaptiveSamplerState> adaptive;  // present when the render samples adaptively
  std::string integrator;  // Integrator::state(): the photon pass's (empty without it)
};

inline constexpr uint32_t kRenderStateVersion = 2;

// FNV-1a 64 of the scene file's bytes, then each mesh file's bytes (in load
// order), then the decoded texels (which cover the texture files). Throws
// caustica::Error when a file cannot be read again.
uint64_t scene_hash(const Scene& scene);
// The identity of a render: the scene's hash, then the mode, size, seed,
// sampler, strategy, depth, adaptive sampling and its options, the half
// buffer, the photon pass, the BVH build (`bvh`, which decides ties between
// equally close hits) and the film's fixed point. The work-group size, device and
// thread count are not in it: the bits do not depend on them.
StateIdentity render_identity(uint64_t scene_hash, RenderMode mode, const RenderSettings& settings,
                              const std::string& bvh);

// The bytes of a state file, and back; `path` names the file in errors.
std::string encode_render_state(const RenderState& state);
RenderState decode_render_state(const std::string& bytes, const std::string& path);
// Reads and decodes a state file (regular files only, bounded by
// limits::kMaxStateFileBytes).
RenderState read_render_state(const std::string& path);
// Writes `path` atomically: path + ".tmp", flushed to disk, renamed.
void write_render_state(const std::string& path, const RenderState& state);
// Refuses (throws) a state whose identity is not `render`'s, naming the
// first difference ("made for scene hash ..., this scene is ...", "width 128
// in the state, 64 asked").
void check_render_state(const std::string& path, const RenderState& state, const StateIdentity& render);

}  // namespace caustica
