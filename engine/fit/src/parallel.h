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
#include <exception>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace sdvi::fit_internal {

// Calls body(worker, chunk, begin, end) for chunk = 0 .. ceil(count / chunk_size) - 1,
// covering [0, count) in pieces of chunk_size items, on up to `threads` threads (chunks
// taken in turn from a shared counter); worker (0 .. threads - 1) names the thread, for
// per-thread scratch. An exception thrown by body (std::bad_alloc, cv::Exception) stops the
// hand-out of chunks and is thrown again on the calling thread after the join.
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
  std::mutex failed_mutex;
  std::exception_ptr failed;
  auto work = [&](size_t worker) {
    try {
      for (size_t k = next++; k < chunks; k = next++) {
        body(worker, k, k * chunk_size, std::min(count, (k + 1) * chunk_size));
      }
    } catch (...) {
      next = chunks;
      std::lock_guard<std::mutex> lock(failed_mutex);
      if (!failed) failed = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(workers - 1);
  for (size_t w = 1; w < workers; ++w) pool.emplace_back(work, w);
  work(0);
  for (std::thread& t : pool) t.join();
  if (failed) std::rethrow_exception(failed);
}

// Calls body(chunk, begin, end) as ForEachChunkOnWorkers does.
template <typename Body>
void ForEachChunk(size_t count, size_t chunk_size, int threads, Body&& body) {
  ForEachChunkOnWorkers(count, chunk_size, threads,
                        [&](size_t, size_t chunk, size_t begin, size_t end) { body(chunk, begin, end); });
}

// One task on a thread of its own beside the caller's work: Wait() joins it and throws again
// what it threw; a task still running when the object goes (an early return, an exception on
// the caller) is joined, what it threw dropped.
class BackgroundTask {
 public:
  BackgroundTask() = default;
  BackgroundTask(const BackgroundTask&) = delete;
  BackgroundTask& operator=(const BackgroundTask&) = delete;
  ~BackgroundTask() {
    if (thread_.joinable()) thread_.join();
  }
  template <typename Body>
  void Start(Body&& body) {
    thread_ = std::thread([this, body = std::forward<Body>(body)]() mutable {
      try {
        body();
      } catch (...) {
        failed_ = std::current_exception();
      }
    });
  }
  void Wait() {
    if (thread_.joinable()) thread_.join();
    if (failed_) std::rethrow_exception(std::exchange(failed_, nullptr));
  }

 private:
  std::thread thread_;
  std::exception_ptr failed_;
};

// The number of chunks ForEachChunk makes.
inline size_t ChunkCount(size_t count, size_t chunk_size) {
  chunk_size = std::max<size_t>(1, chunk_size);
  return (count + chunk_size - 1) / chunk_size;
}

}  // namespace sdvi::fit_internal

#endif  // SDVI_FIT_PARALLEL_H_
