// SPDX-License-Identifier: GPL-3.0-or-later
// The command-line side of batch mode (AddInputs in args.h; the runner is batch.h).
#pragma once

#include <string>
#include <vector>

#include "args.h"

namespace sdvi::cli {

// Called by SetAction before a command's action. With -O DIR (AddInputs): checks the batch's
// command line, runs the batch, sets exit_code and returns true. Otherwise sets the command's
// input from the positional argument (or sets a usage error and returns true) and returns
// false: the single-input command runs. Commands without AddInputs: false, nothing done.
// other_outputs: output files given besides -o (--report ...), which a batch refuses.
bool RunBatchIfAsked(CLI::App* command, const std::vector<std::string>& other_outputs, int& exit_code);

}  // namespace sdvi::cli
