// SPDX-License-Identifier: GPL-3.0-or-later
// Batch runs of a subcommand over many inputs; rules in batch.h.
#include "batch.h"

#include <fcntl.h>
#include <glob.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>
#include <nlohmann/json.hpp>

#include "sdvi/file_util.h"
#include "sdvi/progress.h"

namespace sdvi::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

bool HasExtension(const fs::path& p, const std::vector<std::string>& extensions) {
  std::string ext = Lower(p.extension().string());
  if (!ext.empty()) ext.erase(0, 1);
  return std::find(extensions.begin(), extensions.end(), ext) != extensions.end();
}

bool IsPattern(const std::string& s) { return s.find_first_of("*?[") != std::string::npos; }

// The files one input names (batch.h: files, directories, patterns).
StatusOr<std::vector<std::string>> Expand(const std::string& input, const std::vector<std::string>& extensions) {
  std::error_code ec;
  std::vector<std::string> files;
  if (fs::is_directory(input, ec)) {
    for (const fs::directory_entry& e : fs::directory_iterator(input, ec)) {
      if (e.is_regular_file(ec) && HasExtension(e.path(), extensions)) files.push_back(e.path().string());
    }
    if (ec) return Status(StatusCode::kIoError, input + ": cannot list the directory: " + ec.message());
    std::sort(files.begin(), files.end());
    return files;
  }
  if (fs::exists(input, ec) || !IsPattern(input)) {
    if (!fs::exists(input, ec)) return Status(StatusCode::kNotFound, input + ": no such file or directory");
    files.push_back(input);
    return files;
  }
  glob_t found{};
  const int rc = glob(input.c_str(), 0, nullptr, &found);
  if (rc == 0) {
    for (size_t i = 0; i < found.gl_pathc; ++i) {
      if (fs::is_regular_file(found.gl_pathv[i], ec)) files.push_back(found.gl_pathv[i]);
    }
  }
  globfree(&found);
  if (files.empty()) return Status(StatusCode::kNotFound, input + ": the pattern matches no file");
  std::sort(files.begin(), files.end());
  return files;
}

struct Running {
  BatchJob job;
  Clock::time_point start;
  std::string error_file;
  uint64_t stopped_at_bytes = 0;  // resident memory when the limit stopped it (0: not stopped)
  Clock::time_point stopped;
};

// A running process's resident memory in bytes (/proc/PID/statm), 0 when unknown.
uint64_t ResidentBytes(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/statm");
  uint64_t size = 0, resident = 0;
  if (!(in >> size >> resident)) return 0;
  return resident * uint64_t(sysconf(_SC_PAGESIZE));
}

// Stops the jobs whose resident memory is over the limit (batch.h, Memory): SIGTERM, on
// which sdvi removes its temporary output file, then SIGKILL a second later.
void EnforceMemoryLimit(std::map<pid_t, Running>& running, uint64_t limit) {
  for (auto& [pid, job] : running) {
    if (job.stopped_at_bytes != 0) {
      if (Clock::now() - job.stopped > std::chrono::seconds(1)) kill(pid, SIGKILL);
      continue;
    }
    const uint64_t resident = ResidentBytes(pid);
    if (resident > limit) {
      job.stopped_at_bytes = resident;
      job.stopped = Clock::now();
      kill(pid, SIGTERM);
    }
  }
}

std::string ReadAndRemove(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::error_code ec;
  fs::remove(path, ec);
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return text;
}

// Starts one job: this executable with the subcommand, the input, -o output and the shared
// options; stdout to /dev/null, stderr to error_file; the memory limit applied in the child.
StatusOr<pid_t> Start(const BatchOptions& o, const BatchJob& job, const std::string& error_file) {
  std::vector<std::string> args{o.executable, o.command, job.input, "-o", job.output};
  args.insert(args.end(), o.command_args.begin(), o.command_args.end());
  args.push_back("--quiet");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) return Status(StatusCode::kIoError, std::string("batch: fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    const int null_fd = open("/dev/null", O_WRONLY);
    const int err_fd = open(error_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (null_fd >= 0) dup2(null_fd, STDOUT_FILENO);
    if (err_fd >= 0) dup2(err_fd, STDERR_FILENO);
    execv(o.executable.c_str(), argv.data());
    std::fprintf(stderr, "%s: cannot run %s: %s\n", job.input.c_str(), o.executable.c_str(), std::strerror(errno));
    _exit(127);
  }
  return pid;
}

}  // namespace

StatusOr<std::vector<BatchJob>> PlanBatch(const BatchOptions& options) {
  if (options.inputs.empty()) return Status(StatusCode::kInvalidArgument, "batch: no input given");
  std::vector<BatchJob> jobs;
  std::map<std::string, std::string> writer;  // output -> input
  for (const std::string& input : options.inputs) {
    SDVI_ASSIGN_OR_RETURN(std::vector<std::string> files, Expand(input, options.input_extensions));
    for (const std::string& file : files) {
      const std::string output =
          (fs::path(options.output_dir) / (fs::path(file).stem().string() + "." + options.output_extension)).string();
      std::error_code ec;
      if (fs::equivalent(file, output, ec)) {
        return Status(StatusCode::kInvalidArgument,
                      "batch: " + file + " would be its own output; choose another output directory");
      }
      auto [it, fresh] = writer.emplace(output, file);
      if (!fresh) {
        if (it->second == file) continue;  // the same file named twice
        return Status(StatusCode::kInvalidArgument,
                      "batch: " + it->second + " and " + file + " would both write " + output);
      }
      jobs.push_back({file, output});
    }
  }
  return jobs;
}

