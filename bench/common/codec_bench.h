// SPDX-License-Identifier: GPL-3.0-or-later
// What the benchmarks that compare sdvi with image codecs share (bench_codec, bench_rd):
// timing, running an external codec, reading an image through OpenCV, listing a data
// folder and drawing a bytes-or-bits vs PSNR plot. Header-only; never part of the library.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sdvi/raster.h"

namespace sdvi::bench {

using Clock = std::chrono::steady_clock;

inline double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// s as one word of a POSIX shell command.
inline std::string ShellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Runs command with its output discarded; true when it exits 0.
inline bool Run(const std::string& command) {
  return std::system((command + " >/dev/null 2>&1").c_str()) == 0;
}

// cv::Mat (8/16-bit, grey / grey+alpha / BGR / BGRA) -> Raster (0..255, alpha 0..1).
inline Raster FromMat(const cv::Mat& in) {
  cv::Mat m;
  if (in.depth() == CV_16U) in.convertTo(m, CV_8U, 1.0 / 257.0);
  else m = in;
  Raster r(m.cols, m.rows, m.channels());
  for (int y = 0; y < m.rows; ++y) {
    const uint8_t* row = m.ptr<uint8_t>(y);
    for (int x = 0; x < m.cols; ++x) {
      const uint8_t* p = row + x * m.channels();
      if (m.channels() <= 2) {
        r.at(x, y, 0) = p[0];
        if (m.channels() == 2) r.at(x, y, 1) = p[1] / 255.f;
      } else {
        r.at(x, y, 0) = p[2];
        r.at(x, y, 1) = p[1];
        r.at(x, y, 2) = p[0];
        if (m.channels() == 4) r.at(x, y, 3) = p[3] / 255.f;
      }
    }
  }
  return r;
}

// The raster images (png, jpg, jpeg, tif, bmp) directly in dir, sorted by name.
inline std::vector<std::filesystem::path> ListImages(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> out;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    const std::string ext = e.path().extension().string();
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".tif" || ext == ".bmp") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// One curve of a rate-distortion plot: (rate, PSNR) points, rate > 0.
struct Series {
  std::string label;
  cv::Scalar color;
  std::vector<std::pair<double, double>> points;
};

// Draws the series as a PNG at path: rate on a log axis (labelled x_label), PSNR in dB.
inline void DrawRdPlot(const std::string& path, const std::string& title, const std::string& x_label,
                       std::vector<Series> series) {
  const int w = 900, h = 600, left = 80, right = 30, top = 50, bottom = 70;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (auto& s : series) {
    std::sort(s.points.begin(), s.points.end());
    for (auto [b, p] : s.points) {
      if (!(b > 0) || !std::isfinite(p)) continue;
      x0 = std::min(x0, std::log10(b));
      x1 = std::max(x1, std::log10(b));
      y0 = std::min(y0, p);
      y1 = std::max(y1, p);
    }
  }
  if (!(x1 > x0)) x1 = x0 + 1;
  y0 = std::floor(y0 / 2) * 2;
  y1 = std::ceil(y1 / 2) * 2;
  if (!(y1 > y0)) y1 = y0 + 2;
  x0 -= 0.05;
  x1 += 0.05;
  auto px = [&](double b) { return left + int((std::log10(b) - x0) / (x1 - x0) * (w - left - right)); };
  auto py = [&](double p) { return h - bottom - int((p - y0) / (y1 - y0) * (h - top - bottom)); };
  const cv::Scalar grid(225, 225, 225), ink(40, 40, 40);
  const double ystep = (y1 - y0) > 30 ? 4 : 2;
  for (double y = y0; y <= y1 + 1e-9; y += ystep) {
    cv::line(img, {left, py(y)}, {w - right, py(y)}, grid);
    cv::putText(img, std::to_string(int(y)), {left - 35, py(y) + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45, ink);
  }
  for (int e = int(std::floor(x0)); e <= int(std::ceil(x1)); ++e) {
    for (int m : {1, 2, 5}) {
      const double b = m * std::pow(10.0, e);
      if (std::log10(b) < x0 || std::log10(b) > x1) continue;
      cv::line(img, {px(b), top}, {px(b), h - bottom}, grid);
      std::ostringstream label;
      if (b >= 1000) label << b / 1000 << "k";
      else label << b;
      cv::putText(img, label.str(), {px(b) - 12, h - bottom + 20}, cv::FONT_HERSHEY_SIMPLEX, 0.45, ink);
    }
  }
  cv::rectangle(img, {left, top}, {w - right, h - bottom}, ink);
  cv::putText(img, title, {left, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.6, ink, 2);
  cv::putText(img, x_label + " (log scale)", {w / 2 - 90, h - 25}, cv::FONT_HERSHEY_SIMPLEX, 0.5, ink);
  cv::putText(img, "PSNR dB", {10, top - 6}, cv::FONT_HERSHEY_SIMPLEX, 0.5, ink);
  int legend_y = h - bottom - 20 - 22 * int(series.size());
  for (const auto& s : series) {
    cv::Point prev(-1, -1);
    for (auto [b, p] : s.points) {
      if (!(b > 0) || !std::isfinite(p)) continue;
      cv::Point q(px(b), py(p));
      if (prev.x >= 0) cv::line(img, prev, q, s.color, 2, cv::LINE_AA);
      cv::circle(img, q, 4, s.color, cv::FILLED, cv::LINE_AA);
      prev = q;
    }
    cv::line(img, {w - right - 200, legend_y - 5}, {w - right - 170, legend_y - 5}, s.color, 2);
    cv::putText(img, s.label, {w - right - 160, legend_y}, cv::FONT_HERSHEY_SIMPLEX, 0.5, ink);
    legend_y += 22;
  }
  cv::imwrite(path, img);
}

}  // namespace sdvi::bench
