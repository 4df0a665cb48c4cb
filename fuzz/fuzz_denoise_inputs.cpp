// Fuzz target: what `caustica denoise` reads (host/denoise/denoise_inputs.h):
// an EXR's channel list, its layers as renderers name them, and the guides'
// sizes. The bytes go to a file (the reader takes paths, as the command
// does); a malformed file must give caustica::Error naming it, never a
// crash, a sanitizer report or another exception.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "host/denoise/denoise_inputs.h"
#include "host/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "/tmp/caustica_fuzz_denoise_" + std::to_string(getpid()) + ".exr";
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  try {
    caustica::read_denoise_inputs(path);
  } catch (const caustica::Error&) {
  }
  return 0;
}
