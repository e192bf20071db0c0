// A small argument parser shared by the sdvi subcommands.
//   positional arguments, "--name value", "--name=value", boolean "--flag", "-o FILE".
// Each subcommand declares the options it takes; anything else is an error.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sdvi/status.h"

namespace sdvi::cli {

struct ArgSpec {
  std::set<std::string> valued;  // options that take a value, e.g. "-o", "--levels"
  std::set<std::string> flags;   // boolean options, e.g. "--json", "--quiet"
};

class Args {
 public:
  // Parses args (without the subcommand name) against spec.
  static StatusOr<Args> Parse(const std::vector<std::string>& args, const ArgSpec& spec);

  const std::vector<std::string>& positional() const { return positional_; }
  bool flag(const std::string& name) const { return flags_.count(name) > 0; }
  std::optional<std::string> get(const std::string& name) const;
  // Typed getters: the default when absent, kInvalidArgument when malformed.
  StatusOr<int> GetInt(const std::string& name, int fallback) const;
  StatusOr<double> GetDouble(const std::string& name, double fallback) const;

 private:
  std::vector<std::string> positional_;
  std::set<std::string> flags_;
  std::map<std::string, std::string> values_;
};

// Prints "sdvi <command>: <status message>" to stderr and returns the exit code for it
// (1 for usage errors, 2 for everything else).
int ReportError(const std::string& command, const Status& status);

}  // namespace sdvi::cli
