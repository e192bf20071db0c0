// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target over decode -> compress -> decode: any .sdvi file that decodes
// (DecodeImage, raw or Draco) either compresses (EncodeImage with a Draco payload, at the
// default and at a coarse quantization) and decodes again to the same topology, or is
// refused with a code. (The largest quantization costs 0.4 GB and seconds a run: the
// codec tests cover it.) Catches what `sdvi compress` met: Draco crashing or running away
// on values a real image does not have.
#include <cstdint>
#include <cstdlib>
#include <span>

#include "sdvi/codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  sdvi::ReadOptions options;
  options.max_file_bytes = 1 << 22;
  options.max_vertices = 1 << 16;
  options.max_triangles = 1 << 17;
  sdvi::ReadOptions verified = options;  // what the writer made has a correct checksum
  options.verify_checksums = false;       // mutated inputs reach the checks behind it
  auto image = sdvi::DecodeImage(std::span<const uint8_t>(data, size), "fuzz-input", options);
  if (!image.ok()) {
    if (image.status().message().empty()) std::abort();
    return 0;
  }
  for (int bits : {0, 6}) {
    sdvi::CompressOptions compress;
    compress.position_bits = compress.color_bits = bits;
    compress.speed = size % 11;
    auto bytes = sdvi::EncodeImage(*image, &compress, "fuzz-input");
    if (!bytes.ok()) {
      // A decoded image is valid: only Draco itself may fail to encode it, the image has no
      // mesh to compress (a container may hold none), or explicit position bits (6) fold a
      // triangle, which EncodeImage refuses rather than write a file its reader refuses.
      const sdvi::StatusCode code = bytes.status().code();
      if (code != sdvi::StatusCode::kEncodeFailed &&
          !(code == sdvi::StatusCode::kEmptyInput && (image->vertices.empty() || image->triangles.empty())) &&
          !(code == sdvi::StatusCode::kFoldedTriangle && bits != 0))
        std::abort();
      continue;
    }
    auto again = sdvi::DecodeImage(*bytes, "fuzz-compressed", verified);
    if (!again.ok()) std::abort();
    if (again->vertices.size() != image->vertices.size() ||
        again->triangles.size() != image->triangles.size() ||
        again->crease_edges.size() != image->crease_edges.size() ||
        again->corners.size() != image->corners.size() || again->width != image->width)
      std::abort();
  }
  return 0;
}
