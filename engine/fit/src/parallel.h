// SPDX-License-Identifier: GPL-3.0-or-later
// Fixed chunking over worker threads for the vectorizer's per-pixel and per-triangle loops:
// the work is cut into chunks whose bounds depend only on the count (never on the thread
// count), so per-item results, and per-chunk partial sums added in chunk order, are the
// same for any number of threads.
#ifndef SDVI_FIT_PARALLEL_H_
#define SDVI_FIT_PARALLEL_H_

#include <algorithm>
#include <atomic>
#include <cstddef>

#include "sdvi/parallel.h"

namespace sdvi::fit_internal {

// Calls body(worker, chunk, begin, end) for chunk = 0 .. ceil(count / chunk_size) - 1,
// covering [0, count) in pieces of chunk_size items, on up to `threads` threads (chunks
// taken in turn from a shared counter; sdvi::RunTasks); worker (0 .. threads - 1) names the
// thread, for per-thread scratch. An exception thrown by body (std::bad_alloc,
// cv::Exception) stops the hand-out of chunks and is thrown again on the calling thread
// after the join.
template <typename Body>
void ForEachChunkOnWorkers(size_t count, size_t chunk_size, int threads, Body&& body) {
  if (count == 0) return;
  chunk_size = std::max<size_t>(1, chunk_size);
  const size_t chunks = (count + chunk_size - 1) / chunk_size;
  const size_t workers = std::min<size_t>(std::max(1, threads), chunks);
  if (workers <= 1) {
    for (size_t k = 0; k < chunks; ++k) body(size_t{0}, k, k * chunk_size, std::min(count, (k + 1) * chunk_size));
    return;
  }
  std::atomic<size_t> next{0};
  RunTasks(int(workers), [&](int task) {
    const size_t worker = size_t(task);
    try {
      for (size_t k = next++; k < chunks; k = next++) {
        body(worker, k, k * chunk_size, std::min(count, (k + 1) * chunk_size));
      }
    } catch (...) {
      next = chunks;
      throw;
    }
  });
}

// Calls body(chunk, begin, end) as ForEachChunkOnWorkers does.
template <typename Body>
void ForEachChunk(size_t count, size_t chunk_size, int threads, Body&& body) {
  ForEachChunkOnWorkers(count, chunk_size, threads,
                        [&](size_t, size_t chunk, size_t begin, size_t end) { body(chunk, begin, end); });
}

// The number of chunks ForEachChunk makes.
inline size_t ChunkCount(size_t count, size_t chunk_size) {
  chunk_size = std::max<size_t>(1, chunk_size);
  return (count + chunk_size - 1) / chunk_size;
}

}  // namespace sdvi::fit_internal

#endif  // SDVI_FIT_PARALLEL_H_
