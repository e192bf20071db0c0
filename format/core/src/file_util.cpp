// SPDX-License-Identifier: GPL-3.0-or-later
#include "sdvi/file_util.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>

namespace sdvi {
namespace {

std::string ErrnoText() { return std::strerror(errno); }

// A unique sibling of path with the same extension: "dir/.name.sdvi-tmp-PID-N.ext".
std::string TempSibling(const std::string& path) {
  static std::atomic<int> counter{0};
  std::filesystem::path p(path);
  std::string name(".");
  name.append(p.stem().string())
      .append(".sdvi-tmp-")
      .append(std::to_string(::getpid()))
      .append("-")
      .append(std::to_string(counter++))
      .append(p.extension().string());
  return (p.parent_path() / name).string();
}

// Temporary files being written, removed by the SIGINT/SIGTERM handler. Slots hold
// malloc'ed copies of the names; the handler only reads them and calls unlink
// (async-signal-safe).
constexpr size_t kTempSlots = 64;
std::array<std::atomic<char*>, kTempSlots> g_temp_files{};
struct sigaction g_previous_int, g_previous_term;

void RemoveTempFilesOnSignal(int sig) {
  for (auto& slot : g_temp_files)
    if (char* name = slot.load()) ::unlink(name);
  // Then die of the signal as the previous disposition would have.
  ::sigaction(sig, sig == SIGINT ? &g_previous_int : &g_previous_term, nullptr);
  ::raise(sig);
}

// Installs RemoveTempFilesOnSignal for SIGINT and SIGTERM where their disposition is the
// default (a program's own handler, or an ignored signal, is left alone). Checked at
// every write, so a disposition reset later (e.g. in a child process) is covered too.
void InstallSignalCleanup() {
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  struct sigaction action {};
  action.sa_handler = RemoveTempFilesOnSignal;
  sigemptyset(&action.sa_mask);
  for (auto [sig, previous] : {std::pair{SIGINT, &g_previous_int}, std::pair{SIGTERM, &g_previous_term}}) {
    struct sigaction current {};
    ::sigaction(sig, nullptr, &current);
    if (current.sa_handler != SIG_DFL) continue;
    *previous = current;
    ::sigaction(sig, &action, nullptr);
  }
}

// Registers a temporary file for removal on SIGINT/SIGTERM while it lives.
class TempFileGuard {
 public:
  explicit TempFileGuard(const std::string& path) {
    InstallSignalCleanup();
    char* copy = ::strdup(path.c_str());
    for (auto& slot : g_temp_files) {
      char* expected = nullptr;
      if (copy && slot.compare_exchange_strong(expected, copy)) {
        slot_ = &slot;
        return;
      }
    }
    std::free(copy);  // more than kTempSlots at once: no signal cleanup for this one
  }
  ~TempFileGuard() {
    if (slot_) std::free(slot_->exchange(nullptr));
  }
  TempFileGuard(const TempFileGuard&) = delete;
  TempFileGuard& operator=(const TempFileGuard&) = delete;

