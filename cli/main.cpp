// SPDX-License-Identifier: GPL-3.0-or-later
// sdvi: the command-line tool. CLI11 parses the subcommand and its options; the
// subcommand's callback does the work and sets the exit code (args.h).
#include <malloc.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

#include "commands.h"

namespace {

// `sdvi help [COMMAND]`: the general help, or one command's.
void RegisterHelp(CLI::App& app, sdvi::cli::Outcome& outcome) {
  CLI::App* help = app.add_subcommand("help", "show the help of a command (or of sdvi)");
  auto topic = std::make_shared<std::string>();
  help->add_option("command", *topic, "the command to explain");
  help->callback([&app, topic, &outcome] {
    if (topic->empty()) {
      std::cout << app.help();
      return;
    }
    for (CLI::App* sub : app.get_subcommands({})) {
      if (sub->get_name() == *topic) {
        std::cout << sub->help(app.get_name());
        return;
      }
    }
    outcome.exit_code = sdvi::cli::ReportUsage("help", "unknown command '" + *topic + "'");
  });
}

// The fitting commands' large per-pixel arrays on transparent huge pages (spec/METHOD.md 6,
// "Memory pages"). Where the kernel backs memory with huge pages only on request (THP mode
// "madvise"), glibc's malloc makes that request when GLIBC_TUNABLES holds
// glibc.malloc.hugetlb=1, a setting it reads at start-up only: `vectorize` and `import-svg`
// run themselves again once with it added. A GLIBC_TUNABLES that already names
// glibc.malloc.hugetlb (either value) is the user's choice and is kept; when the exec fails
// the command runs as it is.
void RunAgainWithHugePages(char** argv) {
  const std::string command = argv[1];
  if (command != "vectorize" && command != "import-svg") return;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  const std::string given = tunables != nullptr ? tunables : "";
  if (given.find("glibc.malloc.hugetlb") != std::string::npos) return;
  std::ifstream mode_file("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string mode;
  if (!std::getline(mode_file, mode) || mode.find("[madvise]") == std::string::npos) return;
  const std::string wanted = (given.empty() ? "" : given + ":") + "glibc.malloc.hugetlb=1";
  if (::setenv("GLIBC_TUNABLES", wanted.c_str(), 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  if (tunables != nullptr) {
    ::setenv("GLIBC_TUNABLES", given.c_str(), 1);
  } else {
    ::unsetenv("GLIBC_TUNABLES");
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2) RunAgainWithHugePages(argv);
#ifdef M_ARENA_MAX
  // One malloc arena for all threads (spec/METHOD.md 6, "Memory pages"): the blocks a phase's
  // worker threads free are reused by the next phase instead of held in per-thread arenas.
  mallopt(M_ARENA_MAX, 1);
#endif
#if defined(M_MMAP_THRESHOLD) && defined(M_TRIM_THRESHOLD)
  // Freed heap memory kept for the next phase and round (spec/METHOD.md 6, "Memory pages"):
  // blocks up to 32 MiB (glibc's largest threshold) from the heap, whose top is not handed
  // back to the kernel (explicit malloc_trim calls still do): each round's arrays were
  // fresh pages the kernel clears again (sea 4K: 3.9 -> 1.7 s of system time).
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
  CLI::App app("sdvi: images as curvilinear-feature-driven subdivision surfaces.\n"
               "Vectorize rasters into resolution-free .sdvi files, render them at any size, "
               "export them to glTF, compress them.",
               "sdvi");
  app.set_version_flag("-V,--version", std::string("sdvi ") + SDVI_VERSION);
  app.require_subcommand(1);
  app.footer("\nRun 'sdvi help COMMAND' or 'sdvi COMMAND --help' for a command's options.\n"
             "Exit codes: 0 success, 1 failure, 2 usage error.");
  sdvi::cli::Outcome outcome;
  sdvi::cli::RegisterVectorize(app, outcome);
  sdvi::cli::RegisterImportSvg(app, outcome);
  sdvi::cli::RegisterRender(app, outcome);
  sdvi::cli::RegisterCompare(app, outcome);
  sdvi::cli::RegisterInfo(app, outcome);
  sdvi::cli::RegisterConvert(app, outcome);
  sdvi::cli::RegisterSubdivide(app, outcome);
  sdvi::cli::RegisterExportGltf(app, outcome);
  sdvi::cli::RegisterCompress(app, outcome);
  sdvi::cli::RegisterDecompress(app, outcome);
  sdvi::cli::RegisterExportPdf(app, outcome);
  sdvi::cli::RegisterExportSvg(app, outcome);
  sdvi::cli::RegisterEdit(app, outcome);
  sdvi::cli::RegisterSample(app, outcome);
  RegisterHelp(app, outcome);

  if (argc < 2) {
    std::cerr << app.help();
    return sdvi::cli::kExitUsage;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::string command = "";
    for (CLI::App* sub : app.get_subcommands()) command = sub->get_name();
    std::fprintf(stderr, "sdvi%s%s: %s\nRun 'sdvi %s--help' for the options.\n",
                 command.empty() ? "" : " ", command.c_str(), e.what(),
                 command.empty() ? "" : (command + " ").c_str());
    return sdvi::cli::kExitUsage;
  }
  return outcome.exit_code;
}
