// Host-side data parallelism for per-element work whose result does not
// depend on how it is split: body(begin, end) over [0, n) in blocks of
// `block` elements, shared out to `threads` threads (0: every hardware
// thread) that each take the next block when free. Used where each element
// is computed on its own (the bench's host reference rays, adaptive
// sampling's per-pixel weights), so the outcome is the same bits for any
// thread count. Returns when every block is done.
#pragma once

#include <cstddef>
#include <functional>

namespace caustica {

void parallel_blocks(size_t n, int threads, const std::function<void(size_t, size_t)>& body, size_t block = 4096);

}  // namespace caustica
