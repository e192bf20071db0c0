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
#include <vector>

#include "sdvi/default_init_allocator.h"

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
