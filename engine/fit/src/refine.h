// Interior sample placement for the vectorizer (DESIGN.md 6.4 and 6.6): the initial grid,
// the per-pixel error map and the greedy far-apart selection of badly fitted pixels.
#pragma once

#include <cstdint>
#include <vector>

#include "sdvi/features.h"
#include "sdvi/image.h"
#include "sdvi/raster.h"

namespace sdvi {

// Pixels where no interior sample may go: outside the domain, or within `clearance` px of a
// crease edge of mesh (the pairs' strips and the feature polylines themselves), or of a
// feature curve when mesh is null. One byte per pixel, 1 = blocked.
std::vector<uint8_t> BlockedPixels(const Raster& target, const Raster* mask, const Image* mesh,
                                   const std::vector<FeatureCurve>& curves, double clearance);

// Interior samples on a staggered (hexagonal) grid of the given spacing, at unblocked pixel
// centres only.
std::vector<Point2> GridSamples(int width, int height, double spacing,
                                const std::vector<uint8_t>& blocked);

// Per-pixel squared error sum over R, G, B between the reconstruction (RGBA) and target,
// averaged by a Gaussian of sigma px (sigma <= 0: none); -1 outside the fitting domain.
std::vector<float> ErrorMap(const Raster& reconstruction, const Raster& target, const Raster* mask,
                            double sigma);

// Greedy far-apart selection (DESIGN.md 6.6): visits pixels with error > threshold in order
// of decreasing error (ties: lower pixel index first) and keeps a pixel centre when it is
// farther than spacing from every vertex in `existing` and every pixel kept before; stops
// after max_count. Blocked pixels are skipped.
std::vector<Point2> SelectRefinementSamples(const std::vector<float>& error, int width, int height,
                                            double threshold, double spacing,
                                            const std::vector<Vertex>& existing,
                                            const std::vector<uint8_t>& blocked,
                                            size_t max_count);

}  // namespace sdvi
