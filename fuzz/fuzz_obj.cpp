// Fuzz target: the OBJ reader (our line checks, then tinyobjloader, then the
// index checks and triangulation) with its material library. The input is
// the OBJ text, optionally followed by a NUL byte and the text that every
// "mtllib" line then reads. Any input loads or throws caustica::Error.
#include <cstddef>
#include <cstdint>
#include <string>

#include "host/error.h"
#include "host/scene/mesh_internal.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const size_t nul = input.find('\0');
  const std::string obj = input.substr(0, nul);
  const std::string mtl = nul == std::string::npos ? std::string() : input.substr(nul + 1);
  const caustica::mesh_internal::MtlSource source = [&](const std::string& id, std::string& text, std::string& name,
                                                         std::string& missing) {
    if (nul == std::string::npos) {
      missing = "Material file [ " + id + " ] not found in a path : fuzz";
      return false;
    }
    text = mtl;
    name = "fuzz.mtl";
    return true;
  };
  try {
    caustica::mesh_internal::parse_obj("fuzz.obj", obj, source);
  } catch (const caustica::Error&) {
  }
  return 0;
}
