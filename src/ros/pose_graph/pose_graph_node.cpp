// The standalone pose_graph node: loads the same nodelet class in-process.
#include "shared/standalone.h"

int main(int argc, char** argv) {
  return scan_context_loop::runNodeletStandalone(argc, argv, "pose_graph", "scan_context_loop/PoseGraphNodelet");
}
