// Every topic and service name of the loop-closure node, in one place: topics relative to the node's
// namespace (remap them at launch), services in its private one, the team's topics in team_namespace.
// The README's interface table documents each.
#pragma once

namespace scan_context_loop {
namespace topic_names {

// In.
constexpr char kKeyframeCloud[] = "keyframe_cloud";
constexpr char kKeyframeOdom[] = "keyframe_odom";
constexpr char kCorrectedPath[] = "corrected_path";
// Out.
constexpr char kLoopClosures[] = "loop_closures";
constexpr char kLoopCandidatesRejected[] = "loop_candidates_rejected";
constexpr char kLoopClosurePairs[] = "loop_closure_pairs";
constexpr char kLoopClosureArray[] = "loop_closure_array";
constexpr char kLioLoop[] = "lio_loop";
constexpr char kRelocalization[] = "relocalization";
constexpr char kLoopMarkers[] = "loop_markers";
constexpr char kSelectedKeyframeOdom[] = "selected_keyframe_odom";
constexpr char kSelectedKeyframeCloud[] = "selected_keyframe_cloud";
constexpr char kKeyframeTiming[] = "keyframe_timing";
// Services (private).
constexpr char kSaveDatabase[] = "save_database";
constexpr char kLoadDatabase[] = "load_database";
constexpr char kReset[] = "reset";
constexpr char kRelocalize[] = "relocalize";
// The team: topics in team_namespace, services in each node's private namespace.
constexpr char kTeamKeyframeRecords[] = "keyframe_records";
constexpr char kTeamMembers[] = "members";
constexpr char kTeamRecords[] = "team_records";
constexpr char kTeamCloud[] = "team_cloud";

}  // namespace topic_names
}  // namespace scan_context_loop
