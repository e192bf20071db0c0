// SPDX-License-Identifier: GPL-3.0-or-later
// Embedded ICC profiles -> sRGB with Little CMS (private to sdvi_raster_io).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sdvi/raster.h"
#include "sdvi/status.h"

namespace sdvi {

// What ConvertIccToSrgb did.
struct IccConversion {
  std::string description;  // the profile's description tag ("" when it has none)
  bool converted = false;
};

// Converts raster's colours (8-bit sRGB scale floats, 1 or 3 colour channels plus an
// optional alpha, which is left alone) from the colour space of the ICC profile icc to sRGB:
// RGB profiles to the sRGB profile, grey profiles to a grey profile with the sRGB tone
// curve, in 16 bits, with the profile's rendering intent; results clipped to 0..255.
// kDecodeFailed when the profile cannot be parsed, kUnsupportedFormat when its colour space
// does not match the raster's channels (a CMYK profile on RGB samples); the raster is then
// unchanged.
StatusOr<IccConversion> ConvertIccToSrgb(const std::vector<uint8_t>& icc, Raster& raster);

}  // namespace sdvi
