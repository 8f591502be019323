// The trajectory correction in a build without the reference pose-graph backend (no Ceres): the
// evaluator still scores the loops, and trajectory_error.json says why no correction was computed.
#include "scan_context_loop/eval/graph_study.h"
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

bool readGraphVariants(const std::string&, std::vector<GraphVariant>*, std::string* error) {
  *error = "no graph study: built without the pose-graph backend (Ceres was not found)";
  return false;
}

std::vector<GraphStudyRow> runGraphStudy(const Sequence&, const Evaluation&, const Config&,
                                         const std::vector<GraphVariant>&) {
  return {};
}

bool writeGraphStudyCsv(const std::string&, const std::vector<GraphStudyRow>&, std::string*) { return true; }

}  // namespace eval
}  // namespace scan_context_loop
