// SPDX-License-Identifier: GPL-3.0-or-later
#include "args.h"

#include <cstdio>
#include <new>

#include "sdvi/file_util.h"

namespace sdvi::cli {

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
      outcome.exit_code = run();
    } catch (const std::bad_alloc&) {
      outcome.exit_code = ReportError(command->get_name(),
                                      Status(StatusCode::kLimitExceeded, "out of memory"));
    } catch (const std::exception& e) {
      outcome.exit_code =
          ReportError(command->get_name(), Status(StatusCode::kInternal, e.what()));
    }
  });
}

CLI::Option* AddOutput(CLI::App* command, std::string& path, const std::string& what) {
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
