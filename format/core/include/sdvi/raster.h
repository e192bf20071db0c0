// SPDX-License-Identifier: GPL-3.0-or-later
// Raster: a float image in memory, the common currency between converters, the
// renderer, metrics and the vectorizer.
//
// Channels are interleaved, rows top to bottom. Colour channels use the 8-bit sRGB
// scale (0..255, not clamped); the alpha channel, when present (channels == 2 or 4),
// is coverage in 0..1.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <utility>
#include <vector>

namespace sdvi {

struct Raster {
  int width = 0, height = 0, channels = 0;  // channels: 1 grey, 2 grey+alpha, 3 RGB, 4 RGBA
  std::vector<float> data;                  // width * height * channels

  Raster() = default;
  Raster(int w, int h, int c) : width(w), height(h), channels(c), data(size_t(w) * h * c, 0.f) {}
  bool has_alpha() const { return channels == 2 || channels == 4; }
  bool empty() const { return width <= 0 || height <= 0; }
  float& at(int x, int y, int c) { return data[(size_t(y) * width + x) * channels + c]; }
  float at(int x, int y, int c) const { return data[(size_t(y) * width + x) * channels + c]; }
};

// std::allocator, except that a value-less construct (resize(n), vector(n)) leaves the new
// elements default-initialised (for bytes: unwritten), so that a renderer can write the
// whole array from several threads, each zeroing its own part first (spec/METHOD.md
// section 4, item 5), instead of one thread zeroing it all before.
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

// Raster8: an 8-bit image as an 8-bit PNG stores it, the renderer's output for PNG files
// (spec/METHOD.md section 4, item 5). Same layout as Raster; colours 0..255 and alpha 0..255 (coverage x 255).
struct Raster8 {
  int width = 0, height = 0, channels = 0;  // channels: 1 grey, 2 grey+alpha, 3 RGB, 4 RGBA
  // width * height * channels; resize(n) leaves new bytes unwritten (DefaultInitAllocator),
  // the constructor below zeroes them.
  std::vector<uint8_t, DefaultInitAllocator<uint8_t>> data;

  Raster8() = default;
  Raster8(int w, int h, int c) : width(w), height(h), channels(c), data(size_t(w) * h * c, 0) {}
  bool has_alpha() const { return channels == 2 || channels == 4; }
  bool empty() const { return width <= 0 || height <= 0; }
  uint8_t& at(int x, int y, int c) { return data[(size_t(y) * width + x) * channels + c]; }
  uint8_t at(int x, int y, int c) const { return data[(size_t(y) * width + x) * channels + c]; }
};

}  // namespace sdvi