 private:
  std::atomic<char*>* slot_ = nullptr;
};

// Writes all of data to fd; what names the target in errors.
Status WriteAll(int fd, const void* data, size_t size, const std::string& what) {
  const auto* p = static_cast<const uint8_t*>(data);
  size_t left = size;
  while (left > 0) {
    ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      return Status(StatusCode::kIoError, what + ": write failed: " + ErrnoText());
    }
    p += n;
    left -= static_cast<size_t>(n);
  }
  return Status::Ok();
}

// Where an output path leads: the file a symlink chain ends at (or would be created at).
struct OutputTarget {
  std::string path;        // symlinks resolved
  bool exists = false;
  bool regular = false;    // exists and is a regular file
  struct stat st {};       // when exists
};

StatusOr<OutputTarget> ResolveOutput(const std::string& path) {
  OutputTarget target;
  target.path = path;
  // Follow symlinks by hand so that a dangling link names the file it would create.
  for (int hops = 0;; ++hops) {
    struct stat lst {};
    if (::lstat(target.path.c_str(), &lst) != 0) {
      if (errno == ENOENT) return target;
      return Status(StatusCode::kIoError, path + ": cannot inspect the output path: " + ErrnoText());
    }
    if (!S_ISLNK(lst.st_mode)) break;
    if (hops >= 40) return Status(StatusCode::kIoError, path + ": too many levels of symbolic links");
    std::error_code ec;
    const std::filesystem::path link = std::filesystem::read_symlink(target.path, ec);
    if (ec) return Status(StatusCode::kIoError, path + ": cannot read the symbolic link: " + ec.message());
    target.path = link.is_absolute() ? link.string()
                                     : (std::filesystem::path(target.path).parent_path() / link).string();
  }
  if (::stat(target.path.c_str(), &target.st) != 0)
    return Status(StatusCode::kIoError, path + ": cannot inspect the output path: " + ErrnoText());
  target.exists = true;
  target.regular = S_ISREG(target.st.st_mode);
  if (S_ISDIR(target.st.st_mode))
    return Status(StatusCode::kIoError, path + ": is a directory, expected a file to write");
  return target;
}

// Copies the file at from into the non-regular file at to (device, FIFO, socket).
Status CopyInto(const std::string& from, const std::string& to, const std::string& what) {
  SDVI_ASSIGN_OR_RETURN(std::vector<uint8_t> bytes, ReadFileBytes(from));
  const int fd = ::open(to.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) return Status(StatusCode::kIoError, what + ": cannot open for writing: " + ErrnoText());
  Status status = WriteAll(fd, bytes.data(), bytes.size(), what);
  if (::close(fd) != 0 && status.ok())
    status = Status(StatusCode::kIoError, what + ": write failed: " + ErrnoText());
  return status;
}

// Gives the finished temporary file the mode (and, for root, the owner) of the file it
// replaces.
void KeepModeAndOwner(const std::string& tmp, const struct stat& replaced) {
  ::chmod(tmp.c_str(), replaced.st_mode & 07777);
  if (::geteuid() == 0) {
    if (::chown(tmp.c_str(), replaced.st_uid, replaced.st_gid) == 0)
      ::chmod(tmp.c_str(), replaced.st_mode & 07777);  // chown clears set-id bits
  }
}

// The file an input path names: "-" is standard input.
std::string StdStreamPath(const std::string& path) { return path == "-" ? "/dev/stdin" : path; }

// Writes a temporary file's bytes to standard output (which may be a regular file the
// shell opened: it is written through, never renamed over).
Status CopyToStdout(const std::string& tmp) {
  std::ifstream in(tmp, std::ios::binary);
  if (!in) return Status(StatusCode::kIoError, "standard output: the writer produced no file");
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return WriteAll(STDOUT_FILENO, bytes.data(), bytes.size(), "standard output");
}

}  // namespace

bool IsStdStream(const std::string& path) { return path == "-"; }

StatusOr<std::vector<uint8_t>> ReadFileBytes(const std::string& given_path, uint64_t max_bytes) {
  const std::string path = StdStreamPath(given_path);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    return Status(StatusCode::kNotFound, path + ": no such file");
  if (std::filesystem::is_directory(path, ec))
    return Status(StatusCode::kIoError, path + ": is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status(StatusCode::kIoError, path + ": cannot open for reading: " + ErrnoText());
  if (std::filesystem::is_regular_file(path, ec)) {
    in.seekg(0, std::ios::end);
    std::streamoff size = in.tellg();
    if (size < 0) return Status(StatusCode::kIoError, path + ": cannot determine size");
    if (uint64_t(size) > max_bytes)
      return Status(StatusCode::kLimitExceeded, path + ": " + std::to_string(size) +
                                                    " bytes exceed the limit of " +
                                                    std::to_string(max_bytes));
    in.seekg(0, std::ios::beg);
    std::vector<uint8_t> bytes(static_cast<size_t>(size));
    if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size))
      return Status(StatusCode::kIoError, path + ": read failed");
    return bytes;
  }
  // A FIFO or device: read to the end.
  std::vector<uint8_t> bytes;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    bytes.insert(bytes.end(), buffer, buffer + in.gcount());
    if (bytes.size() > max_bytes)
      return Status(StatusCode::kLimitExceeded,
                    path + ": more than " + std::to_string(max_bytes) + " bytes (the limit)");
  }
  if (in.bad()) return Status(StatusCode::kIoError, path + ": read failed");
  return bytes;
}

