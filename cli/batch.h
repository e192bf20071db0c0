// SPDX-License-Identifier: GPL-3.0-or-later
// Batch runs of one subcommand over many inputs (`sdvi vectorize A.png B.png DIR/ -O OUT/ -j 2`):
// each input is one job, run as a child process (this executable, the same subcommand, one
// input, `-o OUTDIR/stem.ext`), `jobs` at a time.
//
// Rules:
// - Inputs: files, directories (their files with one of `input_extensions`, sorted) and glob
//   patterns (sorted matches), in the order given. Two inputs that would write the same
//   output, or an output that is its own input, are refused before any job starts.
// - Resumable: an output that exists is complete (every command writes atomically), so its
//   job is skipped (`skip_existing`).
// - Memory: while jobs run, their resident memory (/proc/PID/statm) is read every 20 ms; a
//   job over `max_memory_bytes` (0 = no limit) is killed and fails like any other, its error
//   naming the limit. Resident memory, not an rlimit on the address space: thread stacks,
//   allocator arenas and libraries reserve far more address space than a job uses.
// - A failing job (non-zero exit, signal) is reported with its error text and the others go
//   on. The report gets one JSON line per input as it finishes (input, output, status
//   ok | skipped | failed, exit code, seconds, peak RSS in MiB, error).
// - Output order and file contents do not depend on `jobs`: each job is the same
//   deterministic command.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sdvi/status.h"

namespace sdvi::cli {

struct BatchJob {
  std::string input, output;
};

struct BatchOptions {
  std::string executable;                   // this program (argv[0] resolved)
  std::string command;                      // the subcommand run per input
  std::vector<std::string> command_args;    // options passed to every job (without -o)
  std::vector<std::string> inputs;          // files, directories, globs
  std::vector<std::string> input_extensions;  // lower case, without the dot: "png", "sdvi"
  std::string output_dir;
  std::string output_extension;             // without the dot: "sdvi", "png", "glb"
  int jobs = 1;
  uint64_t max_memory_bytes = 0;            // resident memory per job; 0 = no limit
  bool skip_existing = true;
  std::string report_path;                  // JSON lines, appended; empty = none
  bool quiet = false;                       // no progress bar, no summary
};

struct BatchSummary {
  int ok = 0, skipped = 0, failed = 0;
};

// The jobs for options' inputs (see the rules). Errors: kNotFound (an input that is neither
// a file, a directory nor a pattern that matches), kInvalidArgument (two inputs, one output;
// an input that is its own output).
StatusOr<std::vector<BatchJob>> PlanBatch(const BatchOptions& options);

// Runs the jobs; errors only for the batch itself (output directory, report file, fork).
StatusOr<BatchSummary> RunBatch(const BatchOptions& options, const std::vector<BatchJob>& jobs);

}  // namespace sdvi::cli
