// SPDX-License-Identifier: GPL-3.0-or-later
// Tasks on threads, safe under memory limits: the one place where sdvi starts threads
// (spec/METHOD.md 6 "Threads"): RunTasks for tasks the caller waits for, BackgroundTask for
// one task beside the caller's own work.
#ifndef SDVI_PARALLEL_H_
#define SDVI_PARALLEL_H_

#include <exception>
#include <thread>
#include <utility>
#include <vector>

namespace sdvi {

// Worker threads when the caller names none: the cores, at most 8.
inline int DefaultThreads() {
  const unsigned cores = std::thread::hardware_concurrency();
  return cores == 0 ? 1 : int(cores < 8 ? cores : 8);
}

// Runs task(k) for k = 0 .. count - 1: task 0 on the calling thread, each other task on a
// thread of its own. A thread that cannot be started (std::system_error, or std::bad_alloc
// for its stack: an address-space limit such as --max-memory refuses it) leaves its task to
// the calling thread, which runs it after task 0, so the same tasks run whatever the limit.
// An exception thrown by a task (std::bad_alloc, cv::Exception) never leaves its thread:
// every task runs to its end, all threads are joined, and then the exception of the lowest
// task that threw is thrown again on the calling thread. A task that shares a work queue
// with the others should stop taking work once one of them has failed.
template <typename Task>
void RunTasks(int count, Task&& task) {
  if (count <= 0) return;
  std::vector<std::exception_ptr> failed(static_cast<size_t>(count));
  auto run = [&task, &failed](int k) noexcept {
    try {
      task(k);
    } catch (...) {
      failed[static_cast<size_t>(k)] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  int started = 1;
  try {
    for (; started < count; ++started) pool.emplace_back(run, started);
  } catch (...) {
    // Tasks started .. count - 1 have no thread: the calling thread runs them below.
  }
  run(0);
  for (int k = started; k < count; ++k) run(k);
  for (std::thread& thread : pool) thread.join();
  for (const std::exception_ptr& e : failed) {
    if (e) std::rethrow_exception(e);
  }
}

// One task beside the caller's own work, on a thread of its own: Wait() joins it and throws
// again what it threw; a task still running when the object goes (an early return, an
// exception on the caller) is joined, what it threw dropped. When no thread can be started
// (as in RunTasks) Start runs the task itself, before returning.
class BackgroundTask {
 public:
  BackgroundTask() = default;
  BackgroundTask(const BackgroundTask&) = delete;
  BackgroundTask& operator=(const BackgroundTask&) = delete;
  ~BackgroundTask() {
    if (thread_.joinable()) thread_.join();
  }
  template <typename Task>
  void Start(Task&& task) {
    auto run = [this, task = std::forward<Task>(task)]() mutable noexcept {
      try {
        task();
      } catch (...) {
        failed_ = std::current_exception();
      }
    };
    try {
      thread_ = std::thread(run);
    } catch (...) {
      run();  // no thread: the task runs here
    }
  }
  void Wait() {
    if (thread_.joinable()) thread_.join();
    if (failed_) std::rethrow_exception(std::exchange(failed_, nullptr));
  }

 private:
  std::thread thread_;
  std::exception_ptr failed_;
};

}  // namespace sdvi

#endif  // SDVI_PARALLEL_H_
