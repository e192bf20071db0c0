// Placeholder until the module's command lands; replaced by its owner.
#include <cstdio>
#include "commands.h"
namespace sdvi::cli {
int RunConvert(const CommandArgs&) { std::fprintf(stderr, "sdvi: command not built yet\n"); return 2; }
int RunInfo(const CommandArgs&) { std::fprintf(stderr, "sdvi: command not built yet\n"); return 2; }
}  // namespace sdvi::cli
