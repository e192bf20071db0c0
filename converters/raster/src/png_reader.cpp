// SPDX-License-Identifier: GPL-3.0-or-later
// PNG decoding with libpng (spec/RASTER_INPUT.md, "PNG input").
#include "png_reader.h"

#include <png.h>

#include <algorithm>
#include <bit>
#include <csetjmp>
#include <cstring>
#include <memory>
#include <new>
#include <utility>

#include "samples.h"

namespace sdvi::raster_internal {
namespace {

// What the callbacks and the decode share while libpng runs: on the heap, since an automatic
// object that changes between setjmp and longjmp has no defined value after the jump.
struct PngReadState {
  const uint8_t* bytes = nullptr;
  size_t size = 0, at = 0;
  bool ended = false;            // a read asked for bytes past the end
  bool reading_pixels = false;   // past the header
  std::vector<uint8_t> samples;  // the image, rows of interleaved 8- or 16-bit samples
  std::vector<png_bytep> rows;
  DecodedImage out;
};

void ReadBytes(png_structp png, png_bytep data, size_t length) {
  auto* state = static_cast<PngReadState*>(png_get_io_ptr(png));
  if (length > state->size - state->at) {
    state->ended = true;
    png_chunk_error(png, "Read error: hit end of file");
  }
  std::memcpy(data, state->bytes + state->at, length);
  state->at += length;
}

}  // namespace

StatusOr<DecodedImage> DecodePngWithLibpng(const std::vector<uint8_t>& bytes, const std::string& name,
                                          uint64_t max_pixels) {
  // Every C++ object is made before the setjmp below: a libpng error jumps back over the
  // frames between, which then hold none.
  auto state = std::make_unique<PngReadState>();
  state->bytes = bytes.data(), state->size = bytes.size();
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    return Status(StatusCode::kDecodeFailed, name + ": cannot start libpng's PNG reader");
  }
  // libpng's default handlers print its words ("libpng error: IDAT: ...") to standard error.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    if (!state->reading_pixels) return Status(StatusCode::kDecodeFailed, name + ": not a PNG sdvi can decode");
    if (state->ended) return Status(StatusCode::kTruncated, name + ": the data ends early");
    return Status(StatusCode::kDecodeFailed, name + ": cannot decode the pixels");
  }
  png_set_read_fn(png, state.get(), ReadBytes);
#ifdef PNG_SKIP_sRGB_CHECK_PROFILE
  // No warning for the widespread sRGB profiles libpng knows to be slightly off (the profile
  // is converted all the same, as OpenImageIO's reader did it, without the warning).
  png_set_option(png, PNG_SKIP_sRGB_CHECK_PROFILE, PNG_OPTION_ON);
#endif
  png_read_info(png, info);
  // 1-, 2- and 4-bit grey to 8 bits, palettes to RGB, tRNS to alpha; 16-bit samples in the
  // machine's byte order.
  png_set_expand(png);
  if (std::endian::native == std::endian::little) png_set_swap(png);
  png_set_interlace_handling(png);  // Adam7 passes combined by png_read_image
  png_read_update_info(png, info);
  const png_uint_32 width = png_get_image_width(png, info), height = png_get_image_height(png, info);
  const int bits = png_get_bit_depth(png, info), channels = png_get_channels(png, info);
  if (uint64_t(width) * height > max_pixels) {
    png_destroy_read_struct(&png, &info, nullptr);
    return Status(StatusCode::kLimitExceeded, name + ": " + std::to_string(width) + "x" + std::to_string(height) +
                                                  " pixels is over the limit of " + std::to_string(max_pixels));
  }
  const size_t row_bytes = png_get_rowbytes(png, info);
  DecodedImage& out = state->out;
  out.format = "png";
  out.file_channels = channels;
  out.bits = bits;
  try {
    if (png_get_valid(png, info, PNG_INFO_iCCP)) {
      png_charp profile_name = nullptr;
      png_bytep profile = nullptr;
      png_uint_32 profile_size = 0;
      int compression = 0;
      if (png_get_iCCP(png, info, &profile_name, &compression, &profile, &profile_size) && profile && profile_size)
        out.icc_profile.assign(profile, profile + profile_size);
    }
    state->samples.resize(row_bytes * height);
    state->rows.resize(height);
  } catch (const std::bad_alloc&) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw;  // the caller's out-of-memory error
  }
  for (png_uint_32 y = 0; y < height; ++y) state->rows[y] = state->samples.data() + size_t(y) * row_bytes;
  state->reading_pixels = true;
  png_read_image(png, state->rows.data());
  png_destroy_read_struct(&png, &info, nullptr);
  // Grey, grey + alpha, RGB, RGBA: the alpha channel is the last of 2 or 4.
  const int colours = channels == 2 || channels == 4 ? channels - 1 : channels;
  out.raster = Raster(int(width), int(height), channels);
  float* d = out.raster.data.data();
  const size_t pixels = size_t(width) * height;
  if (bits == 8) {
    const uint8_t* s = state->samples.data();
    for (size_t p = 0; p < pixels; ++p, s += channels, d += channels) {
      for (int c = 0; c < colours; ++c) d[c] = ColourOf8(s[c]);
      if (colours < channels) d[colours] = AlphaOf8(s[colours]);
    }
  } else {
    const auto* s = reinterpret_cast<const uint16_t*>(state->samples.data());
    for (size_t p = 0; p < pixels; ++p, s += channels, d += channels) {
      for (int c = 0; c < colours; ++c) d[c] = ColourOf16(s[c]);
      if (colours < channels) d[colours] = AlphaOf16(s[colours]);
    }
  }
  return std::move(out);
}

}  // namespace sdvi::raster_internal
