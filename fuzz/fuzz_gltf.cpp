// Fuzz target: the glTF importer (our schema checks, tinygltf's parse of a
// .gltf text or a .glb container, then the accessor, node graph, material,
// texture and light conversion) on one file's bytes. External files are off:
// every buffer and image must be embedded (data URIs, the GLB's BIN chunk),
// so an input is self-contained. Any input loads or throws caustica::Error.
#include <cstddef>
#include <cstdint>
#include <string>

#include "host/error.h"
#include "host/scene/gltf.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  caustica::Scene scene;
  caustica::TextureLibrary textures(scene);
  try {
    caustica::import_gltf_bytes("fuzz.gltf", input, ".", textures, /*allow_files=*/false);
  } catch (const caustica::Error&) {
  }
  return 0;
}
