// SPDX-License-Identifier: GPL-3.0-or-later
// Raster image files: PNG, JPEG, TIFF, BMP, GIF, WebP, PNM, TGA, OpenEXR and Radiance HDR in;
// PNG (8/16-bit, sRGB-tagged) out. PNGs are read and written with libpng, the other formats
// read with OpenImageIO. The raster module owns this header and may add declarations.
//
// What a loaded raster is (spec/RASTER_INPUT.md has the details and the reasons):
//   - upright: the EXIF/TIFF orientation tag is applied (a camera JPEG tagged "rotate 90"
//     comes out the way a viewer shows it);
//   - sRGB: an embedded ICC profile is converted to sRGB with Little CMS (the profile's own
//     rendering intent; out-of-gamut colours clipped); a profile that cannot be used is
//     reported in RasterSource::warnings and the samples are taken as sRGB;
//   - the file's channels: grey 1, grey+alpha 2, RGB 3, RGBA 4 (palette images expand to
//     RGB(A); a GIF gets alpha only when some pixel is transparent);
//   - colours on the 8-bit sRGB scale (16-bit samples scaled to 0..255), alpha 0..1 straight
//     (not premultiplied);
//   - float images (OpenEXR, Radiance HDR, float TIFF) are scene-linear: colours are
//     un-premultiplied, clipped to 0..1 and encoded with the sRGB transfer function (linear
//     1.0 -> 255). No tone mapping: exposure 1, values above 1 clip to white.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sdvi/raster.h"
#include "sdvi/status.h"

namespace sdvi {

// What LoadRaster / DecodeRaster found and did, for reports and warnings.
struct RasterSource {
  std::string format;         // the decoder's name: "png", "jpeg", "openexr", "gif", ...
  int file_channels = 0;      // channels stored in the file
  int bits = 0;               // bits per stored sample (8, 16, 32 for float; 16 for half)
  bool linear = false;        // float, scene-linear samples encoded to sRGB
  int orientation = 1;        // EXIF/TIFF orientation tag (1..8) that was applied
  std::string icc_profile;    // description of the embedded ICC profile ("" = none)
  bool icc_converted = false; // the profile was converted to sRGB
  std::vector<std::string> warnings;  // things the user should know ("profile ignored: ...")
};

// Loads an image file (see the header comment for what the raster holds). Errors name the
// file: kNotFound, kIoError, kEmptyInput, kDecodeFailed (not an image, corrupt),
// kUnsupportedFormat (channel layout), kLimitExceeded (over 2^28 pixels, checked on the
// header before decoding). source, when given, receives what was found.
StatusOr<Raster> LoadRaster(const std::string& path, RasterSource* source = nullptr);

// Opens now the raster decoders that decoding the files at paths will need: the OpenImageIO
// module and the libraries it loads (spec/RASTER_INPUT.md "Loading"), otherwise opened on
// the first decode of a file that is not a PNG libpng reads. Nothing is opened when every
// path is such a PNG (or cannot be read: its decode reports that); standard input ("-")
// may hold anything. A program that limits its own address space (`sdvi --max-memory`)
// calls it before setting the limit: mapping those libraries needs address space of its
// own, and one of them (log4cplus) hangs in its start-up when a thread it starts is
// refused. Opens once per process; the error is the one a decode would return
// (kDecodeFailed).
Status OpenRasterCodecs(const std::vector<std::string>& paths);

// The same for bytes already in memory (stdin); name is used in messages and, when it has
// an extension, as the decoder's hint.
StatusOr<Raster> DecodeRaster(const std::vector<uint8_t>& bytes, const std::string& name,
                              RasterSource* source = nullptr);

// Sizes DecodeRaster checks on the header, before anything is decoded (kLimitExceeded).
struct RasterLimits {
  uint64_t max_pixels = uint64_t{1} << 28;  // 16384 x 16384
};
// DecodeRaster with explicit limits. Data that ends early or is damaged (the decoder
// reports an error) is an error (kTruncated / kDecodeFailed with the decoder's words),
// never a partial image; running out of memory is kLimitExceeded.
StatusOr<Raster> DecodeRaster(const std::vector<uint8_t>& bytes, const std::string& name,
                              const RasterLimits& limits, RasterSource* source = nullptr);

// Encodes a PNG (bits 8 or 16) with the raster's channels (grey, grey+alpha, RGB, RGBA),
// colours clamped to 0..255 and rounded, alpha to 0..1; tagged sRGB (sRGB chunk, with the
// gAMA and cHRM chunks the PNG specification pairs with it), rows filtered Up and deflated
// as runs (fast, and small for renders; recompress with a PNG optimiser for the smallest
// file). Deterministic bytes.
StatusOr<std::vector<uint8_t>> EncodePng(const Raster& raster, int bits = 8, const std::string& name = "PNG");

// An 8-bit PNG of samples already quantised (the 8-bit render, sdvi::Render8): the same
// chunks as EncodePng; a Raster8 holding EncodePng's quantisation of a Raster encodes to
// the same bytes.
StatusOr<std::vector<uint8_t>> EncodePng(const Raster8& raster, const std::string& name = "PNG");

// EncodePng written to path atomically.
Status SaveRasterPng(const std::string& path, const Raster& raster, int bits = 8);
Status SaveRasterPng(const std::string& path, const Raster8& raster);

// The raster with the channels it needs for an output: alpha dropped when every pixel is
// fully covered (alpha == 1), RGB collapsed to grey when every pixel has R == G == B.
// A render of an RGB image over its whole domain comes back RGB; of a grey image, grey.
Raster WithNeededChannels(const Raster& raster);
// The same for 8-bit samples: alpha dropped when every alpha is 255, grey when every
// pixel's R, G, B bytes are equal (the PNG holds the same pixels either way).
Raster8 WithNeededChannels(const Raster8& raster);

}  // namespace sdvi
