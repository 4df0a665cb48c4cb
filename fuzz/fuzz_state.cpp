// Fuzz target: render state files as `caustica render --resume` and
// `caustica merge` read them (host/render/render_state.h, state_merge.h).
// The first byte chooses the input's form: even, the file's bytes as they
// are; odd, a state's payload, given the header and the checksum it needs
// (so the fuzzer reaches every field behind the checksum, as a file
// altered consistently with it would: issue 38). The contract: a state
// decodes or is refused with caustica::Error; one that decodes encodes to
// bytes that decode to the same state, merges with itself as `caustica
// merge` of one file does (every check of its counts against its data),
// and gives an image of the size its identity names, or is refused there
// with caustica::Error. Anything else (a crash, a sanitizer report, an
// allocation past -rss_limit_mb, another exception) is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "host/error.h"
#include "host/render/render_state.h"
#include "host/render/state_merge.h"

namespace {

// FNV-1a 64, the state file's checksum (docs/state_files.md).
uint64_t fnv1a(const std::string& bytes) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ull;
  return h;
}

template <typename T>
void put(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] & 1) {
    const std::string payload = bytes;
    bytes = std::string("caustica state\n", 15);
    bytes.resize(16, '\0');  // the magic's 16 bytes (render_state.cpp)
    put(bytes, caustica::kRenderStateVersion);
    put(bytes, uint64_t(payload.size()));
    bytes += payload;
    put(bytes, fnv1a(payload));
  }
  caustica::RenderState state;
  try {
    state = caustica::decode_render_state(bytes, "fuzz.cst");
  } catch (const caustica::Error&) {
    return 0;
  }
  // What decodes, encodes to what decodes the same.
  const std::string again = caustica::encode_render_state(state);
  const caustica::RenderState twice = caustica::decode_render_state(again, "fuzz-again.cst");
  if (caustica::encode_render_state(twice) != again) {
    std::fprintf(stderr, "fuzz_state: a decoded state does not survive encoding\n");
    std::abort();
  }
  try {
    const std::vector<caustica::NamedState> states{{"fuzz.cst", state}};
    const caustica::RenderState merged = caustica::merge_render_states(states);
    const int width = std::atoi(caustica::identity_value("fuzz.cst", merged.identity, "width").c_str());
    const int height = std::atoi(caustica::identity_value("fuzz.cst", merged.identity, "height").c_str());
    if (width <= 0 || height <= 0) return 0;  // `merge` refuses these too
    caustica::film_state_mean(merged.film, width, height);
    caustica::film_state_aux_mean(merged.film, width, height);
  } catch (const caustica::Error&) {
  }
  return 0;
}
