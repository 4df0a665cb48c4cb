#include "host/render/state_merge.h"

#include <cstdlib>

#include "host/error.h"
#include "lib/film_sums.h"

namespace caustica {

std::string identity_value(const std::string& path, const StateIdentity& identity, const std::string& name) {
  for (const auto& [n, v] : identity)
    if (n == name) return v;
  throw Error(path + ": the state has no " + name + " (written by another caustica?)");
}

void check_mergeable(const NamedState& first, const NamedState& named) {
  const RenderState& s = named.state;
  const std::string& path = named.path;
  if (!s.integrator.empty())
    throw Error(path + ": a state with the photon pass: its per-pixel SPPM statistics (N, tau, r^2) are not sums of "
                       "passes and cannot be added; render the parts with --caustics off, or the whole in one process or on "
                       "mpirun's ranks");
  if (s.adaptive)
    throw Error(path + ": an adaptive render's state: its waves were planned from the whole film of passes [0, " +
                std::to_string(s.film.held.end()) + "), so its parts cannot be merged; render the parts with "
                "--no-adaptive, or the whole on mpirun's ranks (which keep adaptive sampling)");
  const StateIdentity& want = first.state.identity;
  for (size_t i = 0; i < std::max(want.size(), s.identity.size()); ++i) {
    if (i < want.size() && i < s.identity.size() && want[i] == s.identity[i]) continue;
    if (i >= s.identity.size())
      throw Error(path + ": the state has no " + want[i].first + ", which " + first.path + " has");
    if (i >= want.size())
      throw Error(path + ": " + s.identity[i].first + " " + s.identity[i].second + ", which " + first.path +
                  " does not have");
    const auto& [name, value] = s.identity[i];
    if (name != want[i].first)
      throw Error(path + ": identity entry " + std::to_string(i) + " is " + name + ", " + first.path + "'s is " +
                  want[i].first + " (written by another caustica?)");
    if (name == "scene hash")
      throw Error(path + ": made for scene hash " + value + ", " + first.path + " for " + want[i].second +
                  " (another scene, or the scene file, its meshes or textures changed)");
    throw Error(path + ": " + name + " " + value + ", " + first.path + " has " + name + " " + want[i].second);
  }
  const FilmState &a = first.state.film, &b = s.film;
  if (a.spp.size() != b.spp.size() || a.accumulated.size() != b.accumulated.size() ||
      a.counters.size() != b.counters.size())
    throw Error(path + ": a film of " + std::to_string(b.spp.size()) + " pixels and " +
                std::to_string(b.accumulated.size()) + " sum words, " + first.path + "'s has " +
                std::to_string(a.spp.size()) + " and " + std::to_string(a.accumulated.size()));
  if (b.per_pixel) throw Error(path + ": an uneven (adaptive) film cannot be merged");
  // The header's counts agree with the data they describe.
  FilmLayout layout;
  if (!FilmLayout::from_words(b.spp.size(), b.accumulated.size(), &layout))
    throw Error(path + ": a film of " + std::to_string(b.spp.size()) + " pixels and " +
                std::to_string(b.accumulated.size()) + " sum words, which no film layout has");
  try {
    Film::check_state_counts(b, layout);
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
}

void add_film_sums(uint64_t* into, const uint64_t* from, size_t values) {
  for (size_t i = 0; i < values; ++i) {
    const uint64_t low = into[2 * i] + from[2 * i];
    into[2 * i + 1] += from[2 * i + 1] + (low < from[2 * i] ? 1u : 0u);
    into[2 * i] = low;
  }
}

bool half_is_in_union(const PassSet& held, int union_last) {
  const int p = PassSet::half_start(union_last);
  return p >= 1 && held.last() >= p;
}

RenderState merge_render_states(const std::vector<NamedState>& states) {
  if (states.empty()) throw Error("merge: no states");
  for (const NamedState& s : states) check_mergeable(states.front(), s);
  PassSet all;
  for (size_t i = 0; i < states.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      const int common = states[j].state.film.held.first_common(states[i].state.film.held);
      if (common >= 0)
        throw Error(states[i].path + ": its " + states[i].state.film.held.describe() + " overlap " + states[j].path +
                    "'s " + states[j].state.film.held.describe() + " (both hold pass " + std::to_string(common) +
                    "): merged states must hold disjoint passes");
    }
    all.add(states[i].state.film.held);
  }
  RenderState out;
  out.identity = states.front().state.identity;
  FilmState& f = out.film;
  const FilmState& first = states.front().state.film;
  const size_t pixels = first.spp.size();
  // The sums: the combined sum's values (colour, then the aux passes if
  // kept), then the half's, if kept (FilmLayout).
  FilmLayout layout;
  if (!FilmLayout::from_words(pixels, first.accumulated.size(), &layout))
    throw Error(states.front().path + ": a film of " + std::to_string(pixels) + " pixels and " +
                std::to_string(first.accumulated.size()) + " sum words, which no film layout has");
  const size_t values = layout.values();
  const bool half = layout.half;
  f.held = all;
  f.passes = all.count();
  f.spp.assign(pixels, 0u);
  f.pixel_rays.assign(pixels, 0u);
  f.counters.assign(first.counters.size(), 0u);
  f.accumulated.assign(first.accumulated.size(), 0u);
  for (const NamedState& named : states) {
    const FilmState& s = named.state.film;
    for (size_t p = 0; p < pixels; ++p) {
      f.spp[p] += s.spp[p];
      f.pixel_rays[p] += s.pixel_rays[p];
    }
    for (size_t c = 0; c < f.counters.size(); ++c) f.counters[c] += s.counters[c];
    add_film_sums(f.accumulated.data(), s.accumulated.data(), values);
    if (half && half_is_in_union(s.held, all.last()))
      add_film_sums(f.accumulated.data() + 2 * values, s.accumulated.data() + 2 * values, values);
  }
  const int half_count = all.half_count();
  f.half_start.assign(pixels, half_count > 0 ? uint32_t(f.passes - half_count) : 0u);
  return out;
}

ImageF film_state_mean(const FilmState& film, int width, int height) {
  ImageF image(width, height);
  const size_t pixels = size_t(width) * size_t(height);
  if (film.spp.size() != pixels || film.accumulated.size() < pixels * 6)
    throw Error("film state: " + std::to_string(film.spp.size()) + " pixels for a " + std::to_string(width) + "x" +
                std::to_string(height) + " image");
  for (size_t p = 0; p < pixels; ++p) {
    const float inv = film.spp[p] > 1 ? 1.0f / float(film.spp[p]) : 1.0f;
    for (int c = 0; c < 3; ++c) {
      const size_t i = 3 * p + c;
      // As read_film_sums and Film::divide_by round: two float products.
      float v = film_sum_to_float(film.accumulated[2 * i], film.accumulated[2 * i + 1]);
      if (film.spp[p] > 1) v *= inv;
      image.rgb[i] = v;
    }
  }
  return image;
}

std::optional<AuxImages> film_state_aux_mean(const FilmState& film, int width, int height) {
  const size_t pixels = size_t(width) * size_t(height);
  FilmLayout layout;
  if (film.spp.size() != pixels || !FilmLayout::from_words(pixels, film.accumulated.size(), &layout))
    throw Error("film state: " + std::to_string(film.accumulated.size()) + " sum words for a " +
                std::to_string(width) + "x" + std::to_string(height) + " image");
  if (!layout.aux) return std::nullopt;
  const size_t k = FilmLayout::kAuxChannels;
  AuxImages aux;
  aux.albedo = ImageF(width, height);
  aux.normal = ImageF(width, height);
  aux.depth.assign(pixels, 0.0f);
  for (size_t p = 0; p < pixels; ++p) {
    const float inv = film.spp[p] > 0 ? 1.0f / float(film.spp[p]) : 0.0f;
    float v[FilmLayout::kAuxChannels];
    for (size_t c = 0; c < k; ++c) {
      const size_t i = pixels * 3 + k * p + c;
      v[c] = film_sum_to_float(film.accumulated[2 * i], film.accumulated[2 * i + 1]) * inv;
    }
    for (int c = 0; c < 3; ++c) {
      aux.albedo.rgb[3 * p + c] = v[c];
      aux.normal.rgb[3 * p + c] = film.spp[p] > 0 ? 2.0f * v[3 + c] - 1.0f : 0.0f;
    }
    aux.depth[p] = v[6];
  }
  return aux;
}

}  // namespace caustica
