// The standalone loop-closure node: loads the same nodelet class in-process.
#include "shared/standalone.h"

int main(int argc, char** argv) {
  return scan_context_loop::runNodeletStandalone(argc, argv, "loop_closure", "scan_context_loop/LoopClosureNodelet");
}
