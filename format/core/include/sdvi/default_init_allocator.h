// SPDX-License-Identifier: GPL-3.0-or-later
// DefaultInitAllocator: vectors whose resize leaves new elements unwritten.
#pragma once

#include <memory>
#include <new>
#include <utility>

namespace sdvi {

// std::allocator, except that a value-less construct (resize(n), vector(n)) leaves the new
// elements default-initialised (for bytes and doubles: unwritten), so that an array can be
// written wholly by several threads, each writing (or zeroing) its own part, instead of one
// thread zeroing it all before: the first touch of its pages, most of the cost of a fresh
// large array on a virtual machine, is then spread over the threads (Render8's output,
// spec/METHOD.md section 4 item 5; RefineImage's levels).
template <typename T>
struct DefaultInitAllocator : std::allocator<T> {
  using value_type = T;
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
