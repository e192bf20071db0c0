// SPDX-License-Identifier: GPL-3.0-or-later
// Private to the raster module: the raster's scale of a decoded integer sample (colours
// 0..255, alpha 0..1), one rule for every decoder (spec/RASTER_INPUT.md).
#pragma once

#include <cstdint>

namespace sdvi::raster_internal {

inline float ColourOf8(uint8_t s) { return float(s); }
inline float AlphaOf8(uint8_t s) { return float(s * (1.0 / 255)); }
inline float ColourOf16(uint16_t s) { return float(s * (255.0 / 65535.0)); }
inline float AlphaOf16(uint16_t s) { return float(s * (1.0 / 65535)); }

}  // namespace sdvi::raster_internal
