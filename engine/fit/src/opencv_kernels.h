// SPDX-License-Identifier: GPL-3.0-or-later
// The same bits on every machine from OpenCV's float filters (spec/METHOD.md section 6,
// "Deterministic"). OpenCV chooses its SIMD kernels at run time from the CPU (its baseline,
// or AVX, AVX2 and FMA where the CPU has them), and GaussianBlur and Sobel on floats round
// differently in each, so a vectorized file would depend on the CPU that made it. The fit
// turns that choice off for the process, once, before its first filter: the baseline kernels
// are the same on every x86-64 CPU.
#ifndef SDVI_FIT_OPENCV_KERNELS_H_
#define SDVI_FIT_OPENCV_KERNELS_H_

#include <mutex>

#include <opencv2/core.hpp>

namespace sdvi::fit_internal {

inline void UseOpenCvBaselineKernels() {
  static std::once_flag once;
  std::call_once(once, [] { cv::setUseOptimized(false); });
}

}  // namespace sdvi::fit_internal

#endif  // SDVI_FIT_OPENCV_KERNELS_H_
