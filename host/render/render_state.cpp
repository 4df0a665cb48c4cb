#include "host/render/render_state.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <type_traits>

#include "host/error.h"
#include "host/limits.h"
#include "host/read_file.h"
#include "host/render/integrator.h"
#include "host/render/state_bytes.h"
#include "host/scene/gltf.h"
#include "host/write_file.h"

namespace caustica {
namespace {

namespace fs = std::filesystem;

// The header: magic, version, payload size; the payload; its checksum.
constexpr char kMagic[16] = {'c', 'a', 'u', 's', 't', 'i', 'c', 'a', ' ', 's', 't', 'a', 't', 'e', '\n', '\0'};
constexpr size_t kHeaderBytes = sizeof kMagic + 4 + 8;
constexpr size_t kChecksumBytes = 8;

constexpr uint64_t kFnvOffset = 14695981039346656037ull, kFnvPrime = 1099511628211ull;

uint64_t fnv1a(const void* data, size_t bytes, uint64_t h = kFnvOffset) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) h = (h ^ p[i]) * kFnvPrime;
  return h;
}

std::string hex64(uint64_t v) {
  char b[24];
  std::snprintf(b, sizeof b, "%016llx", (unsigned long long)v);
  return b;
}

std::string number(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

const char* strategy_name(uint32_t s) {
  switch (s) {
    case PATH_STRATEGY_MIS: return "mis";
    case PATH_STRATEGY_NEE: return "light sampling";
    case PATH_STRATEGY_BSDF: return "bsdf sampling";
    default: return "unknown";
  }
}

}  // namespace

uint64_t scene_hash(const Scene& scene) {
  uint64_t h = kFnvOffset;
  const bool gltf = scene.document.empty() && is_gltf_file(scene.source_path);
  const std::string file = !scene.document.empty()
                               ? scene.document
                               : read_input_file(scene.source_path, "scene file",
                                                 gltf ? limits::kMaxMeshFileBytes : limits::kMaxSceneFileBytes);
  h = fnv1a(file.data(), file.size(), h);
  // A glTF file holds several cameras and --camera picks one: the camera
  // used is part of what the state is of (a JSON scene's is in its bytes).
  if (gltf) {
    const CameraDesc& c = scene.camera;
    const float camera[] = {c.position.x, c.position.y, c.position.z, c.look_at.x, c.look_at.y,  c.look_at.z,
                            c.up.x,       c.up.y,       c.up.z,       c.fov_y_degrees, float(c.width), float(c.height)};
    h = fnv1a(camera, sizeof camera, h);
  }
  for (const Scene::MeshInfo& mesh : scene.meshes) {
    if (mesh.file.empty()) continue;  // an inline mesh: its vertices are in the scene's document
    const std::string bytes = read_input_file(mesh.file, "mesh file", limits::kMaxMeshFileBytes);
    h = fnv1a(bytes.data(), bytes.size(), h);
  }
  // The texels as decoded (half floats, no padding): every texture file's
  // content, and the fallback checker of one that could not be read.
  for (uint16_t t : scene.texels) {
    const unsigned char b[2] = {static_cast<unsigned char>(t & 0xFF), static_cast<unsigned char>(t >> 8)};
    h = fnv1a(b, 2, h);
  }
  // The environment map as decoded (a file's texels, or the generated sky).
  if (scene.environment) h = fnv1a(scene.environment->rgb.data(), scene.environment->rgb.size() * sizeof(float), h);
  return h;
}

