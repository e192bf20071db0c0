// SPDX-License-Identifier: GPL-3.0-or-later
// DefaultInitAllocator: vectors whose resize leaves new elements unwritten, large ones on
// huge pages from their first byte.
#pragma once

#include <cstddef>
#include <memory>
#include <new>
#include <utility>

#include "sdvi/large_buffers.h"

namespace sdvi {

// std::allocator, except that a value-less construct (resize(n), vector(n)) leaves the new
// elements default-initialised (for bytes and doubles: unwritten), so that an array can be
// written wholly by several threads, each writing (or zeroing) its own part, instead of one
// thread zeroing it all before: the first touch of its pages, most of the cost of a fresh
// large array on a virtual machine, is then spread over the threads (Render8's output,
// spec/METHOD.md section 4 item 5; RefineImage's levels). Blocks of at least
// internal::kLargeBufferBytes are whole 2 MiB pages, aligned, advised huge pages: with
// std::allocator the part before the first 2 MiB boundary, up to 2 MiB, is faulted in
// 4 KiB pages whatever the hint (sdvi/large_buffers.h).
template <typename T>
struct DefaultInitAllocator : std::allocator<T> {
  using value_type = T;
  static constexpr size_t kHugePage = size_t{2} << 20;
  T* allocate(size_t n) {
    if (n * sizeof(T) < internal::kLargeBufferBytes) return std::allocator<T>::allocate(n);
    const size_t bytes = (n * sizeof(T) + kHugePage - 1) & ~(kHugePage - 1);  // whole huge pages
    // nothrow, then bad_alloc: a failed block is an exception under the sanitizers too
    // (their throwing operator new ends the process).
    void* p = ::operator new(bytes, std::align_val_t{kHugePage}, std::nothrow);
    if (p == nullptr) throw std::bad_alloc();
    internal::AdviseHugePages(p, bytes);
    return static_cast<T*>(p);
  }
  void deallocate(T* p, size_t n) {
    if (n * sizeof(T) < internal::kLargeBufferBytes)
      std::allocator<T>::deallocate(p, n);
    else
      ::operator delete(p, std::align_val_t{kHugePage});
  }
  template <typename U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() = default;
  template <typename U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
  template <typename U>
  void construct(U* p) noexcept(noexcept(::new(static_cast<void*>(p)) U)) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

}  // namespace sdvi
