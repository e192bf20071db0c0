// SPDX-License-Identifier: GPL-3.0-or-later
// Output files (file_util.h): non-regular targets written through, symlinks followed with
// the target's mode kept, outputs checked before work, temporaries removed on signals.
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <thread>

#include "sdvi/file_util.h"

namespace fs = std::filesystem;
using sdvi::StatusCode;

namespace {

// A fresh scratch directory per test case.
fs::path Scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sdvi_files_test_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string Slurp(const fs::path& path) {
  auto bytes = sdvi::ReadFileBytes(path.string());
  REQUIRE(bytes.ok());
  return std::string(bytes->begin(), bytes->end());
}

size_t CountEntries(const fs::path& dir) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  return n;
}

}  // namespace

TEST_CASE("issue 16.2: a symlink is followed; its target is replaced keeping its mode") {
  const fs::path dir = Scratch("symlink");
  const fs::path target = dir / "target.sdvi", link = dir / "link.sdvi";
  REQUIRE(sdvi::WriteFileAtomic(target.string(), "old", 3).ok());
  ::chmod(target.c_str(), 0640);
  fs::create_symlink("target.sdvi", link);
  REQUIRE(sdvi::WriteFileAtomic(link.string(), "new!", 4).ok());
  CHECK(fs::is_symlink(link));
  CHECK(Slurp(target) == "new!");
  struct stat st {};
  REQUIRE(::stat(target.c_str(), &st) == 0);
  CHECK((st.st_mode & 07777) == 0640);
  CHECK(CountEntries(dir) == 2);  // no temporary left
  // A read-only file keeps its mode too.
  ::chmod(target.c_str(), 0444);
  REQUIRE(sdvi::WriteViaTempFile(target.string(), [](const std::string& tmp) {
            return sdvi::WriteFileAtomic(tmp, "via", 3);
          }).ok());
  REQUIRE(::stat(target.c_str(), &st) == 0);
  CHECK((st.st_mode & 07777) == 0444);
  CHECK(Slurp(target) == "via");
  // A dangling link creates the file it names.
  fs::create_symlink("made.sdvi", dir / "dangling.sdvi");
  REQUIRE(sdvi::WriteFileAtomic((dir / "dangling.sdvi").string(), "x", 1).ok());
  CHECK(Slurp(dir / "made.sdvi") == "x");
  fs::remove_all(dir);
}

TEST_CASE("issue 16.2: devices are written through, never replaced") {
  REQUIRE(sdvi::WriteFileAtomic("/dev/null", "abc", 3).ok());
  CHECK(fs::is_character_file("/dev/null"));
  const sdvi::Status full = sdvi::WriteFileAtomic("/dev/full", "abc", 3);
  CHECK(full.code() == StatusCode::kIoError);
  CHECK(full.message().find("/dev/full") == 0);
  CHECK(fs::is_character_file("/dev/full"));
  // Writers that need a file name (OpenCV, OpenEXR) go through a temporary elsewhere.
  CHECK(sdvi::WriteViaTempFile("/dev/null", [](const std::string& tmp) {
          return sdvi::WriteFileAtomic(tmp, "abc", 3);
        }).ok());
  CHECK(fs::is_character_file("/dev/null"));
  CHECK(sdvi::WriteViaTempFile("/dev/full", [](const std::string& tmp) {
          return sdvi::WriteFileAtomic(tmp, "abc", 3);
        }).code() == StatusCode::kIoError);
}

TEST_CASE("issue 16.2: a FIFO is written through and stays a FIFO") {
  const fs::path dir = Scratch("fifo");
  const fs::path fifo = dir / "pipe.sdvi";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  std::string received;
  std::thread reader([&] {
    const int fd = ::open(fifo.c_str(), O_RDONLY);
    char buf[64];
    for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) > 0;) received.append(buf, size_t(n));
    ::close(fd);
  });
  const sdvi::Status status = sdvi::WriteFileAtomic(fifo.string(), "through", 7);
  reader.join();
  CHECK(status.ok());
  CHECK(received == "through");
  CHECK(fs::is_fifo(fifo));
  CHECK(CountEntries(dir) == 1);
  fs::remove_all(dir);
}