StateIdentity render_identity(uint64_t scene, RenderMode mode, const RenderSettings& settings,
                              const std::string& bvh) {
  StateIdentity id;
  id.emplace_back("scene hash", hex64(scene));
  id.emplace_back("mode", render_mode_name(mode));
  id.emplace_back("width", std::to_string(settings.width));
  id.emplace_back("height", std::to_string(settings.height));
  const bool path = mode == RenderMode::Path;
  if (path) {
    id.emplace_back("seed", std::to_string(settings.seed));
    id.emplace_back("sampler", settings.sampler == SAMPLER_INDEPENDENT ? "independent" : "sobol");
    id.emplace_back("strategy", strategy_name(settings.path_strategy));
    id.emplace_back("adaptive", settings.adaptive ? "on" : "off");
    if (settings.adaptive) {
      const AdaptiveOptions& a = settings.adaptive_options;
      id.emplace_back("adaptive min spp", std::to_string(a.min_spp));
      id.emplace_back("adaptive uniform share", number(a.uniform_share));
      id.emplace_back("adaptive filter radius", std::to_string(a.filter_radius));
      id.emplace_back("adaptive dilate radius", std::to_string(a.dilate_radius));
      id.emplace_back("adaptive weighs cost", a.weigh_cost ? "on" : "off");
    }
  }
  id.emplace_back("half buffer", settings.half_buffer || settings.adaptive ? "on" : "off");
  id.emplace_back("photon pass", settings.caustics ? "on" : "off");
  // The light sampler picks other lights for the same samples; named only
  // when it is not the power CDF, which every state before it used.
  if (path && settings.light_sampler != LightSampler::Power)
    id.emplace_back("light sampler", light_sampler_name(settings.light_sampler));
  if (path) id.emplace_back("aux passes", settings.aux_passes ? "on" : "off");
  if (settings.caustics) {
    id.emplace_back("caustics", settings.caustics_auto ? "auto" : "on");
    id.emplace_back("photons per pass", std::to_string(settings.photons_per_pass));
    id.emplace_back("caustic radius", number(settings.caustic_radius));
    id.emplace_back("photon guiding", settings.photon_guiding ? "on" : "off");
  }
  id.emplace_back("bvh", bvh);
  id.emplace_back("film fixed point", "2^-" + std::to_string(FILM_FRACTION_BITS));
  return id;
}

std::string encode_render_state(const RenderState& state) {
  StateWriter payload;
  payload.put(uint32_t(state.identity.size()));
  for (const auto& [name, value] : state.identity) {
    payload.text(name);
    payload.text(value);
  }
  const FilmState& f = state.film;
  payload.put(int32_t(f.passes));
  payload.put(uint32_t(f.held.ranges().size()));
  for (const auto& [begin, end] : f.held.ranges()) {
    payload.put(int32_t(begin));
    payload.put(int32_t(end));
  }
  payload.put(uint8_t(f.per_pixel ? 1 : 0));
  payload.array(f.spp);
  payload.array(f.half_start);
  payload.array(f.pixel_rays);
  payload.array(f.counters);
  payload.array(f.accumulated);
  payload.put(uint8_t(state.adaptive ? 1 : 0));
  if (state.adaptive) {
    payload.put(int32_t(state.adaptive->weights_passes));
    payload.array(state.adaptive->weights);
  }
  payload.blob(state.integrator);
  const std::string& body = payload.bytes();
  StateWriter file;
  file.bytes().assign(kMagic, sizeof kMagic);
  file.put(kRenderStateVersion);
  file.put(uint64_t(body.size()));
  file.bytes() += body;
  file.put(fnv1a(body.data(), body.size()));
  return std::move(file.bytes());
}

