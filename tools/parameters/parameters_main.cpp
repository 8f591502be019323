// scan_context_parameters: prints or writes the files written from the settings tables of both nodes
// (generated_files.h): doc/parameters.md (the default), config/default.yaml, config/pose_graph.yaml and
// cfg/LoopClosure.cfg. `rosrun scan_context_loop scan_context_parameters --write $(rospack find
// scan_context_loop)` rewrites them all.
#include <cstdio>
#include <string>

#include "cli.h"
#include "generated_files.h"
#include "parameters_page.h"

int main(int argc, char** argv) {
  using namespace scan_context_loop;
  std::string (*print)() = parametersPage;
  std::string write_dir;
  cli::Parser cli("scan_context_parameters",
                  "Prints a file written from the settings tables of the loop_closure and pose_graph nodes: "
                  "doc/parameters.md unless an option names another, or writes them all (--write).");
  for (const auto& file : generatedFiles()) {
    cli.flag(file.option, "print " + file.path, [&print, &file] { print = file.text; });
  }
  cli.option("--write", "PACKAGE_DIR", "write every file into the package's folder (a checkout's root)", &write_dir);
  if (const int status = cli.parse(argc, argv); status >= 0) return status;
  if (!write_dir.empty()) {
    std::string error;
    if (writeGeneratedFiles(write_dir, &error)) return 0;
    std::fprintf(stderr, "scan_context_parameters: %s\n", error.c_str());
    return 1;
  }
  std::fputs(print().c_str(), stdout);
  return 0;
}
