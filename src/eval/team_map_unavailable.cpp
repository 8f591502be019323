// The team's map in a build without the pose-graph backend: nothing is computed, and the note says why.
#include "scan_context_loop/eval/team_map.h"

namespace scan_context_loop {
namespace eval {

TeamMap mergeTeamMap(const TeamSequence&, const TeamEvaluation&, const Config&) {
  TeamMap map;
  map.note = "built without the pose-graph backend (Ceres): no map of the team";
  return map;
}

}  // namespace eval
}  // namespace scan_context_loop
