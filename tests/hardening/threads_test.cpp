// SPDX-License-Identifier: GPL-3.0-or-later
// sdvi::RunTasks (sdvi/parallel.h, spec/METHOD.md 6 "Threads"): every task runs once, an
// exception thrown on a thread reaches the caller, and a thread that cannot be started
// leaves its task to the calling thread (issue 16: under --max-memory a worker's stack may
// not fit, and a thread pool that let that escape ended the process).
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "sdvi/parallel.h"

namespace {

// Runs tasks that record their own index and the thread they ran on; tasks listed in
// `throwing` throw "task K". Returns the message of what RunTasks threw ("" if nothing).
std::string RunRecorded(int count, const std::vector<int>& throwing, std::vector<int>& runs,
                        std::vector<std::thread::id>& ran_on) {
  runs.assign(size_t(count), 0);
  ran_on.assign(size_t(count), std::thread::id());
  try {
    sdvi::RunTasks(count, [&](int k) {
      ++runs[size_t(k)];
      ran_on[size_t(k)] = std::this_thread::get_id();
      for (int t : throwing)
        if (t == k) throw std::runtime_error("task " + std::to_string(k));
    });
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

bool EachRanOnce(const std::vector<int>& runs) {
  for (int r : runs)
    if (r != 1) return false;
  return true;
}

}  // namespace

TEST_CASE("RunTasks runs every task once, task 0 on the calling thread", "[threads]") {
  for (int count : {0, 1, 2, 5, 33}) {
    std::vector<int> runs;
    std::vector<std::thread::id> ran_on;
    CHECK(RunRecorded(count, {}, runs, ran_on).empty());
    CHECK(EachRanOnce(runs));
    if (count > 0) CHECK(ran_on[0] == std::this_thread::get_id());
  }
}

TEST_CASE("RunTasks carries the lowest failing task's exception to the caller after all ran", "[threads]") {
  std::vector<int> runs;
  std::vector<std::thread::id> ran_on;
  CHECK(RunRecorded(8, {5, 2, 7}, runs, ran_on) == "task 2");
  CHECK(EachRanOnce(runs));
  CHECK(RunRecorded(3, {0}, runs, ran_on) == "task 0");
  CHECK(EachRanOnce(runs));
}

#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
TEST_CASE("RunTasks runs the tasks of threads that cannot start on the calling thread", "[threads]") {
  // In a child process, an address-space limit a little above what the process holds: a
  // new thread's stack (8 MiB) does not fit, so thread starts fail.
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    long pages = 0;
    if (std::FILE* statm = std::fopen("/proc/self/statm", "r")) {
      if (std::fscanf(statm, "%ld", &pages) != 1) pages = 0;
      std::fclose(statm);
    }
    struct rlimit limit {};
    ::getrlimit(RLIMIT_AS, &limit);
    limit.rlim_cur = rlim_t(pages) * rlim_t(::sysconf(_SC_PAGESIZE)) + (rlim_t(2) << 20);
    if (pages == 0 || ::setrlimit(RLIMIT_AS, &limit) != 0) ::_exit(3);
    // glibc keeps the stacks of ended threads for new ones: hold threads until none starts.
    std::atomic<bool> release{false};
    std::vector<std::thread> holders;
    holders.reserve(1000);
    for (;;) {
      if (holders.size() == 1000) ::_exit(4);
      try {
        holders.emplace_back([&release] {
          while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        });
      } catch (const std::system_error&) {
        break;
      }
    }
    std::vector<int> runs;
    std::vector<std::thread::id> ran_on;
    if (!RunRecorded(6, {}, runs, ran_on).empty() || !EachRanOnce(runs)) ::_exit(5);
    for (const std::thread::id& id : ran_on)
      if (id != std::this_thread::get_id()) ::_exit(6);
    if (RunRecorded(6, {4, 1}, runs, ran_on) != "task 1" || !EachRanOnce(runs)) ::_exit(7);
    release = true;
    for (std::thread& t : holders) t.join();
    ::_exit(0);
  }
  int status = 0;
  REQUIRE(::waitpid(child, &status, 0) == child);
  REQUIRE(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);  // 3: no limit set, 4: a thread started, 5-7: wrong runs
}
#endif
