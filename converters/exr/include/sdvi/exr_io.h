// SPDX-License-Identifier: GPL-3.0-or-later
// OpenEXR files for compositing: linear-light RGBA (half or float) with an optional
// per-pixel `error` channel. The exr module owns this header.
//
// Conventions (OpenEXR's): colour is linear light (the raster's 8-bit sRGB scale is decoded
// with the sRGB transfer function, 255 -> 1.0) and premultiplied by alpha; A is coverage.
// Grey rasters are written as R = G = B. Channels are named R, G, B, A and `error`; A only
// when the raster has alpha (a render covering its whole output has none: RGB stays RGB).
// A region of a larger render keeps its place: the data window is the region, the display
// window the whole render (what compositors use to line tiles up).
#pragma once

#include <string>
#include <vector>

#include "sdvi/raster.h"
#include "sdvi/status.h"

namespace sdvi {

// sRGB transfer function on the 8-bit scale: v in 0..255 -> linear 0..1 (and back).
double SrgbToLinear(double v255);
double LinearToSrgb(double linear);

struct ExrWriteOptions {
  bool half = false;                // 16-bit half floats instead of 32-bit floats
  const std::vector<float>* error = nullptr;  // optional `error` channel, width*height values
  // Data window origin inside the display window (a --region's x, y in output pixels).
  int data_x = 0, data_y = 0;
  // Display window size (the whole render); 0 = the raster's own size.
  int display_width = 0, display_height = 0;
};

// Writes raster (1-4 channels, colours 0..255 sRGB, alpha 0..1) as a ZIP-compressed EXR
// with data window [data_x, data_x + width) x [data_y, data_y + height),
// atomically. Errors: kEmptyInput, kInvalidArgument (channel count, error size), kIoError,
// kEncodeFailed (OpenEXR refused), each naming the path.
Status SaveExr(const std::string& path, const Raster& raster, const ExrWriteOptions& options = {});

// An EXR file read back: rgba as stored (linear, premultiplied; A = 1 when absent), and the
// `error` channel when the file has one.
struct ExrImage {
  Raster rgba;               // 4 channels
  std::vector<float> error;  // empty when the file has no `error` channel
  int data_x = 0, data_y = 0;                  // data window origin
  int display_width = 0, display_height = 0;   // display window size
  bool has_alpha = false;                      // the file has an A channel
};
// Errors: kNotFound, kDecodeFailed (not an EXR, corrupt), kLimitExceeded (over 2^28 pixels).
// data_x/y and display_width/height: the file's data window origin and display window size.
StatusOr<ExrImage> LoadExr(const std::string& path);

// The `error` channel of a render against a reference of the same size: mean absolute
// difference over R, G, B in 8-bit units (grey counts as R = G = B); 0 where the render or
// the reference has alpha <= 0.5. kInvalidArgument when the sizes differ.
StatusOr<std::vector<float>> ErrorChannel(const Raster& render, const Raster& reference);

}  // namespace sdvi
