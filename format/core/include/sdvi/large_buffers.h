// SPDX-License-Identifier: GPL-3.0-or-later
// Large scratch and output arrays: reserving them with a hint to the kernel to back them
// with transparent huge pages. On virtual machines a 4 KiB page fault can cost tens of
// microseconds, which made first-touch faults most of the cost of building a stencil
// table; 2 MiB pages cut their number by 512. Only a hint: behaviour is unchanged where
// the kernel ignores it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace sdvi::internal {

// Advises huge pages for the 2 MiB-aligned part of [data, data + bytes).
inline void AdviseHugePages([[maybe_unused]] const void* data, [[maybe_unused]] size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr uintptr_t kHuge = uintptr_t{2} << 20;
  const uintptr_t begin = (reinterpret_cast<uintptr_t>(data) + kHuge - 1) & ~(kHuge - 1);
  const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) & ~(kHuge - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#endif
}

// Arrays of at least this many bytes are reserved with the huge-page hint.
inline constexpr size_t kLargeBufferBytes = size_t{1} << 20;

// v.reserve(n), with the huge-page hint when the new storage is large and untouched. The
// storage is reserved up to 2 MiB longer, so that the huge page holding the array's end lies
// inside it: only the part before the first 2 MiB boundary (where malloc placed the block)
// is faulted in 4 KiB pages.
template <typename T, typename A>
void ReserveLarge(std::vector<T, A>& v, size_t n) {
  if (n <= v.capacity()) return;
  if (!v.empty() || n * sizeof(T) < kLargeBufferBytes) {
    v.reserve(n);
    return;
  }
  v.reserve(n + ((size_t{2} << 20) + sizeof(T) - 1) / sizeof(T));
  AdviseHugePages(v.data(), v.capacity() * sizeof(T));
}

}  // namespace sdvi::internal
