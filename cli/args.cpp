// SPDX-License-Identifier: GPL-3.0-or-later
#include "args.h"

#include <cstdio>
#include <map>
#include <new>

#include "sdvi/file_util.h"

namespace sdvi::cli {
namespace {

// The files each command reads and writes (MarkInput, MarkOutput), read when it runs.
struct FileRoles {
  std::vector<const std::string*> inputs, outputs;
};
std::map<const CLI::App*, FileRoles>& Roles() {
  static std::map<const CLI::App*, FileRoles> roles;
  return roles;
}

Status CheckOutputs(const CLI::App* command) {
  const FileRoles& roles = Roles()[command];
  std::vector<std::string> inputs;
  for (const std::string* in : roles.inputs)
    if (!in->empty()) inputs.push_back(*in);
  for (const std::string* out : roles.outputs)
    if (!out->empty()) SDVI_RETURN_IF_ERROR(CheckOutputPath(*out, inputs));
  return Status::Ok();
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
  return command;
}

void SetAction(CLI::App* command, Outcome& outcome, std::function<int()> run) {
  command->callback([command, &outcome, run = std::move(run)] {
    try {
      const Status outputs = CheckOutputs(command);
      outcome.exit_code = outputs.ok() ? run() : ReportError(command->get_name(), outputs);
    } catch (const std::bad_alloc&) {
      outcome.exit_code = ReportError(command->get_name(),
                                      Status(StatusCode::kLimitExceeded, "out of memory"));
    } catch (const std::exception& e) {
      outcome.exit_code =
          ReportError(command->get_name(), Status(StatusCode::kInternal, e.what()));
    }
  });
}

void MarkInput(CLI::App* command, const std::string& path) { Roles()[command].inputs.push_back(&path); }
void MarkOutput(CLI::App* command, const std::string& path) { Roles()[command].outputs.push_back(&path); }

CLI::Option* AddOutput(CLI::App* command, std::string& path, const std::string& what) {
  MarkOutput(command, path);
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
