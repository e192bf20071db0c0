// SPDX-License-Identifier: GPL-3.0-or-later
// Object-mode domain: the mask's outer contours and holes as boundary feature curves.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "sdvi/features.h"
#include "sdvi/status.h"

namespace sdvi {

// domain: CV_8U, non-zero = inside. Returns one closed boundary curve (boundary = true,
// sharpness 1) per outer contour and hole whose area is at least
// options.min_domain_area, fitted as B-splines through the pixel-boundary contour (the
// pixel centres of the rim moved 0.5 px outwards, smoothed [1 2 1]/4, tolerance
// min(fit_tolerance, 1 px); where that fit would come within 0.3 px of itself, the raw
// contour at 0.5 px), with corners where the contour kinks.
// kEmptyInput when nothing of the domain is left.
StatusOr<std::vector<FeatureCurve>> DomainBoundaryCurves(const cv::Mat& domain,
                                                         const FeatureOptions& options);

// Corner candidates of a sampled chain (about 1 px apart): indices where the turning
// angle over `window` samples on each side exceeds angle_deg and is a local maximum.
// Ends of open chains are never returned (they are corners anyway).
std::vector<uint32_t> FindChainCorners(const std::vector<Point2>& samples, bool closed,
                                       double angle_deg, int window);

}  // namespace sdvi