RenderState decode_render_state(const std::string& bytes, const std::string& path) {
  if (bytes.size() < sizeof kMagic && std::memcmp(bytes.data(), kMagic, bytes.size()) == 0)
    throw Error(path + ": truncated: " + std::to_string(bytes.size()) + " bytes, less than a state's header");
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw Error(path + ": not a caustica state file (it does not start with \"caustica state\")");
  if (bytes.size() < kHeaderBytes + kChecksumBytes)
    throw Error(path + ": truncated: " + std::to_string(bytes.size()) + " bytes, less than a state's header");
  StateReader header(bytes, sizeof kMagic, kHeaderBytes, path);
  const uint32_t version = header.get<uint32_t>("version");
  if (version != kRenderStateVersion)
    throw Error(path + ": state file version " + std::to_string(version) + ", this caustica reads version " +
                std::to_string(kRenderStateVersion));
  const uint64_t payload = header.get<uint64_t>("payload size");
  const uint64_t expected = kHeaderBytes + payload + kChecksumBytes;
  if (payload > bytes.size() || expected > bytes.size())
    throw Error(path + ": truncated: " + std::to_string(bytes.size()) + " bytes, its header says " +
                std::to_string(payload > bytes.size() ? payload : expected));
  if (expected < bytes.size())
    throw Error(path + ": " + std::to_string(bytes.size() - expected) + " bytes after the state's end (" +
                std::to_string(expected) + " bytes)");
  StateReader trailer(bytes, kHeaderBytes + payload, bytes.size(), path);
  const uint64_t stored = trailer.get<uint64_t>("checksum");
  const uint64_t computed = fnv1a(bytes.data() + kHeaderBytes, payload);
  if (stored != computed)
    throw Error(path + ": checksum mismatch (stored " + hex64(stored) + ", computed " + hex64(computed) +
                "): the file is damaged");

  StateReader in(bytes, kHeaderBytes, kHeaderBytes + payload, path);
  RenderState state;
  const uint32_t names = in.get<uint32_t>("identity");
  for (uint32_t i = 0; i < names; ++i) {
    std::string name = in.text("identity");
    std::string value = in.text("identity");
    state.identity.emplace_back(std::move(name), std::move(value));
  }
  FilmState& f = state.film;
  f.passes = in.get<int32_t>("film");
  const uint32_t ranges = in.get<uint32_t>("pass set");
  std::vector<PassSet::Range> held;
  for (uint32_t i = 0; i < ranges; ++i) {
    const int32_t begin = in.get<int32_t>("pass set");
    held.emplace_back(begin, in.get<int32_t>("pass set"));
  }
  f.held = PassSet::from_ranges(std::move(held), path);
  f.per_pixel = in.get<uint8_t>("film") != 0;
  f.spp = in.array<uint32_t>("per-pixel samples");
  f.half_start = in.array<uint32_t>("half starts");
  f.pixel_rays = in.array<uint64_t>("per-pixel rays");
  f.counters = in.array<uint32_t>("film counters");
  f.accumulated = in.array<uint64_t>("accumulated sums");
  if (in.get<uint8_t>("adaptive sampler") != 0) {
    AdaptiveSamplerState a;
    a.weights_passes = in.get<int32_t>("adaptive sampler");
    a.weights = in.array<double>("adaptive weights");
    state.adaptive = std::move(a);
  }
  state.integrator = in.blob("integrator state");
  if (!in.done()) throw Error(path + ": the state's payload has bytes after its end (written by another caustica?)");
  return state;
}

RenderState read_render_state(const std::string& path) {
  return decode_render_state(read_input_file(path, "state file", limits::kMaxStateFileBytes), path);
}

void write_render_state(const std::string& path, const RenderState& state) {
  write_output_file(path, encode_render_state(state), "state file");
}

void check_render_state(const std::string& path, const RenderState& state, const StateIdentity& render) {
  for (const auto& [name, asked] : render) {
    const std::string* held = nullptr;
    for (const auto& [n, v] : state.identity)
      if (n == name) held = &v;
    if (!held) throw Error(path + ": the state has no " + name + " (written by another caustica?)");
    if (*held == asked) continue;
    if (name == "scene hash")
      throw Error(path + ": made for scene hash " + *held + ", this scene is " + asked +
                  " (the scene file, its meshes and textures)");
    throw Error(path + ": " + name + " " + *held + " in the state, " + asked + " asked");
  }
  for (const auto& [name, value] : state.identity) {
    bool known = false;
    for (const auto& entry : render) known = known || entry.first == name;
    if (!known) throw Error(path + ": " + name + " " + value + " in the state, which this render does not have");
  }
}

}  // namespace caustica
