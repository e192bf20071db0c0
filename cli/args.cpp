// SPDX-License-Identifier: GPL-3.0-or-later
#include "args.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <map>
#include <new>

#include "batch_args.h"
#include "sdvi/file_util.h"
#include "sdvi/raster_io.h"

namespace sdvi::cli {
namespace {

// What SetAction applies before a command runs: the files it reads and writes
// (MarkInput, MarkOutput) and its memory limit (--max-memory).
struct CommandSetup {
  std::vector<const std::string*> inputs, outputs;
  uint64_t max_memory = 0;
  const std::string* output = nullptr;  // -o (AddOutput)
  std::function<bool()> raster_codecs;  // UsesRasterCodecs: whether this run opens them
};
std::map<const CLI::App*, CommandSetup>& Setup() {
  static std::map<const CLI::App*, CommandSetup> setups;
  return setups;
}

std::string Mebibytes(uint64_t bytes) { return std::to_string(bytes >> 20) + " MiB"; }

// The process's address space now (its shared libraries and start-up allocations).
uint64_t AddressSpaceNow() {
  unsigned long long pages = 0;
  std::FILE* statm = std::fopen("/proc/self/statm", "r");
  if (statm == nullptr) return 0;
  if (std::fscanf(statm, "%llu", &pages) != 1) pages = 0;
  std::fclose(statm);
  return uint64_t(pages) * uint64_t(::sysconf(_SC_PAGESIZE));
}

// Lets the command add at most max_memory bytes of address space to what the process
// holds at start-up (about 0.3 GiB of shared libraries and thread arenas); 0: no limit.
Status LimitMemory(uint64_t max_memory) {
  if (max_memory == 0) return Status::Ok();
  struct rlimit limit {};
  if (::getrlimit(RLIMIT_AS, &limit) != 0) return Status::Ok();
  uint64_t total = AddressSpaceNow() + max_memory;
  if (limit.rlim_max != RLIM_INFINITY && total > limit.rlim_max) total = limit.rlim_max;
  limit.rlim_cur = total;
  if (::setrlimit(RLIMIT_AS, &limit) != 0)
    return Status(StatusCode::kInvalidArgument, "--max-memory " + Mebibytes(max_memory) + ": cannot set the limit");
  return Status::Ok();
}

Status CheckOutputs(const CLI::App* command) {
  const CommandSetup& setup = Setup()[command];
  std::vector<std::string> inputs;
  for (const std::string* in : setup.inputs)
    if (!in->empty()) inputs.push_back(*in);
  for (const std::string* out : setup.outputs)
    if (!out->empty()) SDVI_RETURN_IF_ERROR(CheckOutputPath(*out, inputs));
  return Status::Ok();
}

// The output files given other than -o (a batch refuses them: every job would write them).
std::vector<std::string> OtherOutputs(const CLI::App* command) {
  const CommandSetup& setup = Setup()[command];
  std::vector<std::string> given;
  for (const std::string* out : setup.outputs)
    if (out != setup.output && !out->empty()) given.push_back(*out);
  return given;
}

}  // namespace

CLI::App* AddCommand(CLI::App& app, const std::string& name, const std::string& description,
                     const std::vector<std::string>& examples) {
  CLI::App* command = app.add_subcommand(name, description);
  command->option_defaults()->always_capture_default();
  std::string footer = "\nExamples:";
  for (const std::string& e : examples) footer += "\n  " + e;
  footer += "\n\nExit codes: 0 success, 1 failure, 2 usage error.";
  command->footer(footer);
  Setup()[command].max_memory = DefaultMaxMemory();
  command->add_option("--max-memory", Setup()[command].max_memory,
                      "limit the memory the command may allocate (address space beyond what the program holds "
                      "at start) to SIZE, e.g. 2G, 512M; 0 = no limit; default: 3/4 of the physical memory")
      ->transform(CLI::AsSizeValue(false).description(""))
      ->default_str(Mebibytes(DefaultMaxMemory()) + " here")
      ->type_name("SIZE");
  return command;
}

uint64_t DefaultMaxMemory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return 0;
  return uint64_t(pages) * uint64_t(page) / 4 * 3;
}

void SetAction(CLI::App* command, Outcome& outcome, std::function<int()> run) {
  command->callback([command, &outcome, run = std::move(run)] {
    try {
      if (RunBatchIfAsked(command, OtherOutputs(command), outcome.exit_code)) return;
      Status ready = CheckOutputs(command);
      const CommandSetup& setup = Setup()[command];
      // Before the limit (OpenRasterCodecs); a failure here is reported by the decode itself.
      if (ready.ok() && setup.raster_codecs && setup.raster_codecs()) {
        std::vector<std::string> rasters;  // the inputs that may be rasters (not .sdvi files)
        for (const std::string* in : setup.inputs)
          if (!in->empty() && FileExtension(*in) != "sdvi") rasters.push_back(*in);
        (void)OpenRasterCodecs(rasters);
      }
      if (ready.ok()) ready = LimitMemory(setup.max_memory);
      outcome.exit_code = ready.ok() ? run() : ReportError(command->get_name(), ready);
    } catch (const std::bad_alloc&) {
      const CommandSetup& setup = Setup()[command];
      std::string message = "out of memory";
      if (!setup.inputs.empty() && !setup.inputs.front()->empty())
        message = *setup.inputs.front() + ": " + message;  // the main input
      if (setup.max_memory) message += " (--max-memory " + Mebibytes(setup.max_memory) + ")";
      outcome.exit_code = ReportError(command->get_name(), Status(StatusCode::kLimitExceeded, message));
    } catch (const std::exception& e) {
      outcome.exit_code =
          ReportError(command->get_name(), Status(StatusCode::kInternal, e.what()));
    }
  });
}

void UsesRasterCodecs(CLI::App* command, const std::string* when_given) {
  Setup()[command].raster_codecs = [when_given] { return when_given == nullptr || !when_given->empty(); };
}

void MarkInput(CLI::App* command, const std::string& path) { Setup()[command].inputs.push_back(&path); }
void MarkOutput(CLI::App* command, const std::string& path) { Setup()[command].outputs.push_back(&path); }

CLI::Option* AddOutput(CLI::App* command, std::string& path, const std::string& what) {
  MarkOutput(command, path);
  Setup()[command].output = &path;
  return command->add_option("-o,--output", path, what + " ('-' writes standard output)")
      ->required()
      ->type_name("FILE");
}

CLI::Option* AddQuiet(CLI::App* command, bool& quiet) {
  return command->add_flag("-q,--quiet", quiet, "no progress display and no summary line");
}

CLI::Option* AddJson(CLI::App* command, bool& json) {
  return command->add_flag("--json", json, "print the result as JSON on standard output");
}

int ReportError(const std::string& command, const Status& status) {
  std::fprintf(stderr, "sdvi %s: %s\n", command.c_str(), status.ToString().c_str());
  return kExitFailure;
}

int ReportUsage(const std::string& command, const std::string& message) {
  std::fprintf(stderr, "sdvi %s: %s\nRun 'sdvi %s --help' for the options.\n", command.c_str(),
               message.c_str(), command.c_str());
  return kExitUsage;
}

std::FILE* SummaryStream(const std::string& output) {
  return IsStdStream(output) ? stderr : stdout;
}

}  // namespace sdvi::cli