Status WriteFileAtomic(const std::string& path, const void* data, size_t size) {
  if (IsStdStream(path)) return WriteAll(STDOUT_FILENO, data, size, "standard output");
  if (!path.empty()) {
    SDVI_ASSIGN_OR_RETURN(OutputTarget target, ResolveOutput(path));
    if (target.exists && !target.regular) {
      // A device, FIFO or socket: write through (a rename would replace it).
      const int fd = ::open(target.path.c_str(), O_WRONLY | O_CLOEXEC);
      if (fd < 0) return Status(StatusCode::kIoError, path + ": cannot open for writing: " + ErrnoText());
      Status status = WriteAll(fd, data, size, path);
      if (::close(fd) != 0 && status.ok())
        status = Status(StatusCode::kIoError, path + ": write failed: " + ErrnoText());
      return status;
    }
  }
  return WriteViaTempFile(path, [&](const std::string& tmp) -> Status {
    int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) return Status(StatusCode::kIoError, path + ": cannot create: " + ErrnoText());
    if (Status s = WriteAll(fd, data, size, path); !s.ok()) {
      ::close(fd);
      return s;
    }
    if (::fsync(fd) != 0 || ::close(fd) != 0)
      return Status(StatusCode::kIoError, path + ": flush failed: " + ErrnoText());
    return Status::Ok();
  });
}

Status WriteViaTempFile(const std::string& path,
                        const std::function<Status(const std::string& temp_path)>& write) {
  if (IsStdStream(path)) {
    std::error_code ec;
    const std::string tmp = TempSibling((std::filesystem::temp_directory_path(ec) / "stdout").string());
    TempFileGuard guard(tmp);
    Status status;
    try {
      status = write(tmp);
    } catch (const std::exception& e) {
      status = Status(StatusCode::kIoError, std::string("standard output: ") + e.what());
    }
    if (status.ok()) status = CopyToStdout(tmp);
    std::filesystem::remove(tmp, ec);
    return status;
  }
  if (path.empty()) return Status(StatusCode::kInvalidArgument, "empty output path");
  SDVI_ASSIGN_OR_RETURN(OutputTarget target, ResolveOutput(path));
  // A non-regular target gets the bytes written into it; the temporary then lives in the
  // temporary directory (a device's directory is no place for it).
  const bool write_through = target.exists && !target.regular;
  std::error_code ec;
  const std::string tmp =
      write_through ? TempSibling((std::filesystem::temp_directory_path(ec) /
                                   std::filesystem::path(path).filename()).string())
                    : TempSibling(target.path);
  TempFileGuard guard(tmp);
  Status status;
  try {
    status = write(tmp);
  } catch (const std::exception& e) {
    status = Status(StatusCode::kIoError, path + ": " + e.what());
  }
  if (status.ok() && !std::filesystem::exists(tmp, ec))
    status = Status(StatusCode::kIoError, path + ": the writer produced no file");
  if (status.ok() && write_through) status = CopyInto(tmp, target.path, path);
  if (!status.ok() || write_through) {
    std::filesystem::remove(tmp, ec);
    return status;
  }
  if (target.exists) KeepModeAndOwner(tmp, target.st);
  if (std::rename(tmp.c_str(), target.path.c_str()) != 0) {
    std::string why = ErrnoText();
    std::filesystem::remove(tmp, ec);
    return Status(StatusCode::kIoError, path + ": rename failed: " + why);
  }
  return Status::Ok();
}

Status CheckOutputPath(const std::string& path, const std::vector<std::string>& inputs) {
  if (IsStdStream(path)) return Status::Ok();
  if (path.empty()) return Status(StatusCode::kInvalidArgument, "empty output path");
  SDVI_ASSIGN_OR_RETURN(OutputTarget target, ResolveOutput(path));
  if (target.exists) {
    for (const std::string& input : inputs) {
      struct stat in {};
      if (::stat(input.c_str(), &in) == 0 && in.st_dev == target.st.st_dev && in.st_ino == target.st.st_ino)
        return Status(StatusCode::kInvalidArgument,
                      path + ": the output is the input file " + input + "; choose another output");
    }
    if (!target.regular) {
      if (::access(target.path.c_str(), W_OK) != 0)
        return Status(StatusCode::kIoError, path + ": cannot write: " + ErrnoText());
      return Status::Ok();
    }
  }
  // The temporary file is created beside the target, then renamed: the directory must
  // exist and be writable.
  std::filesystem::path dir = std::filesystem::path(target.path).parent_path();
  if (dir.empty()) dir = ".";
  struct stat dst {};
  if (::stat(dir.c_str(), &dst) != 0)
    return Status(StatusCode::kNotFound, path + ": the directory " + dir.string() + " does not exist");
  if (!S_ISDIR(dst.st_mode))
    return Status(StatusCode::kIoError, path + ": " + dir.string() + " is not a directory");
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    return Status(StatusCode::kIoError, path + ": cannot create files in " + dir.string() + ": " + ErrnoText());
  return Status::Ok();
}

std::string FileExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace sdvi
