// SPDX-License-Identifier: GPL-3.0-or-later
// PNG encoding with libpng (spec/RASTER_INPUT.md, "Written PNGs").
#include "png_writer.h"

#include <png.h>

#include <csetjmp>
#include <new>

namespace sdvi::raster_internal {
namespace {

// Where libpng's write callback appends; failed is set instead of letting an exception cross
// libpng's C frames.
struct PngSink {
  std::vector<uint8_t>* bytes;
  bool failed = false;
};

void AppendBytes(png_structp png, png_bytep data, size_t length) {
  auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
  try {
    sink->bytes->insert(sink->bytes->end(), data, data + length);
  } catch (const std::bad_alloc&) {
    sink->failed = true;
  }
  if (sink->failed) png_error(png, "out of memory");  // no C++ object of this frame is live
}

void FlushNothing(png_structp) {}

// libpng's error text, kept for the status (libpng's default handler prints it to stderr).
void KeepError(png_structp png, png_const_charp message) {
  auto* text = static_cast<char*>(png_get_error_ptr(png));
  size_t i = 0;
  for (; message && message[i] && i + 1 < 256; ++i) text[i] = message[i];
  text[i] = '\0';
  png_longjmp(png, 1);
}

void IgnoreWarning(png_structp, png_const_charp) {}

}  // namespace

StatusOr<std::vector<uint8_t>> EncodePngWithLibpng(int width, int height, int channels, int bits, const void* samples,
                                                   int compression_level, const std::string& name) {
  const int colour_type = channels == 1   ? PNG_COLOR_TYPE_GRAY
                          : channels == 2 ? PNG_COLOR_TYPE_GRAY_ALPHA
                          : channels == 3 ? PNG_COLOR_TYPE_RGB
                                          : PNG_COLOR_TYPE_RGBA;
  // Every C++ object is made before the setjmp below: a libpng error jumps back over the
  // frames between, which then hold none.
  std::vector<uint8_t> bytes;
  std::vector<png_bytep> rows;
  try {
    rows.resize(size_t(height));
    bytes.reserve(size_t(width) * height * channels * (bits / 8) / 2 + 1024);
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::kLimitExceeded, name + ": out of memory while encoding the PNG");
  }
  const size_t row_bytes = size_t(width) * channels * (bits / 8);
  for (int y = 0; y < height; ++y)
    rows[size_t(y)] = const_cast<png_bytep>(static_cast<const png_byte*>(samples) + size_t(y) * row_bytes);
  char error[256] = "";
  PngSink sink{&bytes};
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, error, KeepError, IgnoreWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    return Status(StatusCode::kEncodeFailed, name + ": cannot start libpng's PNG writer");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    if (sink.failed) return Status(StatusCode::kLimitExceeded, name + ": out of memory while encoding the PNG");
    return Status(StatusCode::kEncodeFailed, name + ": PNG encoding failed: " + error);
  }
  png_set_write_fn(png, &sink, AppendBytes, FlushNothing);
  png_set_compression_level(png, compression_level);
  png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), bits, colour_type, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  // The sRGB chunk with the gAMA and cHRM values the PNG specification pairs with it.
  png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  if (bits == 16) {
    const uint16_t probe = 1;
    if (*reinterpret_cast<const uint8_t*>(&probe) == 1) png_set_swap(png);  // PNG's samples are big-endian
  }
  png_write_image(png, rows.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return bytes;
}

}  // namespace sdvi::raster_internal
