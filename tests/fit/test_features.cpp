// SPDX-License-Identifier: GPL-3.0-or-later
// Curvilinear feature detection on synthetic images drawn with OpenCV (paper IV step 1-2).
#include <catch2/catch.hpp>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "sdvi/bspline.h"
#include "sdvi/features.h"

namespace {

using sdvi::Distance;
using sdvi::FeatureCurve;
using sdvi::Point2;

// CV_8UC1 or CV_8UC3 (RGB order) or CV_8UC4 -> Raster (alpha scaled to 0..1).
sdvi::Raster ToRaster(const cv::Mat& m) {
  sdvi::Raster r(m.cols, m.rows, m.channels());
  for (int y = 0; y < m.rows; ++y)
    for (int x = 0; x < m.cols; ++x)
      for (int c = 0; c < m.channels(); ++c) {
        float v = m.ptr<uint8_t>(y)[x * m.channels() + c];
        r.at(x, y, c) = (m.channels() == 4 && c == 3) ? v / 255.f : v;
      }
  return r;
}

const FeatureCurve* Longest(const std::vector<FeatureCurve>& curves, bool boundary = false) {
  const FeatureCurve* best = nullptr;
  for (const FeatureCurve& c : curves)
    if (c.boundary == boundary && (!best || c.points.size() > best->points.size())) best = &c;
  return best;
}

}  // namespace

TEST_CASE("a disc gives one closed smooth feature on its rim", "[features]") {
  cv::Mat img(200, 200, CV_8UC1, cv::Scalar(40));
  cv::circle(img, {100, 100}, 60, cv::Scalar(210), -1, cv::LINE_AA);
  auto curves = sdvi::DetectFeatures(ToRaster(img), nullptr, {});
  REQUIRE(curves.ok());
  const FeatureCurve* c = Longest(*curves);
  REQUIRE(c != nullptr);
  REQUIRE(c->closed);
  REQUIRE(c->corners.empty());
  REQUIRE(c->sharpness > 0.5f);
  // The spline runs along the rim (radius 60 around the centre of pixel (100, 100)).
  for (const Point2& p : sdvi::SampleFeatureCurve(*c, 4))
    REQUIRE(std::fabs(Distance(p, {100.5, 100.5}) - 60) < 1.5);
}

TEST_CASE("a square gives a closed feature with corners at its corners", "[features]") {
  cv::Mat img(160, 160, CV_8UC3, cv::Scalar(30, 60, 200));
  cv::rectangle(img, {40, 50}, {119, 109}, cv::Scalar(250, 220, 40), -1);
  auto curves = sdvi::DetectFeatures(ToRaster(img), nullptr, {});
  REQUIRE(curves.ok());
  const FeatureCurve* c = Longest(*curves);
  REQUIRE(c != nullptr);
  REQUIRE(c->closed);
  REQUIRE(c->corners.size() == 4);
  // The colour boundary runs along pixel edges x = 40, 120 and y = 50, 110.
  const Point2 expected[4] = {{40, 50}, {120, 50}, {120, 110}, {40, 110}};
  for (const Point2& e : expected) {
    double best = 1e9;
    for (uint32_t k : c->corners) best = std::min(best, Distance(c->points[k], e));
    REQUIRE(best < 3.0);
  }
}

TEST_CASE("a blurred step gets lower sharpness than a crisp one", "[features]") {
  // Left half: a crisp vertical step; right half: the same step blurred (sigma 3).
  cv::Mat crisp(160, 100, CV_8UC1, cv::Scalar(50));
  crisp.colRange(50, 100).setTo(200);
  cv::Mat blurred = crisp.clone();
  cv::GaussianBlur(blurred, blurred, cv::Size(0, 0), 3.0);
  cv::Mat img(160, 240, CV_8UC1, cv::Scalar(50));
  crisp.copyTo(img(cv::Rect(0, 0, 100, 160)));
  blurred.copyTo(img(cv::Rect(140, 0, 100, 160)));
  img.colRange(100, 140).setTo(125);  // separate the two steps with a flat gap
  auto curves = sdvi::DetectFeatures(ToRaster(img), nullptr, {});
  REQUIRE(curves.ok());
  float crisp_s = -1, blurred_s = -1;
  for (const FeatureCurve& c : *curves) {
    double len = Distance(c.points.front(), c.points.back());
    if (len < 100) continue;  // the two long vertical steps only
    double x = c.points[c.points.size() / 2].x;
    if (std::fabs(x - 50) < 3) crisp_s = c.sharpness;
    if (std::fabs(x - 190) < 3) blurred_s = c.sharpness;
  }
  REQUIRE(crisp_s >= 0);
  REQUIRE(blurred_s >= 0);
  REQUIRE(crisp_s > 0.8f);
  REQUIRE(blurred_s < crisp_s - 0.3f);
}

