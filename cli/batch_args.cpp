// SPDX-License-Identifier: GPL-3.0-or-later
// Batch mode on the command line: the options AddInputs adds, and the batch a command runs
// when -O DIR is given (README "Many images"; the runner's rules are in batch.h).
#include "batch_args.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>
#include <thread>

#include "batch.h"

namespace sdvi::cli {
namespace {

// One command's batch options, bound by AddInputs and read when it runs.
struct BatchState {
  BatchSpec spec;
  std::string* input = nullptr;     // the command's own input (single mode)
  std::vector<std::string> inputs;  // the positional arguments
  std::string output_dir, report;
  int jobs = 1;
  uint64_t max_memory = 0;
  bool overwrite = false;
  CLI::Option *inputs_opt = nullptr, *output = nullptr, *output_dir_opt = nullptr, *jobs_opt = nullptr,
              *report_opt = nullptr, *memory_opt = nullptr, *overwrite_opt = nullptr;

  bool Owns(const CLI::Option* o) const {
    return o == inputs_opt || o == output || o == output_dir_opt || o == jobs_opt || o == report_opt ||
           o == memory_opt || o == overwrite_opt;
  }
};

std::map<const CLI::App*, std::unique_ptr<BatchState>>& States() {
  static std::map<const CLI::App*, std::unique_ptr<BatchState>> states;
  return states;
}

constexpr uint64_t kMinJobMemory = uint64_t{64} << 20;

// The options every job gets: those given on the command line, as given, except the input,
// -o, the batch's own and --quiet (RunBatch adds it); long names take their value after '='
// so that a value starting with '-' stays a value.
std::vector<std::string> JobArguments(const CLI::App* command, const BatchState& s) {
  std::vector<std::string> args;
  const CLI::Option* quiet = command->get_option_no_throw("--quiet");
  for (const CLI::Option* opt : command->get_options()) {
    if (opt->count() == 0 || s.Owns(opt) || opt == quiet || opt == command->get_help_ptr()) continue;
    const std::string name = opt->get_name();
    const bool long_name = name.rfind("--", 0) == 0;
    const std::vector<std::string>& results = opt->results();
    if (opt->get_expected_min() == 0) {  // a flag: its value unless it is plain "true"
      for (const std::string& r : results) args.push_back(r == "true" || !long_name ? name : name + "=" + r);
      continue;
    }
    const size_t size = size_t(std::max(1, opt->get_type_size_max()));
    for (size_t i = 0; i < results.size(); i += size) {
      if (size == 1 && long_name) {
        args.push_back(name + "=" + results[i]);
        continue;
      }
      args.push_back(name);
      for (size_t j = i; j < std::min(results.size(), i + size); ++j) args.push_back(results[j]);
    }
  }
  return args;
}

std::string SelfExecutable() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("sdvi") : self.string();
}

}  // namespace

CLI::Option* AddInputs(CLI::App* command, std::string& input, const std::string& what, const BatchSpec& spec) {
  auto state = std::make_unique<BatchState>();
  BatchState& s = *state;
  s.spec = spec;
  s.input = &input;
  s.output = command->get_option_no_throw("--output");
  if (s.output == nullptr) throw std::logic_error(command->get_name() + ": AddInputs needs AddOutput first");
  s.output->required(false);
  MarkInput(command, input);
  const std::string type = spec.input_extensions.size() == 1 ? "IN." + spec.input_extensions[0] : "IN";
  s.inputs_opt = command->add_option("input", s.inputs, what + "; several files, directories or globs with -O DIR")
                     ->required()
                     ->default_str("")
                     ->type_name(type);
  const char* group = "Batch (several inputs, -O DIR; README \"Many images\")";
  s.output_dir_opt =
      command
          ->add_option("-O,--output-dir", s.output_dir,
                       "write DIR/STEM." + spec.output_extension +
                           " for every input, one job each; an existing output is skipped (resumable)")
          ->type_name("DIR")
          ->excludes(s.output)
          ->group(group);
  s.jobs_opt = command->add_option("-j,--jobs", s.jobs, "jobs at once (each a process; its --threads default "
                                                        "is the cores divided by N)")
                   ->check(CLI::Range(1, 256))
                   ->needs(s.output_dir_opt)
                   ->group(group);
  s.report_opt = command
                     ->add_option("--batch-report", s.report,
                                  "append one JSON line per input: input, output, status ok|skipped|failed, "
                                  "exit code, seconds, peak RSS, error")
                     ->type_name("R.jsonl")
                     ->needs(s.output_dir_opt)
                     ->group(group);
  s.memory_opt = command
                     ->add_option("--max-memory-per-job", s.max_memory,
                                  "resident memory limit of each job in bytes, or with a unit: 512M, 2G (0: none); "
                                  "a job over it is stopped and fails")
                     ->transform(CLI::AsSizeValue(false))
                     ->type_name("SIZE")
                     ->needs(s.output_dir_opt)
                     ->group(group);
  s.overwrite_opt = command->add_flag("--overwrite", s.overwrite, "redo inputs whose output exists")
                        ->needs(s.output_dir_opt)
                        ->group(group);
  CLI::Option* inputs = s.inputs_opt;
  States()[command] = std::move(state);
  return inputs;
}

