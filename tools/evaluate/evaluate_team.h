// scan_context_evaluate --team: a simulated team's sequence scored offline (eval/team_evaluation.h).
#pragma once

#include <string>

#include "scan_context_loop/core/config.h"
#include "scan_context_loop/eval/sequence.h"

namespace scan_context_loop {
namespace tools {

/// Loads the team in `team_dir` (each robot's sequence with `options`), runs and scores it, writes
/// OUT_DIR/team.json, inter_robot_loops.csv and per robot OUT_DIR/<robot>/ (results.csv, metrics.json,
/// trajectory.csv, verifications.csv as a single run writes them), prints the summary and last
/// `output: OUT_DIR`. Returns the exit status.
int evaluateTeam(const std::string& team_dir, const std::string& out_dir, const Config& config,
                 const eval::SequenceOptions& options, double revisit_radius);

}  // namespace tools
}  // namespace scan_context_loop
