// The trajectory correction in a build without the reference pose-graph backend (no Ceres): the
// evaluator still scores the loops, and trajectory_error.json says why no correction was computed.
#include "scan_context_loop/eval/trajectory_correction.h"

namespace scan_context_loop {
namespace eval {

TrajectoryCorrection correctTrajectory(const Sequence&, const Evaluation&, const Config&, const PoseGraphConfig&) {
  TrajectoryCorrection c;
  c.note = "built without the pose-graph backend (Ceres was not found)";
  return c;
}

bool saveCorrectedMap(const std::string&, const Sequence&, const TrajectoryCorrection&, std::string*,
                      std::string* error) {
  *error = "no corrected map: built without the pose-graph backend (Ceres was not found)";
  return false;
}

}  // namespace eval
}  // namespace scan_context_loop
