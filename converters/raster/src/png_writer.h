// SPDX-License-Identifier: GPL-3.0-or-later
// Private to sdvi_raster_io: PNG encoding with libpng (spec/RASTER_INPUT.md, "Written PNGs").
// It lives outside the OpenImageIO module, so that a command which only writes PNGs (render,
// sample) never loads OpenImageIO and the libraries it needs.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sdvi/status.h"

namespace sdvi::raster_internal {

// The PNG of width x height pixels of channels (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA)
// interleaved samples of bits (8, or 16 in the machine's byte order), straight alpha, tagged
// sRGB, rows filtered Up and deflated as runs. Errors: kEncodeFailed naming name.
StatusOr<std::vector<uint8_t>> EncodePngWithLibpng(int width, int height, int channels, int bits, const void* samples,
                                                   const std::string& name);

}  // namespace sdvi::raster_internal
