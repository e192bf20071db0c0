// SPDX-License-Identifier: GPL-3.0-or-later
// Private to sdvi_raster_io: PNG decoding with libpng (spec/RASTER_INPUT.md, "PNG input"),
// outside the OpenImageIO module, so that reading a PNG does not load OpenImageIO.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "oiio_module.h"
#include "sdvi/status.h"

namespace sdvi::raster_internal {

inline uint32_t BigEndian32(const uint8_t* p) {
  return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | p[3];
}

// Whether the first 16 bytes of a file are the PNG signature and an IHDR chunk's length and type.
inline bool StartsAsPng(const uint8_t* head) {
  static const uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
  return std::equal(kSignature, kSignature + 8, head) && std::memcmp(head + 12, "IHDR", 4) == 0;
}

// Whether a file is a PNG that DecodePngWithLibpng reads as OpenImageIO's PNG reader would:
// the signature and an IHDR first, and no eXIf chunk before IEND (an EXIF orientation is
// OpenImageIO's to read and apply). read(offset, n, out) copies n bytes at offset into out,
// false past the end; the chunks' headers alone are read.
template <typename Read>
bool DecodesWithLibpng(Read&& read) {
  uint8_t head[16];
  if (!read(0, 16, head) || !StartsAsPng(head)) return false;
  // The chunks (length, type, data, CRC), as far as the file holds them; a file of more than
  // a million chunks (a real PNG has tens to thousands) goes to OpenImageIO unread.
  uint64_t at = 8;
  for (int chunks = 0; read(at, 8, head); ++chunks) {
    const uint64_t length = BigEndian32(head);
    if (std::memcmp(head + 4, "eXIf", 4) == 0 || chunks == (1 << 20)) return false;
    if (std::memcmp(head + 4, "IEND", 4) == 0) break;
    at += 12 + length;
  }
  return true;
}

// The same for bytes in memory (at least 33: a signature and a whole IHDR).
inline bool DecodesWithLibpng(const std::vector<uint8_t>& bytes) {
  return bytes.size() >= 33 && DecodesWithLibpng([&](uint64_t at, size_t n, uint8_t* out) {
           if (at > bytes.size() || n > bytes.size() - at) return false;
           std::memcpy(out, bytes.data() + at, n);
           return true;
         });
}

// The PNG's pixels as OpenImageIO's PNG reader gives them: palettes, grey below 8 bits and
// tRNS expanded (to 8-bit samples, alpha), 16-bit samples kept, no gamma applied, alpha
// straight; its ICC profile's bytes. Errors name name: kLimitExceeded (over max_pixels,
// from the header), kTruncated (the data ends early), kDecodeFailed. libpng's own words go
// to standard error, which the caller captures (raster_io.cpp, CapturedStderr).
StatusOr<DecodedImage> DecodePngWithLibpng(const std::vector<uint8_t>& bytes, const std::string& name,
                                          uint64_t max_pixels);

}  // namespace sdvi::raster_internal
