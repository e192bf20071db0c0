// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target over DecodeDracoPayload alone (the compressed payload of spec/FORMAT.md
// section 8: header, Draco mesh, tag stream). Never crash; a payload that decodes gives
// an image that passes ValidateImage or is refused with a code, never garbage.
#include <cstdint>
#include <cstdlib>
#include <span>

#include "sdvi/codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  sdvi::Image image;
  image.width = image.height = 64;
  const sdvi::Status status =
      sdvi::DecodeDracoPayload(std::span<const uint8_t>(data, size), "fuzz-payload", &image, 1 << 20,
                               /*verify_checksum=*/false);  // reach the checks behind it
  if (!status.ok()) {
    if (status.message().empty()) std::abort();
    if (!image.vertices.empty()) std::abort();  // on error the image is unchanged
    return 0;
  }
  // Every index the payload produced is in range (DecodeImage's ValidateImage relies on it).
  const size_t n = image.vertices.size();
  for (const sdvi::Triangle& t : image.triangles)
    for (uint32_t v : t.v)
      if (v >= n) std::abort();
  for (const sdvi::Edge& e : image.crease_edges)
    if (e.a >= e.b || e.b >= n) std::abort();
  for (uint32_t c : image.corners)
    if (c >= n) std::abort();
  return 0;
}
