// SPDX-License-Identifier: GPL-3.0-or-later
// Helpers for the format tests: synthetic meshes and byte-level file surgery.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "sdvi/format.h"
#include "sdvi_generated.h"

namespace sdvi::test {

// True when a and b hold the same vertices bit for bit.
inline bool BitEqual(const std::vector<Vertex>& a, const std::vector<Vertex>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vertex)) == 0;
}

// A grid of (n+1) x (n+1) vertices (spacing 4 px), two triangles a cell, every boundary
// edge tagged crease; colours vary with position.
inline Image Grid(uint32_t n) {
  Image image;
  image.width = image.height = 4 * n;
  for (uint32_t y = 0; y <= n; ++y)
    for (uint32_t x = 0; x <= n; ++x)
      image.vertices.push_back({4.f * x, 4.f * y, float(x % 256) + 0.25f, float(y % 256) * 0.5f,
                                float((x * y) % 256) / 3.f});
  auto id = [n](uint32_t x, uint32_t y) { return y * (n + 1) + x; };
  for (uint32_t y = 0; y < n; ++y)
    for (uint32_t x = 0; x < n; ++x) {
      image.triangles.push_back({{id(x, y), id(x + 1, y), id(x + 1, y + 1)}});
      image.triangles.push_back({{id(x, y), id(x + 1, y + 1), id(x, y + 1)}});
    }
  for (uint32_t i = 0; i < n; ++i) {
    image.crease_edges.push_back(Edge::Of(id(i, 0), id(i + 1, 0)));
    image.crease_edges.push_back(Edge::Of(id(i, n), id(i + 1, n)));
    image.crease_edges.push_back(Edge::Of(id(0, i), id(0, i + 1)));
    image.crease_edges.push_back(Edge::Of(id(n, i), id(n, i + 1)));
  }
  std::sort(image.crease_edges.begin(), image.crease_edges.end());
  return image;
}

// Byte offset of the 28-byte header in an encoded file.
inline size_t HeaderOffset(const std::vector<uint8_t>& bytes) {
  return reinterpret_cast<const uint8_t*>(fb::GetImage(bytes.data())->header()) - bytes.data();
}

// Byte offset of the first vertex / triangle element of a raw narrow file.
inline size_t VertexDataOffset(const std::vector<uint8_t>& bytes) {
  return reinterpret_cast<const uint8_t*>(fb::GetImage(bytes.data())->vertices()->Data()) -
         bytes.data();
}
inline size_t TriangleDataOffset(const std::vector<uint8_t>& bytes) {
  return reinterpret_cast<const uint8_t*>(fb::GetImage(bytes.data())->triangles()->Data()) -
         bytes.data();
}

template <typename T>
void Poke(std::vector<uint8_t>& bytes, size_t offset, T value) {
  std::memcpy(bytes.data() + offset, &value, sizeof value);  // little-endian host
}

// Recomputes the header's CRC-32 after the bytes were edited on purpose.
inline void FixCrc(std::vector<uint8_t>& bytes) {
  const size_t crc_pos = HeaderOffset(bytes) + 24;
  Poke<uint32_t>(bytes, crc_pos, 0);
  Poke<uint32_t>(bytes, crc_pos, Crc32(bytes));
}

}  // namespace sdvi::test
