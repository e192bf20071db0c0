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
#include <thread>
#include <vector>

namespace sdvi::fit_internal {

// Calls body(chunk, begin, end) for chunk = 0 .. ceil(count / chunk_size) - 1, covering
// [0, count) in pieces of chunk_size items, on up to `threads` threads (chunks taken in
// turn from a shared counter).
template <typename Body>
void ForEachChunk(size_t count, size_t chunk_size, int threads, Body&& body) {
  if (count == 0) return;
  chunk_size = std::max<size_t>(1, chunk_size);
  const size_t chunks = (count + chunk_size - 1) / chunk_size;
  const size_t workers = std::min<size_t>(std::max(1, threads), chunks);
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t k = next++; k < chunks; k = next++) {
      body(k, k * chunk_size, std::min(count, (k + 1) * chunk_size));
    }
  };
  if (workers <= 1) {
    work();
    return;
  }
  std::vector<std::thread> pool;
  pool.reserve(workers - 1);
  for (size_t w = 1; w < workers; ++w) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
}

// The number of chunks ForEachChunk makes.
inline size_t ChunkCount(size_t count, size_t chunk_size) {
  chunk_size = std::max<size_t>(1, chunk_size);
  return (count + chunk_size - 1) / chunk_size;
}

}  // namespace sdvi::fit_internal

#endif  // SDVI_FIT_PARALLEL_H_