StatusOr<BatchSummary> RunBatch(const BatchOptions& options, const std::vector<BatchJob>& jobs) {
  std::error_code ec;
  fs::create_directories(options.output_dir, ec);
  if (ec) return Status(StatusCode::kIoError, options.output_dir + ": cannot create the output directory: " + ec.message());
  std::FILE* report = nullptr;
  if (!options.report_path.empty()) {
    report = std::fopen(options.report_path.c_str(), "a");
    if (report == nullptr) {
      return Status(StatusCode::kIoError, options.report_path + ": cannot open the report: " + std::strerror(errno));
    }
  }
  // Each job's stderr goes to a file of its own here, read when it ends (never into the
  // output directory, where an interrupted batch would leave it).
  std::string scratch = (fs::temp_directory_path(ec) / "sdvi-batch-XXXXXX").string();
  if (mkdtemp(scratch.data()) == nullptr) {
    if (report != nullptr) std::fclose(report);
    return Status(StatusCode::kIoError, scratch + ": cannot create a scratch directory: " + std::strerror(errno));
  }
  BatchSummary summary;
  Progress progress(options.quiet);
  progress.Phase(options.command + " " + std::to_string(jobs.size()) + " files");
  size_t finished = 0;
  auto record = [&](const BatchJob& job, const char* status, int exit_code, double seconds, double rss_mib,
                    const std::string& error) {
    ++finished;
    if (report != nullptr) {
      nlohmann::json line = {{"input", job.input}, {"output", job.output}, {"command", options.command},
                             {"status", status},   {"exit_code", exit_code}, {"seconds", seconds},
                             {"peak_rss_mib", rss_mib}};
      if (!error.empty()) line["error"] = error;
      const std::string text = line.dump() + "\n";
      std::fwrite(text.data(), 1, text.size(), report);
      std::fflush(report);
    }
    if (!error.empty()) std::fprintf(stderr, "%s%s\n", progress.enabled() ? "\n" : "", error.c_str());
    progress.Update(double(finished) / double(std::max<size_t>(1, jobs.size())),
                    std::to_string(finished) + "/" + std::to_string(jobs.size()) + ", " +
                        std::to_string(summary.failed) + " failed");
  };

  std::map<pid_t, Running> running;
  size_t next = 0;
  const int slots = std::max(1, options.jobs);
  Status batch_error;
  while (next < jobs.size() || !running.empty()) {
    while (batch_error.ok() && next < jobs.size() && int(running.size()) < slots) {
      const BatchJob& job = jobs[next++];
      if (options.skip_existing && fs::exists(job.output, ec)) {
        ++summary.skipped;
        record(job, "skipped", 0, 0, 0, "");
        continue;
      }
      const std::string error_file = (fs::path(scratch) / std::to_string(next)).string();
      StatusOr<pid_t> pid = Start(options, job, error_file);
      if (!pid.ok()) {
        batch_error = pid.status();
        break;
      }
      running[*pid] = {job, Clock::now(), error_file, 0, {}};
    }
    if (running.empty()) break;
    int status = 0;
    rusage usage{};
    const bool watch = options.max_memory_bytes > 0;
    const pid_t pid = wait4(-1, &status, watch ? WNOHANG : 0, &usage);
    if (pid == 0) {  // none finished yet (watching memory)
      EnforceMemoryLimit(running, options.max_memory_bytes);
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    if (pid < 0) {
      if (errno == EINTR) continue;
      batch_error = Status(StatusCode::kInternal, std::string("batch: wait failed: ") + std::strerror(errno));
      break;
    }
    auto it = running.find(pid);
    if (it == running.end()) continue;
    const Running done = std::move(it->second);
    running.erase(it);
    const double seconds = std::chrono::duration<double>(Clock::now() - done.start).count();
    const double rss_mib = double(usage.ru_maxrss) / 1024.0;
    std::string error = ReadAndRemove(done.error_file);
    if (done.stopped_at_bytes != 0) {
      error = done.job.input + ": stopped at " + std::to_string((done.stopped_at_bytes + (1u << 20) - 1) >> 20) +
              " MiB resident, over the memory limit of " + std::to_string(options.max_memory_bytes >> 20) +
              " MiB per job";
    } else if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      ++summary.ok;
      record(done.job, "ok", 0, seconds, rss_mib, "");
      continue;
    }
    ++summary.failed;
    int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    if (code == 0) code = 128 + SIGTERM;  // stopped by the memory limit as it finished
    if (error.empty()) {
      error = done.job.input + ": " +
              (WIFSIGNALED(status) ? std::string("killed by signal ") + std::to_string(WTERMSIG(status))
                                   : "failed with exit code " + std::to_string(code));
    }
    record(done.job, "failed", code, seconds, rss_mib, error);
  }
  progress.Done();
  if (report != nullptr) std::fclose(report);
  fs::remove_all(scratch, ec);
  if (!batch_error.ok()) return batch_error;
  return summary;
}

}  // namespace sdvi::cli
