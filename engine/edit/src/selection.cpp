// SPDX-License-Identifier: GPL-3.0-or-later
// Selections: which vertices an operation touches (rules in sdvi/edit.h).
#include <algorithm>
#include <cmath>
#include <string>

#include "edit_internal.h"
#include "sdvi/edit.h"

namespace sdvi {
namespace {

using edit_internal::Bad;

// Even-odd rule, a horizontal ray to the right.
bool InsidePolygon(const std::vector<Point2>& poly, double x, double y) {
  bool inside = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Point2 a = poly[i], b = poly[j];
    if ((a.y > y) != (b.y > y)) {
      const double cx = a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y);
      if (x < cx) inside = !inside;
    }
  }
  return inside;
}

}  // namespace

StatusOr<std::vector<uint32_t>> ResolveSelection(const Image& image, const Selection& selection) {
  const size_t n = image.vertices.size();
  std::vector<uint32_t> out;
  switch (selection.kind) {
    case Selection::Kind::kAll:
      out.resize(n);
      for (size_t i = 0; i < n; ++i) out[i] = uint32_t(i);
      return out;
    case Selection::Kind::kVertices:
      for (uint32_t v : selection.vertices)
        if (v >= n)
          return Bad("vertex " + std::to_string(v) + " does not exist (the image has " + std::to_string(n) +
                     " vertices)");
      out = selection.vertices;
      break;
    case Selection::Kind::kPolyline:
      if (selection.id >= image.polylines.size())
        return Bad("polyline " + std::to_string(selection.id) + " does not exist (the image has " +
                   std::to_string(image.polylines.size()) + " polylines)");
      out = image.polylines[selection.id].vertices;
      break;
    case Selection::Kind::kPair: {
      if (selection.id >= image.pairs.size())
        return Bad("pair " + std::to_string(selection.id) + " does not exist (the image has " +
                   std::to_string(image.pairs.size()) + " pairs)");
      const FeaturePair& pair = image.pairs[selection.id];
      out = image.polylines[pair.first].vertices;
      const auto& second = image.polylines[pair.second].vertices;
      out.insert(out.end(), second.begin(), second.end());
      break;
    }
    case Selection::Kind::kRegion:
      if (selection.region.size() < 3)
        return Bad("a region needs at least 3 points, got " + std::to_string(selection.region.size()));
      for (const Point2& p : selection.region)
        if (!std::isfinite(p.x) || !std::isfinite(p.y)) return Bad("a region point is not finite");
      for (size_t i = 0; i < n; ++i)
        if (InsidePolygon(selection.region, image.vertices[i].x, image.vertices[i].y)) out.push_back(uint32_t(i));
      return out;
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace sdvi
