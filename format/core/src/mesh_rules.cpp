// SPDX-License-Identifier: GPL-3.0-or-later
#include "sdvi/mesh_rules.h"

#include <algorithm>
#include <array>

namespace sdvi {

std::optional<std::pair<uint32_t, uint32_t>> FindDuplicateTriangle(std::span<const Triangle> triangles) {
  std::vector<std::pair<std::array<uint32_t, 3>, uint32_t>> keys(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t) {
    std::array<uint32_t, 3> k = triangles[t].v;
    std::sort(k.begin(), k.end());
    keys[t] = {k, static_cast<uint32_t>(t)};
  }
  std::sort(keys.begin(), keys.end());
  for (size_t i = 1; i < keys.size(); ++i)
    if (keys[i].first == keys[i - 1].first) return std::make_pair(keys[i].second, keys[i - 1].second);
  return std::nullopt;
}

}  // namespace sdvi
