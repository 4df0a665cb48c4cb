// Fuzz target: the PLY reader (header, ASCII and binary bodies of either
// byte order, lists, triangulation). Any input loads or throws caustica::Error.
#include <cstddef>
#include <cstdint>
#include <string>

#include "host/error.h"
#include "host/scene/mesh_internal.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    caustica::mesh_internal::parse_ply("fuzz.ply", std::string(reinterpret_cast<const char*>(data), size));
  } catch (const caustica::Error&) {
  }
  return 0;
}
