// SPDX-License-Identifier: GPL-3.0-or-later
// Debug pictures of the features and the control mesh (for vectorize --debug-dir).
#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "sdvi/bspline.h"
#include "sdvi/features.h"

namespace sdvi {
namespace {

constexpr int kShift = 4;  // fixed-point bits for sub-pixel drawing
constexpr double kScale = 1 << kShift;

// The image as 8-bit BGR, dimmed so that overlays stand out.
cv::Mat Background(const Raster& image) {
  cv::Mat out(std::max(1, image.height), std::max(1, image.width), CV_8UC3, cv::Scalar(0, 0, 0));
  if (image.empty() || image.channels < 1) return out;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      float r, g, b;
      if (image.channels >= 3) {
        r = image.at(x, y, 0);
        g = image.at(x, y, 1);
        b = image.at(x, y, 2);
      } else {
        r = g = b = image.at(x, y, 0);
      }
      auto dim = [](float v) { return cv::saturate_cast<uint8_t>(0.35f * 255 + 0.65f * std::clamp(v, 0.f, 255.f)); };
      out.at<cv::Vec3b>(y, x) = cv::Vec3b(dim(b), dim(g), dim(r));
    }
  return out;
}

Raster ToRaster(const cv::Mat& bgr) {
  Raster r(bgr.cols, bgr.rows, 3);
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x) {
      const cv::Vec3b& p = bgr.at<cv::Vec3b>(y, x);
      r.at(x, y, 0) = p[2];
      r.at(x, y, 1) = p[1];
      r.at(x, y, 2) = p[0];
    }
  return r;
}

cv::Point Fixed(double x, double y) { return {int(std::lround(x * kScale)), int(std::lround(y * kScale))}; }

void Square(cv::Mat& img, double x, double y, const cv::Scalar& colour) {
  cv::rectangle(img, Fixed(x - 2, y - 2), Fixed(x + 2, y + 2), colour, 1, cv::LINE_AA, kShift);
}

}  // namespace

Raster DrawFeatures(const Raster& image, const std::vector<FeatureCurve>& curves) {
  cv::Mat img = Background(image);
  const cv::Scalar red(0, 0, 255), green(0, 200, 0), blue(255, 80, 0), yellow(0, 230, 255);
  for (const FeatureCurve& c : curves) {
    if (c.points.empty()) continue;
    cv::Scalar colour = c.boundary ? blue : (c.sharpness >= 0.5f ? red : green);
    std::vector<Point2> s = SampleFeatureCurve(c, 8);
    std::vector<cv::Point> pts;
    for (const Point2& p : s) pts.push_back(Fixed(p.x, p.y));
    cv::polylines(img, pts, c.closed, colour, 1, cv::LINE_AA, kShift);
    for (const Point2& p : c.points) cv::circle(img, Fixed(p.x, p.y), int(kScale), colour, -1, cv::LINE_AA, kShift);
    for (uint32_t k : c.corners)
      if (k < c.points.size()) Square(img, c.points[k].x, c.points[k].y, yellow);
    if (!c.closed) {
      Square(img, c.points.front().x, c.points.front().y, yellow);
      Square(img, c.points.back().x, c.points.back().y, yellow);
    }
  }
  return ToRaster(img);
}

Raster DrawControlMesh(const Raster& image, const Image& mesh) {
  cv::Mat img = Background(image);
  const cv::Scalar grey(140, 140, 140), red(0, 0, 255), yellow(0, 230, 255);
  const size_t nv = mesh.vertices.size();
  auto pt = [&](uint32_t i) { return Fixed(mesh.vertices[i].x, mesh.vertices[i].y); };
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      uint32_t a = std::min(t.v[k], t.v[(k + 1) % 3]), b = std::max(t.v[k], t.v[(k + 1) % 3]);
      if (b < nv) cv::line(img, pt(a), pt(b), grey, 1, cv::LINE_AA, kShift);  // same pixels twice
    }
  for (const Edge& e : mesh.crease_edges)
    if (e.a < nv && e.b < nv) cv::line(img, pt(e.a), pt(e.b), red, 1, cv::LINE_AA, kShift);
  for (uint32_t c : mesh.corners)
    if (c < nv) Square(img, mesh.vertices[c].x, mesh.vertices[c].y, yellow);
  return ToRaster(img);
}

}  // namespace sdvi
