// Object-mode domain boundary: mask contours (outer and holes) as boundary feature curves.
#include "contours.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "sdvi/bspline.h"

namespace sdvi {

StatusOr<std::vector<FeatureCurve>> DomainBoundaryCurves(const cv::Mat& domain,
                                                         const FeatureOptions& options) {
  if (domain.empty() || domain.type() != CV_8U)
    return Status(StatusCode::kInvalidArgument, "DomainBoundaryCurves: domain must be a non-empty 8-bit mask");
  // Remove one-pixel spurs, bridges and pin holes: their contours retrace themselves.
  cv::Mat clean = (domain != 0);
  cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3));
  cv::morphologyEx(clean, clean, cv::MORPH_OPEN, kernel);
  cv::morphologyEx(clean, clean, cv::MORPH_CLOSE, kernel);
  // Nothing may touch the frame's outermost pixel ring, or the contour would run along
  // the image border outside [0, w] x [0, h] after the half-pixel push.
  std::vector<std::vector<cv::Point>> contours;
  std::vector<cv::Vec4i> hierarchy;
  cv::findContours(clean, contours, hierarchy, cv::RETR_CCOMP, cv::CHAIN_APPROX_NONE);

  // Biggest first: outer contours before the holes they contain.
  std::vector<size_t> order(contours.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::vector<double> area(contours.size());
  for (size_t i = 0; i < contours.size(); ++i) area[i] = std::fabs(cv::contourArea(contours[i]));
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return area[a] > area[b]; });

  BSplineFitOptions fit;
  fit.tolerance = std::min(options.fit_tolerance, 0.5);
  fit.max_spacing = options.max_spacing;
  const double w = domain.cols, h = domain.rows;
  std::vector<FeatureCurve> curves;
  for (size_t idx : order) {
    const auto& c = contours[idx];
    if (area[idx] < std::max(1.0, options.min_domain_area) || c.size() < 8) continue;
    const int m = int(c.size());
    // Outward (away from the domain) side of the contour by majority vote of the mask.
    int votes = 0;
    std::vector<Point2> normal(m);
    for (int i = 0; i < m; ++i) {
      const cv::Point& a = c[(i - 2 + m) % m];
      const cv::Point& b = c[(i + 2) % m];
      double tx = b.x - a.x, ty = b.y - a.y, len = std::hypot(tx, ty);
      if (len < 1e-9) continue;
      normal[i] = {ty / len, -tx / len};
      int px = int(std::lround(c[i].x + 1.2 * normal[i].x)), py = int(std::lround(c[i].y + 1.2 * normal[i].y));
      bool outside = px < 0 || py < 0 || px >= domain.cols || py >= domain.rows || !clean.at<uint8_t>(py, px);
      votes += outside ? 1 : -1;
    }
    const double sign = votes >= 0 ? 1.0 : -1.0;
    std::vector<Point2> samples;
    samples.reserve(m);
    for (int i = 0; i < m; ++i) {
      double x = c[i].x + 0.5 + 0.5 * sign * normal[i].x;
      double y = c[i].y + 0.5 + 0.5 * sign * normal[i].y;
      samples.push_back({std::clamp(x, 0.0, w), std::clamp(y, 0.0, h)});
    }
    std::vector<uint32_t> corners = FindChainCorners(samples, true, options.corner_angle_deg, 3);
    FeatureCurve curve = FitChain(samples, true, corners, fit);
    for (Point2& p : curve.points) {
      p.x = std::clamp(p.x, 0.0, w);
      p.y = std::clamp(p.y, 0.0, h);
    }
    curve.boundary = true;
    curve.sharpness = 1.0f;
    if (curve.points.size() >= 3) curves.push_back(std::move(curve));
  }
  if (curves.empty())
    return Status(StatusCode::kEmptyInput, "object mask: no domain region of at least " +
                                               std::to_string(options.min_domain_area) + " px^2");
  return curves;
}

}  // namespace sdvi
