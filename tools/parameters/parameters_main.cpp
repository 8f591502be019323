// scan_context_parameters: prints doc/parameters.md, the parameters of both nodes from their settings
// tables (`rosrun scan_context_loop scan_context_parameters > doc/parameters.md`).
#include <cstdio>

#include "cli.h"
#include "parameters_page.h"

int main(int argc, char** argv) {
  const scan_context_loop::cli::Parser cli("scan_context_parameters",
                                           "Prints doc/parameters.md: every parameter of the loop_closure and "
                                           "pose_graph nodes, from their settings tables.");
  if (const int status = cli.parse(argc, argv); status >= 0) return status;
  std::fputs(scan_context_loop::parametersPage().c_str(), stdout);
  return 0;
}
