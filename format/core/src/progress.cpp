// SPDX-License-Identifier: GPL-3.0-or-later
#include "sdvi/progress.h"

#include <unistd.h>

#include <cstdio>

namespace sdvi {

Progress::Progress(bool quiet) : enabled_(!quiet && ::isatty(STDERR_FILENO)) {}

Progress::~Progress() { Done(); }

void Progress::Phase(const std::string& name) {
  Done();
  phase_ = name;
  phase_start_ = last_draw_ = std::chrono::steady_clock::now();
  if (enabled_) std::fprintf(stderr, "\r\033[K%s ...", phase_.c_str());
}

void Progress::Update(double fraction, const std::string& detail) {
  if (!enabled_ || phase_.empty()) return;
  auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  std::fprintf(stderr, "\r\033[K%s %3d%% %s", phase_.c_str(), static_cast<int>(fraction * 100 + 0.5),
               detail.c_str());
}

void Progress::Done() {
  if (phase_.empty()) return;
  if (enabled_) {
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - phase_start_).count();
    std::fprintf(stderr, "\r\033[K%s done (%.2f s)\n", phase_.c_str(), s);
  }
  phase_.clear();
}

}  // namespace sdvi