TEST_CASE("the blur estimate is calibrated to the Gaussian width", "[features]") {
  // Without quantisation each chain keeps its own blur = min(1, sigma_b / blur_scale).
  sdvi::FeatureOptions o;
  o.quantize_sharpness = false;
  o.blur_scale = 4.0;
  for (double sigma : {1.0, 2.0, 3.0}) {
    cv::Mat img(120, 120, CV_8UC1, cv::Scalar(40));
    img.colRange(60, 120).setTo(220);
    cv::GaussianBlur(img, img, cv::Size(0, 0), sigma);
    auto curves = sdvi::DetectFeatures(ToRaster(img), nullptr, o);
    REQUIRE(curves.ok());
    const FeatureCurve* c = Longest(*curves);
    REQUIRE(c != nullptr);
    double estimated = (1.0 - c->sharpness) * o.blur_scale;
    CAPTURE(sigma, estimated);
    REQUIRE(std::fabs(estimated - sigma) < 0.35 * sigma);
  }
}

TEST_CASE("flat images and detect_edges = false give no interior features", "[features]") {
  cv::Mat flat(64, 64, CV_8UC3, cv::Scalar(10, 20, 30));
  auto none = sdvi::DetectFeatures(ToRaster(flat), nullptr, {});
  REQUIRE(none.ok());
  REQUIRE(none->empty());
  cv::Mat disc(64, 64, CV_8UC1, cv::Scalar(0));
  cv::circle(disc, {32, 32}, 20, cv::Scalar(255), -1);
  sdvi::FeatureOptions o;
  o.detect_edges = false;
  auto off = sdvi::DetectFeatures(ToRaster(disc), nullptr, o);
  REQUIRE(off.ok());
  REQUIRE(off->empty());
}

TEST_CASE("a faint step keeps its edge when an explicit threshold is under its gradient", "[features]") {
  // Contrast 3 (8-bit units): its colour range is under the default low threshold (0.4 x 8),
  // so the passes are skipped and nothing is found; with high = 1 (low 0.4) the range does
  // not rule edges out and the step's gradient (about 1.1) is found as an edge.
  cv::Mat step(64, 64, CV_8UC3, cv::Scalar(100, 100, 100));
  cv::rectangle(step, {32, 0}, {63, 63}, cv::Scalar(103, 103, 103), -1);
  auto by_default = sdvi::DetectFeatures(ToRaster(step), nullptr, {});
  REQUIRE(by_default.ok());
  REQUIRE(by_default->empty());
  sdvi::FeatureOptions low;
  low.high_threshold = 1.0;
  auto found = sdvi::DetectFeatures(ToRaster(step), nullptr, low);
  REQUIRE(found.ok());
  const FeatureCurve* c = Longest(*found);
  REQUIRE(c != nullptr);
  for (const Point2& p : c->points) REQUIRE(std::fabs(p.x - 32) < 1.5);
}

TEST_CASE("object mode: alpha gives boundary curves for the outline and the hole", "[features]") {
  cv::Mat img(200, 200, CV_8UC4, cv::Scalar(90, 120, 200, 0));
  cv::circle(img, {100, 100}, 80, cv::Scalar(90, 120, 200, 255), -1);
  cv::circle(img, {100, 100}, 30, cv::Scalar(0, 0, 0, 0), -1);
  auto curves = sdvi::DetectFeatures(ToRaster(img), nullptr, {});
  REQUIRE(curves.ok());
  std::vector<double> radii;
  for (const FeatureCurve& c : *curves) {
    if (!c.boundary) continue;
    REQUIRE(c.closed);
    double mean = 0;
    std::vector<Point2> s = sdvi::SampleFeatureCurve(c, 4);
    for (const Point2& p : s) mean += Distance(p, {100.5, 100.5});
    radii.push_back(mean / s.size());
  }
  REQUIRE(radii.size() == 2);
  std::sort(radii.begin(), radii.end());
  // Pixel-boundary contours: radius 30 hole rim and radius 80 outer rim (+-1 px).
  REQUIRE(std::fabs(radii[0] - 30.5) < 1.5);
  REQUIRE(std::fabs(radii[1] - 80.5) < 1.5);
  // No interior feature along the (transparent) rims.
  for (const FeatureCurve& c : *curves) REQUIRE(c.boundary);
}

TEST_CASE("an explicit mask selects the domain and must match the image size", "[features]") {
  cv::Mat img(100, 120, CV_8UC1, cv::Scalar(128));
  sdvi::Raster mask(120, 100, 1);
  for (int y = 20; y < 80; ++y)
    for (int x = 30; x < 90; ++x) mask.at(x, y, 0) = 1.f;
  auto curves = sdvi::DetectFeatures(ToRaster(img), &mask, {});
  REQUIRE(curves.ok());
  REQUIRE(curves->size() == 1);
  REQUIRE((*curves)[0].boundary);
  REQUIRE((*curves)[0].corners.size() == 4);
  sdvi::Raster wrong(50, 50, 1);
  auto bad = sdvi::DetectFeatures(ToRaster(img), &wrong, {});
  REQUIRE(!bad.ok());
  REQUIRE(bad.status().code() == sdvi::StatusCode::kInvalidArgument);
}

