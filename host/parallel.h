// Host-side data parallelism, one helper for every caller: Workers runs a
// function over contiguous chunks (one per thread; the BVH builders merge
// per-chunk results with exact operations, so the chunking cannot show) or
// over tasks taken one by one as threads come free (for_each_dynamic);
// parallel_blocks is the latter over blocks of an index range, for
// per-element work whose result does not depend on the split (the bench's
// host reference rays, adaptive sampling's per-pixel weights): the same
// bits for any thread count. Each returns when all its work is done;
// for_each_dynamic and parallel_blocks rethrow the first exception a task
// threw (for_chunks' functions must not throw).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace caustica {

// A thread-count option: positive as given, 0 for every hardware thread.
inline int resolve_threads(int requested) {
  return requested > 0 ? requested : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

class Workers {
 public:
  explicit Workers(int threads) : threads_(threads < 1 ? 1 : threads) {}
  int threads() const { return threads_; }
  int chunks(size_t n) const { return n >= kMinChunk * 2 ? int(std::min<size_t>(threads_, n / kMinChunk)) : 1; }

  // Runs fn(chunk, begin, end) over chunk_count contiguous chunks of [0, n),
  // one per thread, the first on the calling thread.
  template <class F>
  void for_chunks(size_t n, int chunk_count, F&& fn) const {
    if (chunk_count <= 1) {
      fn(0, size_t{0}, n);
      return;
    }
    std::vector<std::thread> pool;
    for (int c = 1; c < chunk_count; ++c)
      pool.emplace_back([&fn, n, c, chunk_count] { fn(c, n * c / chunk_count, n * (c + 1) / chunk_count); });
    fn(0, size_t{0}, n / chunk_count);
    for (std::thread& t : pool) t.join();
  }

  // Runs fn(i) for every i in [0, count), on up to threads() threads that
  // each take the next i as soon as they are free (for tasks of uneven
  // size); the first exception thrown is rethrown here once all stop.
  template <class F>
  void for_each_dynamic(size_t count, F&& fn) const {
    std::atomic<size_t> next{0};
    std::exception_ptr error;
    std::mutex error_mutex;
    const int threads = static_cast<int>(std::max<size_t>(1, std::min<size_t>(threads_, count)));
    for_chunks(size_t(threads), threads, [&](int, size_t, size_t) {
      try {
        for (size_t i; (i = next++) < count;) fn(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next = count;
      }
    });
    if (error) std::rethrow_exception(error);
  }

 private:
  static constexpr size_t kMinChunk = 2048;  // below this a thread costs more than it saves
  int threads_;
};

// body(begin, end) over [0, n) in blocks of `block` elements, on `threads`
// threads (0: every hardware thread), each taking the next block when free.
void parallel_blocks(size_t n, int threads, const std::function<void(size_t, size_t)>& body, size_t block = 4096);

}  // namespace caustica
