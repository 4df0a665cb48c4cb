// Allocator for large arrays that are written right after they are sized:
// resize() default-initialises, so plain data (TriangleBlock4) is not
// zero-filled first, on one thread, only to be overwritten. The first
// write then faults each page in on whichever thread fills that part,
// which matters here: a fresh 4 KiB page costs about 1.5 us (16 MB zero-
// filled serially took ~6 ms of the conference room's collapse).
//
// Transparent huge pages (madvise) were tried as well: 3x cheaper faults,
// but the kernel's synchronous compaction made some first allocations
// take 30 ms, so they are not used.
#pragma once

#include <cstddef>
#include <limits>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace caustica {

template <class T>
struct BulkAllocator {
  using value_type = T;

  BulkAllocator() = default;
  template <class U>
  BulkAllocator(const BulkAllocator<U>&) noexcept {}

  T* allocate(size_t n) {
    if (n > std::numeric_limits<size_t>::max() / sizeof(T)) throw std::bad_array_new_length();
    return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(alignof(T))));
  }
  void deallocate(T* p, size_t) noexcept { ::operator delete(p, std::align_val_t(alignof(T))); }

  // Value-less construction default-initialises: resize() leaves plain data
  // as it is instead of zeroing it.
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible<U>::value) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }

  template <class U>
  bool operator==(const BulkAllocator<U>&) const noexcept {
    return true;
  }
  template <class U>
  bool operator!=(const BulkAllocator<U>&) const noexcept {
    return false;
  }
};

template <class T>
using BulkVector = std::vector<T, BulkAllocator<T>>;

}  // namespace caustica
