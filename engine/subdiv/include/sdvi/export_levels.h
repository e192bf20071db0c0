// SPDX-License-Identifier: GPL-3.0-or-later
// What the exporters (glTF, PDF, SVG) share: the input check and the subdivision level they
// use when none is given (fine triangles small enough to look smooth when the file is
// magnified, bounded in number).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "sdvi/image.h"
#include "sdvi/status.h"

namespace sdvi {

// kEmptyInput when the image has no triangles, kNonFinite naming the first control vertex
// with a NaN or infinite value; messages start with `what` ("PDF export").
inline Status CheckExportInput(const Image& image, const std::string& what) {
  if (image.triangles.empty() || image.vertices.empty()) {
    return Status(StatusCode::kEmptyInput, what + ": the image has no triangles");
  }
  for (size_t i = 0; i < image.vertices.size(); ++i) {
    const Vertex& v = image.vertices[i];
    for (float value : {v.x, v.y, v.r, v.g, v.b}) {
      if (!std::isfinite(value)) {
        return Status(StatusCode::kNonFinite, what + ": control vertex " + std::to_string(i) +
                                                  " has a NaN or infinite coordinate or colour");
      }
    }
  }
  return Status::Ok();
}

inline constexpr int kDefaultExportLevelCap = 5;
inline constexpr uint64_t kDefaultExportFineTriangleCap = uint64_t(1) << 21;
inline constexpr double kDefaultExportFineArea = 2.0;  // source pixels^2 per fine triangle

// The level r whose fine triangles average at most ~2 source pixels in area (each level
// divides a triangle's area by 4), capped at 5 and lowered until there are at most ~2M
// fine triangles; 0 for an empty mesh. Triangles with an out-of-range index count as area 0.
inline int DefaultExportLevels(const Image& image) {
  if (image.triangles.empty()) return 0;
  double area = 0;
  for (const Triangle& t : image.triangles) {
    if (t.v[0] >= image.vertices.size() || t.v[1] >= image.vertices.size() ||
        t.v[2] >= image.vertices.size()) {
      continue;
    }
    const Vertex& a = image.vertices[t.v[0]];
    const Vertex& b = image.vertices[t.v[1]];
    const Vertex& c = image.vertices[t.v[2]];
    area += std::abs((double(b.x) - a.x) * (double(c.y) - a.y) -
                     (double(b.y) - a.y) * (double(c.x) - a.x)) / 2;
  }
  const double mean_area = area / double(image.triangles.size());
  int levels = 0;
  while (levels < kDefaultExportLevelCap &&
         mean_area / std::pow(4.0, levels) > kDefaultExportFineArea) {
    ++levels;
  }
  while (levels > 0 &&
         uint64_t(image.triangles.size()) << (2 * levels) > kDefaultExportFineTriangleCap) {
    --levels;
  }
  return levels;
}

}  // namespace sdvi
