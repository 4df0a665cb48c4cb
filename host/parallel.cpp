#include "host/parallel.h"

namespace caustica {

void parallel_blocks(size_t n, int threads, const std::function<void(size_t, size_t)>& body, size_t block) {
  block = std::max<size_t>(1, block);
  Workers(resolve_threads(threads)).for_each_dynamic((n + block - 1) / block, [&](size_t b) {
    body(b * block, std::min(n, (b + 1) * block));
  });
}

}  // namespace caustica
