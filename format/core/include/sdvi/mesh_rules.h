// SPDX-License-Identifier: GPL-3.0-or-later
// Rules on a control mesh's triangles that the format's validation (spec/FORMAT.md
// section 9) and the subdivision engine both apply: one definition for both.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "sdvi/image.h"

namespace sdvi {

// Two triangles with the same vertex set (in any order or orientation): the later one's
// index and the earlier one's, or nullopt when every triangle is distinct.
std::optional<std::pair<uint32_t, uint32_t>> FindDuplicateTriangle(std::span<const Triangle> triangles);

}  // namespace sdvi