bool RunBatchIfAsked(CLI::App* command, const std::vector<std::string>& other_outputs, int& exit_code) {
  const auto found = States().find(command);
  if (found == States().end()) return false;
  BatchState& s = *found->second;
  const std::string name = command->get_name();
  auto usage = [&](const std::string& message) {
    exit_code = ReportUsage(name, message);
    return true;
  };
  if (s.output_dir_opt->count() == 0) {  // the single-input command
    if (s.inputs.size() > 1) return usage("several inputs need -O DIR (batch mode)");
    if (s.output->count() == 0) return usage("--output is required (or -O DIR for a batch)");
    std::error_code ec;
    if (std::filesystem::is_directory(s.inputs.front(), ec)) {
      return usage(s.inputs.front() + " is a directory: -O DIR converts the files in it");
    }
    *s.input = s.inputs.front();
    return false;
  }
  for (const std::string& in : s.inputs) {
    if (in == "-") return usage("'-' (standard input) is not a batch input");
  }
  if (!other_outputs.empty()) {
    return usage(other_outputs.front() + ": an output file of its own is for one input; a batch "
                 "writes --batch-report");
  }
  std::vector<std::string> single_only = s.spec.single_only;
  single_only.push_back("--json");
  for (const std::string& option : single_only) {
    const CLI::Option* o = command->get_option_no_throw(option);
    if (o != nullptr && o->count() > 0) return usage(option + " is for one input, not a batch");
  }
  if (s.max_memory != 0 && s.max_memory < kMinJobMemory) {
    return usage("--max-memory-per-job must be 0 or at least 64M");
  }

  BatchOptions options;
  options.executable = SelfExecutable();
  options.command = name;
  options.command_args = JobArguments(command, s);
  const CLI::Option* threads = command->get_option_no_throw("--threads");
  if (threads != nullptr && threads->count() == 0 && s.jobs > 1) {
    // Jobs share the cores; outputs do not depend on the thread count.
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    options.command_args.push_back("--threads=" + std::to_string(std::max(1, cores / s.jobs)));
  }
  options.inputs = s.inputs;
  options.input_extensions = s.spec.input_extensions;
  options.output_dir = s.output_dir;
  options.output_extension = s.spec.output_extension;
  const CLI::Option* format =
      s.spec.format_option.empty() ? nullptr : command->get_option_no_throw(s.spec.format_option);
  if (format != nullptr && format->count() > 0) options.output_extension = format->results().back();
  options.jobs = s.jobs;
  options.max_memory_bytes = s.max_memory;
  options.skip_existing = !s.overwrite;
  options.report_path = s.report;
  const CLI::Option* quiet = command->get_option_no_throw("--quiet");
  options.quiet = quiet != nullptr && quiet->count() > 0 && quiet->as<bool>();

  StatusOr<std::vector<BatchJob>> jobs = PlanBatch(options);
  if (!jobs.ok()) {
    exit_code = ReportError(name, jobs.status());
    return true;
  }
  StatusOr<BatchSummary> summary = RunBatch(options, *jobs);
  if (!summary.ok()) {
    exit_code = ReportError(name, summary.status());
    return true;
  }
  if (!options.quiet) {
    std::printf("sdvi %s: %d done, %d skipped (output exists), %d failed\n", name.c_str(), summary->ok,
                summary->skipped, summary->failed);
  }
  exit_code = summary->failed > 0 ? kExitFailure : kExitOk;
  return true;
}

}  // namespace sdvi::cli
