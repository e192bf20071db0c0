// SPDX-License-Identifier: GPL-3.0-or-later
#include "sdvi/mesh_rules.h"

#include <algorithm>
#include <array>
#include <cstdio>

namespace sdvi {
namespace {

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

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

Status CheckImageValues(const Image& image, const std::string& source) {
  if (image.width > kMaxImageSide || image.height > kMaxImageSide)
    return Status(StatusCode::kLimitExceeded,
                  source + ": image size " + std::to_string(image.width) + " x " +
                      std::to_string(image.height) + " exceeds the largest an .sdvi file holds (" +
                      std::to_string(kMaxImageSide) + " x " + std::to_string(kMaxImageSide) + ")");
  const double s = std::max(image.width, image.height);
  const double x_lo = -s, x_hi = image.width + s, y_lo = -s, y_hi = image.height + s;
  for (size_t i = 0; i < image.vertices.size(); ++i) {
    const Vertex& v = image.vertices[i];
    if (!(v.x >= x_lo && v.x <= x_hi && v.y >= y_lo && v.y <= y_hi))
      return Status(StatusCode::kValueOutOfRange,
                    source + ": vertex " + std::to_string(i) + " lies at (" + Num(v.x) + ", " +
                        Num(v.y) + "), more than one image size outside the " +
                        std::to_string(image.width) + " x " + std::to_string(image.height) +
                        " image (allowed: x in [" + Num(x_lo) + ", " + Num(x_hi) + "], y in [" +
                        Num(y_lo) + ", " + Num(y_hi) + "])");
    for (float c : {v.r, v.g, v.b})
      if (!(c >= kMinColor && c <= kMaxColor))
        return Status(StatusCode::kValueOutOfRange,
                      source + ": vertex " + std::to_string(i) + " has colour (" + Num(v.r) + ", " +
                          Num(v.g) + ", " + Num(v.b) + "); components must lie in [" +
                          Num(kMinColor) + ", " + Num(kMaxColor) + "]");
  }
  return Status::Ok();
}

}  // namespace sdvi
