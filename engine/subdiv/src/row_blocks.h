// SPDX-License-Identifier: GPL-3.0-or-later
// Contiguous blocks of rows over threads, for the subdivision's tables and values: each row
// is computed by one thread, so the result does not depend on the number of threads.
#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

#include "sdvi/parallel.h"

namespace sdvi::subdiv_internal {

// The hardware's threads, at most 8 (asked once: the query reads a file on Linux).
inline unsigned HardwareThreads() {
  static const unsigned threads = std::min(8u, std::max(1u, std::thread::hardware_concurrency()));
  return threads;
}

// Threads for num_rows rows of work (one per 16384 rows at most); requested = 0: the hardware's.
inline unsigned ThreadsFor(size_t num_rows, int requested) {
  const unsigned hw = requested > 0 ? static_cast<unsigned>(requested) : HardwareThreads();
  return static_cast<unsigned>(std::clamp<size_t>(num_rows / 16384, 1, hw));
}

// Runs body(begin, end) over contiguous blocks of [0, num_rows), one thread a block
// (ThreadsFor).
template <typename Body>
void ForRowBlocks(size_t num_rows, int requested_threads, const Body& body) {
  const unsigned threads = ThreadsFor(num_rows, requested_threads);
  RunTasks(int(threads), [&body, num_rows, threads](int i) {
    body(num_rows * unsigned(i) / threads, num_rows * unsigned(i + 1) / threads);
  });
}

}  // namespace sdvi::subdiv_internal
