// Placeholder until the module's command lands; replaced by its owner.
#include <cstdio>
#include "commands.h"
namespace sdvi::cli {
int RunSubdivide(const CommandArgs&) { std::fprintf(stderr, "sdvi: command not built yet\n"); return 2; }
}  // namespace sdvi::cli
