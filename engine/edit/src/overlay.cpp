// SPDX-License-Identifier: GPL-3.0-or-later
// The feature overlay: polylines and their ids over a render, for picking features.
#include <algorithm>
#include <cmath>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "sdvi/edit.h"

namespace sdvi {
namespace {

cv::Mat ToBgr(const Raster& picture) {
  cv::Mat out(picture.height, picture.width, CV_8UC3);
  const bool grey = picture.channels <= 2;
  for (int y = 0; y < picture.height; ++y)
    for (int x = 0; x < picture.width; ++x) {
      // Domain-free pixels (alpha 0) show as mid grey.
      const float alpha = picture.has_alpha() ? picture.at(x, y, picture.channels - 1) : 1.f;
      for (int c = 0; c < 3; ++c) {
        const float v = picture.at(x, y, grey ? 0 : c);
        const float mixed = alpha * v + (1 - alpha) * 128.f;
        out.at<cv::Vec3b>(y, x)[2 - c] = cv::saturate_cast<uint8_t>(std::lround(mixed));
      }
    }
  return out;
}

Raster FromBgr(const cv::Mat& m) {
  Raster out(m.cols, m.rows, 3);
  for (int y = 0; y < m.rows; ++y)
    for (int x = 0; x < m.cols; ++x)
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = m.at<cv::Vec3b>(y, x)[2 - c];
  return out;
}

// Output position of control point v through the viewport, in fixed point (4 fractional
// bits, OpenCV's `shift`) or whole pixels. Pixel (i, j) covers [i, i+1) x [j, j+1), so
// OpenCV's integer pixel centre i sits at i + 0.5: shift by half a pixel.
cv::Point At(const Vertex& v, const Viewport& vp, int one = 16) {
  const double x = (v.x - vp.origin_x) * vp.scale_x - 0.5, y = (v.y - vp.origin_y) * vp.scale_y - 0.5;
  return {int(std::lround(std::clamp(x, -1e6, 1e6) * one)), int(std::lround(std::clamp(y, -1e6, 1e6) * one))};
}

void DrawPolyline(cv::Mat& m, const Image& image, const FeaturePolyline& l, const Viewport& vp,
                  const cv::Scalar& colour) {
  std::vector<cv::Point> pts;
  for (uint32_t v : l.vertices) pts.push_back(At(image.vertices[v], vp));
  cv::polylines(m, pts, l.closed, colour, 1, cv::LINE_AA, 4);
  for (const cv::Point& p : pts) cv::circle(m, p, 2 * 16, colour, cv::FILLED, cv::LINE_AA, 4);
}

// The id at the polyline's middle vertex, white on a dark box.
void Label(cv::Mat& m, const Image& image, const FeaturePolyline& l, const Viewport& vp, const std::string& text,
           const cv::Scalar& colour) {
  if (l.vertices.empty()) return;
  const cv::Point at = At(image.vertices[l.vertices[l.vertices.size() / 2]], vp, 1);
  const double font = 0.4;
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, font, 1, &baseline);
  cv::Point origin(at.x + 3, at.y - 3);
  origin.x = std::clamp(origin.x, 0, std::max(0, m.cols - size.width));
  origin.y = std::clamp(origin.y, size.height, std::max(size.height, m.rows - baseline));
  cv::rectangle(m, origin + cv::Point(-1, baseline), origin + cv::Point(size.width + 1, -size.height - 1),
                cv::Scalar(0, 0, 0), cv::FILLED);
  cv::putText(m, text, origin, cv::FONT_HERSHEY_SIMPLEX, font, colour, 1, cv::LINE_AA);
}

}  // namespace

Raster DrawFeatureOverlay(const Raster& picture, const Image& image, const Viewport& viewport) {
  if (picture.empty()) return Raster();
  cv::Mat m = ToBgr(picture);
  const cv::Scalar red(40, 40, 255), green(60, 220, 60), blue(255, 120, 40), yellow(0, 230, 255);
  for (const FeatureInfo& f : ListFeatures(image)) {
    if (f.kind == FeatureKind::kPair) continue;
    const FeaturePolyline& l = image.polylines[f.id];
    const cv::Scalar colour = f.kind == FeatureKind::kBoundary   ? blue
                              : f.kind == FeatureKind::kPolyline ? yellow
                              : f.sharpness >= 0.5f              ? red
                                                                 : green;
    DrawPolyline(m, image, l, viewport, colour);
  }
  // Labels last, so that no line covers them.
  for (const FeatureInfo& f : ListFeatures(image)) {
    if (f.kind == FeatureKind::kPair)
      Label(m, image, image.polylines[f.first], viewport, std::string("P").append(std::to_string(f.id)),
            f.sharpness >= 0.5f ? red : green);
    else if (f.kind == FeatureKind::kPolyline)
      Label(m, image, image.polylines[f.id], viewport, std::string("L").append(std::to_string(f.id)), yellow);
  }
  return FromBgr(m);
}

}  // namespace sdvi
