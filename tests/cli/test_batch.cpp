// SPDX-License-Identifier: GPL-3.0-or-later
// The batch runner (cli/batch.h) with a stand-in command: a shell script that copies its
// input to its output atomically, fails on inputs named *bad*, and fills 512 MiB on
// inputs named *huge* (which the per-job memory limit must stop).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "batch.h"

namespace fs = std::filesystem;
using sdvi::cli::BatchOptions;

namespace {

struct Fixture {
  fs::path root;
  BatchOptions options;

  Fixture() {
    root = fs::temp_directory_path() / ("sdvi_batch_test_" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root / "in");
    const fs::path script = root / "fake_sdvi.sh";
    std::ofstream(script) << "#!/bin/sh\n"
                             "cmd=\"$1\"; in=\"$2\"; out=\"$4\"; shift 4\n"
                             "case \"$in\" in\n"
                             "  *bad*) echo \"$in: not an image\" >&2; exit 1;;\n"
                             "  *huge*) exec /usr/bin/python3 -c 'x = b\"x\" * (512 << 20)';;\n"
                             "esac\n"
                             "{ cat \"$in\"; echo \"$cmd $*\"; } > \"$out.part\" && mv \"$out.part\" \"$out\"\n";
    fs::permissions(script, fs::perms::owner_all);
    for (const char* name : {"a.png", "b.PNG", "c.jpg", "bad.png", "notes.txt"}) {
      std::ofstream(root / "in" / name) << "pixels of " << name << "\n";
    }
    options.executable = script.string();
    options.command = "vectorize";
    options.command_args = {"--threads", "1"};
    options.inputs = {(root / "in").string()};
    options.input_extensions = {"png", "jpg"};
    options.output_dir = (root / "out").string();
    options.output_extension = "sdvi";
    options.jobs = 2;
    options.report_path = (root / "report.jsonl").string();
    options.quiet = true;
  }
  ~Fixture() { fs::remove_all(root); }

  std::vector<nlohmann::json> Report() const {
    std::vector<nlohmann::json> lines;
    std::ifstream in(root / "report.jsonl");
    for (std::string line; std::getline(in, line);) lines.push_back(nlohmann::json::parse(line));
    return lines;
  }
  std::string Read(const fs::path& p) const {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
};

}  // namespace

TEST_CASE("a directory expands to its image files, sorted, one output each", "[batch]") {
  Fixture f;
  auto jobs = sdvi::cli::PlanBatch(f.options);
  REQUIRE(jobs.ok());
  std::vector<std::string> names;
  for (const auto& j : *jobs) names.push_back(fs::path(j.input).filename().string() + ">" + fs::path(j.output).filename().string());
  CHECK(names == std::vector<std::string>{"a.png>a.sdvi", "b.PNG>b.sdvi", "bad.png>bad.sdvi", "c.jpg>c.sdvi"});
}

TEST_CASE("a failing input is reported, the others finish, a rerun skips them", "[batch]") {
  Fixture f;
  auto jobs = sdvi::cli::PlanBatch(f.options);
  REQUIRE(jobs.ok());
  auto summary = sdvi::cli::RunBatch(f.options, *jobs);
  REQUIRE(summary.ok());
  CHECK(summary->ok == 3);
  CHECK(summary->failed == 1);
  CHECK(summary->skipped == 0);
  CHECK(f.Read(f.root / "out" / "a.sdvi") == "pixels of a.png\nvectorize --threads 1 --quiet\n");
  CHECK_FALSE(fs::exists(f.root / "out" / "bad.sdvi"));
  auto lines = f.Report();
  REQUIRE(lines.size() == 4);
  int failed = 0;
  for (const auto& l : lines) {
    if (l["status"] == "failed") {
      ++failed;
      CHECK(l["exit_code"] == 1);
      CHECK(l["error"].get<std::string>().find("bad.png: not an image") != std::string::npos);
    } else {
      CHECK(l["status"] == "ok");
    }
  }
  CHECK(failed == 1);
  // No stray error files are left in the output directory.
  int files = 0;
  for (const auto& e : fs::directory_iterator(f.root / "out")) files += e.is_regular_file() ? 1 : 0;
  CHECK(files == 3);

  auto again = sdvi::cli::RunBatch(f.options, *jobs);
  REQUIRE(again.ok());
  CHECK(again->skipped == 3);
  CHECK(again->failed == 1);
  CHECK(f.Report().size() == 8);
}

TEST_CASE("globs and files combine; two inputs writing one output are refused", "[batch]") {
  Fixture f;
  f.options.inputs = {(f.root / "in" / "*.png").string(), (f.root / "in" / "c.jpg").string()};
  auto jobs = sdvi::cli::PlanBatch(f.options);
  REQUIRE(jobs.ok());
  CHECK(jobs->size() == 3);  // a.png, bad.png (case-sensitive glob), c.jpg
  std::ofstream(f.root / "in" / "a.jpg") << "another a\n";
  f.options.inputs = {(f.root / "in" / "a.png").string(), (f.root / "in" / "a.jpg").string()};
  auto clash = sdvi::cli::PlanBatch(f.options);
  REQUIRE_FALSE(clash.ok());
  CHECK(clash.status().code() == sdvi::StatusCode::kInvalidArgument);
  CHECK(clash.status().message().find("would both write") != std::string::npos);
  f.options.inputs = {(f.root / "in" / "a.png").string()};
  f.options.output_dir = (f.root / "in").string();
  f.options.output_extension = "png";
  auto self = sdvi::cli::PlanBatch(f.options);
  REQUIRE_FALSE(self.ok());
  CHECK(self.status().code() == sdvi::StatusCode::kInvalidArgument);
  CHECK(self.status().message().find("its own output") != std::string::npos);
  f.options.inputs = {(f.root / "in" / "missing.png").string()};
  auto missing = sdvi::cli::PlanBatch(f.options);
  REQUIRE_FALSE(missing.ok());
  CHECK(missing.status().code() == sdvi::StatusCode::kNotFound);
}

TEST_CASE("the per-job memory limit stops a job that needs more", "[batch]") {
  Fixture f;
  std::ofstream(f.root / "in" / "huge.png") << "big\n";
  f.options.inputs = {(f.root / "in" / "huge.png").string(), (f.root / "in" / "a.png").string()};
  f.options.max_memory_bytes = uint64_t(128) << 20;
  auto jobs = sdvi::cli::PlanBatch(f.options);
  REQUIRE(jobs.ok());
  auto summary = sdvi::cli::RunBatch(f.options, *jobs);
  REQUIRE(summary.ok());
  CHECK(summary->failed == 1);
  CHECK(summary->ok == 1);
  CHECK_FALSE(fs::exists(f.root / "out" / "huge.sdvi"));
  bool named = false;
  for (const auto& l : f.Report()) {
    if (l["status"] == "failed") {
      CHECK(l["exit_code"].get<int>() > 128);  // a signal
      named = l["error"].get<std::string>().find("over the memory limit of 128 MiB per job") != std::string::npos;
    }
  }
  CHECK(named);
  // Without the limit the same job succeeds (it exits 0 without writing: python only allocates).
  f.options.max_memory_bytes = 0;
  f.options.inputs = {(f.root / "in" / "huge.png").string()};
  auto unlimited = sdvi::cli::RunBatch(f.options, *sdvi::cli::PlanBatch(f.options));
  REQUIRE(unlimited.ok());
  CHECK(unlimited->ok == 1);
}
