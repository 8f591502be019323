// The standalone base-station node: loads the same nodelet class in-process.
#include "shared/standalone.h"

int main(int argc, char** argv) {
  return scan_context_loop::runNodeletStandalone(argc, argv, "team_base", "scan_context_loop/TeamBaseNodelet");
}