TEST_CASE("issue 16.2 and 16.6: CheckOutputPath refuses an output equal to an input, a missing directory, a directory") {
  const fs::path dir = Scratch("check");
  const fs::path in = dir / "in.png";
  REQUIRE(sdvi::WriteFileAtomic(in.string(), "png", 3).ok());
  const sdvi::Status same = sdvi::CheckOutputPath(in.string(), {in.string()});
  CHECK(same.code() == StatusCode::kInvalidArgument);
  CHECK(same.message().find(in.string()) == 0);
  // The same file by another name (a symlink, a hard link) is the same file.
  fs::create_symlink(in, dir / "alias.png");
  CHECK(sdvi::CheckOutputPath((dir / "alias.png").string(), {in.string()}).code() == StatusCode::kInvalidArgument);
  fs::create_hard_link(in, dir / "hard.png");
  CHECK(sdvi::CheckOutputPath((dir / "hard.png").string(), {in.string()}).code() == StatusCode::kInvalidArgument);
  CHECK(sdvi::CheckOutputPath(in.string(), {(dir / "other.png").string()}).ok());
  CHECK(sdvi::CheckOutputPath((dir / "new.sdvi").string(), {in.string()}).ok());
  const sdvi::Status nodir = sdvi::CheckOutputPath((dir / "nodir" / "r.json").string());
  CHECK(nodir.code() == StatusCode::kNotFound);
  CHECK(nodir.message().find("r.json") != std::string::npos);
  CHECK(sdvi::CheckOutputPath(dir.string()).code() == StatusCode::kIoError);
  CHECK(sdvi::CheckOutputPath((in / "x.sdvi").string()).code() != StatusCode::kOk);  // parent is a file
  CHECK(sdvi::CheckOutputPath("/dev/null").ok());
  fs::remove_all(dir);
}

TEST_CASE("ReadFileBytes refuses a file over its limit before reading it") {
  const fs::path dir = Scratch("limit");
  REQUIRE(sdvi::WriteFileAtomic((dir / "f").string(), "0123456789", 10).ok());
  CHECK(sdvi::ReadFileBytes((dir / "f").string(), 9).status().code() == StatusCode::kLimitExceeded);
  CHECK(sdvi::ReadFileBytes((dir / "f").string(), 10).ok());
  fs::remove_all(dir);
}

TEST_CASE("issue 16.2: SIGTERM and SIGINT during a write remove the temporary file") {
  for (int sig : {SIGTERM, SIGINT}) {
    const fs::path dir = Scratch("signal" + std::to_string(sig));
    const fs::path out = dir / "out.sdvi";
    int ready[2];
    REQUIRE(::pipe(ready) == 0);
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
      // Catch2 handles signals in the test process; a program has the defaults.
      ::signal(SIGINT, SIG_DFL);
      ::signal(SIGTERM, SIG_DFL);
      // The writer creates its temporary, says so, and waits to be killed.
      (void)sdvi::WriteViaTempFile(out.string(), [&](const std::string& tmp) {
        (void)sdvi::WriteFileAtomic(tmp, "partial", 7);
        const char c = 1;
        (void)!::write(ready[1], &c, 1);
        for (;;) ::pause();
        return sdvi::Status::Ok();
      });
      ::_exit(0);
    }
    char c = 0;
    REQUIRE(::read(ready[0], &c, 1) == 1);
    CHECK(CountEntries(dir) == 1);  // the temporary exists
    ::kill(child, sig);
    int status = 0;
    ::waitpid(child, &status, 0);
    CHECK(WIFSIGNALED(status));
    CHECK(WTERMSIG(status) == sig);
    CHECK(CountEntries(dir) == 0);
    ::close(ready[0]);
    ::close(ready[1]);
    fs::remove_all(dir);
  }
}
