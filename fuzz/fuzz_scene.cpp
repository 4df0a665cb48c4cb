// Fuzz target: the scene loader from the text of a scene file
// (parse_scene_text: JSON syntax, nesting, every key's type and range, shapes,
// materials, lights, and the meshes and textures a scene names, resolved
// against fuzz/assets/). The contract under test: any input either loads or
// throws caustica::Error; anything else (a crash, a sanitizer report, another
// exception escaping, a timeout, memory beyond -rss_limit_mb) is a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "host/error.h"
#include "host/scene/load_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> warnings;
  caustica::LoadOptions options;
  options.warnings = &warnings;
  try {
    caustica::parse_scene_text(text, "fuzz.json", CAUSTICA_FUZZ_ASSETS, options);
  } catch (const caustica::Error&) {
  }
  return 0;
}