TEST_CASE("bad images and options are rejected with specific codes", "[features]") {
  auto empty = sdvi::DetectFeatures(sdvi::Raster(), nullptr, {});
  REQUIRE(empty.status().code() == sdvi::StatusCode::kEmptyInput);
  sdvi::Raster nan(8, 8, 1);
  nan.data[5] = std::nanf("");
  REQUIRE(sdvi::DetectFeatures(nan, nullptr, {}).status().code() == sdvi::StatusCode::kNonFinite);
  sdvi::FeatureOptions o;
  o.low_ratio = 2;
  REQUIRE(sdvi::DetectFeatures(sdvi::Raster(8, 8, 3), nullptr, o).status().code() ==
          sdvi::StatusCode::kInvalidArgument);
  sdvi::Raster all_transparent(16, 16, 4);
  REQUIRE(sdvi::DetectFeatures(all_transparent, nullptr, {}).status().code() == sdvi::StatusCode::kEmptyInput);
}

TEST_CASE("detection is deterministic", "[features]") {
  cv::Mat img(128, 128, CV_8UC3, cv::Scalar(0, 0, 0));
  cv::circle(img, {50, 60}, 30, cv::Scalar(200, 100, 50), -1, cv::LINE_AA);
  cv::line(img, {0, 100}, {127, 20}, cv::Scalar(20, 220, 90), 3, cv::LINE_AA);
  auto a = sdvi::DetectFeatures(ToRaster(img), nullptr, {});
  auto b = sdvi::DetectFeatures(ToRaster(img), nullptr, {});
  REQUIRE(a.ok());
  REQUIRE(b.ok());
  REQUIRE(a->size() == b->size());
  for (size_t i = 0; i < a->size(); ++i) {
    REQUIRE((*a)[i].points.size() == (*b)[i].points.size());
    for (size_t k = 0; k < (*a)[i].points.size(); ++k) REQUIRE((*a)[i].points[k].x == (*b)[i].points[k].x);
    REQUIRE((*a)[i].sharpness == (*b)[i].sharpness);
  }
}

namespace {

// Many edges over several bands of rows (the per-pixel passes work in bands of 64 rows):
// discs, rings and lines of random colours, a seeded generator.
cv::Mat ManyEdges(int width, int height, int channels) {
  cv::Mat img(height, width, CV_8UC(channels), cv::Scalar::all(90));
  cv::RNG rng(12345);
  for (int k = 0; k < 60; ++k) {
    const cv::Point c(rng.uniform(0, width), rng.uniform(0, height));
    const cv::Scalar colour(rng.uniform(0, 256), rng.uniform(0, 256), rng.uniform(0, 256), 255);
    if (k % 3 == 0)
      cv::circle(img, c, rng.uniform(5, 60), colour, -1, cv::LINE_AA);
    else if (k % 3 == 1)
      cv::circle(img, c, rng.uniform(10, 80), colour, rng.uniform(1, 6), cv::LINE_AA);
    else
      cv::line(img, c, {rng.uniform(0, width), rng.uniform(0, height)}, colour, rng.uniform(1, 5), cv::LINE_AA);
  }
  if (channels == 4) {
    // Object mode: a transparent margin and a hole.
    cv::Mat alpha(height, width, CV_8UC1, cv::Scalar(0));
    cv::rectangle(alpha, {10, 12}, {width - 11, height - 9}, cv::Scalar(255), -1);
    cv::circle(alpha, {width / 3, height / 2}, 25, cv::Scalar(0), -1);
    cv::Mat planes[4];
    cv::split(img, planes);
    planes[3] = alpha;
    cv::merge(planes, 4, img);
  }
  return img;
}

void RequireSameCurves(const std::vector<FeatureCurve>& a, const std::vector<FeatureCurve>& b) {
  REQUIRE(a.size() == b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    REQUIRE(a[i].points.size() == b[i].points.size());
    for (size_t k = 0; k < a[i].points.size(); ++k) {
      REQUIRE(a[i].points[k].x == b[i].points[k].x);
      REQUIRE(a[i].points[k].y == b[i].points[k].y);
    }
    REQUIRE(a[i].closed == b[i].closed);
    REQUIRE(a[i].corners == b[i].corners);
    REQUIRE(a[i].sharpness == b[i].sharpness);
    REQUIRE(a[i].contrast == b[i].contrast);
    REQUIRE(a[i].boundary == b[i].boundary);
  }
}

}  // namespace

TEST_CASE("detection gives the same curves on 1, 2 and 3 threads", "[features]") {
  for (int channels : {1, 3, 4}) {
    for (double sigma : {0.8, 0.0, 2.5}) {
      CAPTURE(channels, sigma);
      const sdvi::Raster image = ToRaster(ManyEdges(331, 277, channels));
      sdvi::FeatureOptions o;
      o.smoothing_sigma = sigma;
      auto one = sdvi::DetectFeatures(image, nullptr, o);
      REQUIRE(one.ok());
      REQUIRE(one->size() > 20);
      for (int threads : {2, 3}) {
        o.threads = threads;
        auto more = sdvi::DetectFeatures(image, nullptr, o);
        REQUIRE(more.ok());
        RequireSameCurves(*one, *more);
      }
    }
  }
}
