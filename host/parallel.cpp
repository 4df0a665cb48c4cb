#include "host/parallel.h"

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace caustica {

void parallel_blocks(size_t n, int threads, const std::function<void(size_t, size_t)>& body, size_t block) {
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
  block = std::max<size_t>(1, block);
  std::atomic<size_t> next{0};
  auto worker = [&] {
    for (size_t begin; (begin = next.fetch_add(block)) < n;) body(begin, std::min(n, begin + block));
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads && size_t(t) * block < n; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
}

}  // namespace caustica
