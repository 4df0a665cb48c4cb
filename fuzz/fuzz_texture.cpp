// Fuzz target: texture decoding from a file's bytes (our Netpbm reader and
// the header checks in front of stb_image for PNG, JPEG, BMP, TGA, HDR...).
// decode_texture_image reports failure by its return value; nothing may
// throw, crash or allocate beyond the texture limits.
#include <cstddef>
#include <cstdint>
#include <string>

#include "host/scene/textures.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  caustica::LinearImage image;
  caustica::decode_texture_image(std::string(reinterpret_cast<const char*>(data), size), image);
  return 0;
}
