// SPDX-License-Identifier: GPL-3.0-or-later
// Rules on a control mesh that the format's validation (spec/FORMAT.md section 9), the
// subdivision engine and the editor apply: one definition for all.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "sdvi/image.h"
#include "sdvi/status.h"

namespace sdvi {

// Two triangles with the same vertex set (in any order or orientation): the later one's
// index and the earlier one's, or nullopt when every triangle is distinct.
std::optional<std::pair<uint32_t, uint32_t>> FindDuplicateTriangle(std::span<const Triangle> triangles);

// Values a real image has (spec/FORMAT.md section 9, checks 19-21); ValidateImage
// refuses anything else, so every reader and writer refuses it, and the editor refuses an
// edit that would leave it.
// Width and height: 1 .. kMaxImageSide pixels (kLimitExceeded).
inline constexpr uint32_t kMaxImageSide = 1u << 18;  // 262144 pixels
// Control vertices lie within one image size of the image: with S = max(width, height),
// x in [-S, width + S] and y in [-S, height + S] (kValueOutOfRange). The limit surface
// interpolates the boundary, so control vertices of a fitted image stay near it.
// Colours (0..255 scale) may overshoot, as least-squares control colours do near sharp
// edges, but by at most kColorMargin on either side (kValueOutOfRange).
inline constexpr float kColorMargin = 1024.0f;
inline constexpr float kMinColor = -kColorMargin, kMaxColor = 255.0f + kColorMargin;

// The size and value checks above (not NaN: a NaN fails every range): ok, or the first
// breach, naming source and the vertex.
Status CheckImageValues(const Image& image, const std::string& source);

}  // namespace sdvi
