// SPDX-License-Identifier: GPL-3.0-or-later
// What every sdvi subcommand shares on top of CLI11: the exit codes, how a subcommand is
// declared (description, options with meanings and defaults, examples), and how errors
// are reported. README "Exit codes" documents the codes.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sdvi/status.h"

namespace sdvi::cli {

inline constexpr int kExitOk = 0;       // success
inline constexpr int kExitFailure = 1;  // the work failed: bad input, I/O error, a limit
inline constexpr int kExitUsage = 2;    // the command line is wrong: unknown option, bad value

// The exit code of the subcommand that ran; its callback sets it.
struct Outcome {
  int exit_code = kExitOk;
};

// Adds subcommand `name` to app with a one-line description and a footer of examples
// (one command line per entry). Every option added to it shows its default in --help.
// Every command gets --max-memory SIZE: the address space the process may add to what it
// holds at start is limited to it before the action runs (default DefaultMaxMemory()), so a runaway allocation becomes a
// clean limit_exceeded error instead of the system running out of memory.
CLI::App* AddCommand(CLI::App& app, const std::string& name, const std::string& description,
                     const std::vector<std::string>& examples);

// Three quarters of the machine's physical memory: the default of --max-memory.
uint64_t DefaultMaxMemory();

// Makes run the subcommand's action: its return value becomes the exit code; an exception
// escaping it (a bug or out of memory) is reported as a failure, never a crash.
void SetAction(CLI::App* command, Outcome& outcome, std::function<int()> run);

// Adds "-o,--output FILE" (required) with the given meaning; "-" is standard output.
// The path is marked as an output (MarkOutput).
CLI::Option* AddOutput(CLI::App* command, std::string& path, const std::string& what);

// Declare the files a command reads and writes. Before its action runs, every non-empty
// output is checked against every input (CheckOutputPath: its directory exists and is
// writable, it is not a directory, it is not one of the inputs), so a command whose output
// cannot be written fails before any work and leaves nothing behind.
void MarkInput(CLI::App* command, const std::string& path);
void MarkOutput(CLI::App* command, const std::string& path);
// The command decodes raster images (PNG, JPEG, ...), always or, with when_given, only when
// that option is non-empty: the raster decoders are opened before its memory limit is set
// (sdvi/raster_io.h, OpenRasterCodecs). Writing PNGs needs nothing opened (libpng is linked).
void UsesRasterCodecs(CLI::App* command, const std::string* when_given = nullptr);
// Batch mode (README "Many images"): what a directory contributes to a batch and what each
// job writes.
struct BatchSpec {
  std::vector<std::string> input_extensions;  // lower case, no dot: "png", "sdvi"
  std::string output_extension;               // each job writes DIR/STEM.<this>
  std::string format_option;                  // when given, its value is the extension ("--format")
  std::vector<std::string> single_only;       // options that name one output ("--debug-dir")
};

// Adds the positional input of a command that also runs over many files: "IN..." (required,
// marked as an input). One input with -o is the command itself; several inputs, directories
// (their files with one of spec.input_extensions) or globs with -O DIR run it once per file
// (cli/batch.h), each job the same command with -o DIR/STEM.EXT and the other options as
// given, with -j N, --batch-report, --max-memory-per-job and --overwrite. -o and -O exclude
// each other; one of them is required. Call after AddOutput; SetAction runs the batch.
CLI::Option* AddInputs(CLI::App* command, std::string& input, const std::string& what, const BatchSpec& spec);

// Adds "--quiet" (no progress, no summary line).
CLI::Option* AddQuiet(CLI::App* command, bool& quiet);
// Adds "--json" (the result as JSON on standard output).
CLI::Option* AddJson(CLI::App* command, bool& json);

// Prints "sdvi <command>: <code>: <message>" to stderr; returns kExitFailure.
int ReportError(const std::string& command, const Status& status);
// Prints "sdvi <command>: <message>" and a pointer to --help to stderr; returns kExitUsage.
int ReportUsage(const std::string& command, const std::string& message);

// Where a command's human-readable summary goes: stdout, or stderr when stdout carries
// the output itself ("-o -").
std::FILE* SummaryStream(const std::string& output);

}  // namespace sdvi::cli
