// SPDX-License-Identifier: GPL-3.0-or-later
// Progress: phase and step reporting for long work. Prints to stderr only when stderr
// is a terminal and the caller did not ask for quiet; otherwise does nothing.
#pragma once

#include <chrono>
#include <string>

namespace sdvi {

class Progress {
 public:
  // quiet: the user's --quiet; output also stays off when stderr is not a TTY.
  explicit Progress(bool quiet = false);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  bool enabled() const { return enabled_; }
  // Starts a named phase ("features", "triangulate", "fit 3/8"); ends the previous one.
  void Phase(const std::string& name);
  // Updates the current phase's fraction done (0..1), redrawn at most ~10 times a second.
  void Update(double fraction, const std::string& detail = {});
  // Ends the current phase, printing its time.
  void Done();

 private:
  bool enabled_ = false;
  std::string phase_;
  std::chrono::steady_clock::time_point phase_start_, last_draw_;
};

}  // namespace sdvi
