// RViz markers go out incrementally: chunks of keyframes and rejected candidates, one id per loop.
#include <gtest/gtest.h>

#include "loop_closure/markers.h"

namespace scan_context_loop {
namespace {

std::size_t pointsIn(const visualization_msgs::MarkerArray& a, const std::string& ns) {
  std::size_t n = 0;
  for (const auto& m : a.markers) n += m.ns == ns ? m.points.size() : 0;
  return n;
}

TEST(Markers, UpdatesCarryOnlyWhatChanged) {
  std::vector<Eigen::Vector3d> positions;
  for (int k = 0; k < 250; ++k) positions.emplace_back(2.0 * k, 0.0, 0.0);
  std::vector<LoopEdge> loops = {{120, 3, 0.1}, {121, 4, 0.12}};
  std::vector<LoopEdge> rejected(130, LoopEdge{200, 10, 0.3});
  const ros::Time stamp(10.0);
  MarkerState shown;
  const auto full = makeLoopMarkers(positions, {}, loops, rejected, "odom", stamp, 0.21, &shown);
  EXPECT_EQ(pointsIn(full, "keyframes"), 250u);
  EXPECT_EQ(pointsIn(full, "loops"), 4u);
  EXPECT_EQ(pointsIn(full, "rejected"), 260u);
  EXPECT_EQ(shown.keyframes, 250u);

  // One more keyframe and loop: the last keyframe chunk (150 minus 100 points plus the new one) and the
  // new loop's three markers; no rejected chunk, no older loop.
  positions.emplace_back(500.0, 0.0, 0.0);
  loops.push_back({250, 5, 0.2});
  const auto update = makeLoopMarkers(positions, {}, loops, rejected, "odom", stamp, 0.21, &shown);
  EXPECT_EQ(pointsIn(update, "keyframes"), 51u);
  EXPECT_EQ(pointsIn(update, "loops"), 2u);
  EXPECT_EQ(pointsIn(update, "rejected"), 0u);
  for (const auto& m : update.markers) {
    if (m.ns == "loops") EXPECT_EQ(m.id, 2);
    if (m.ns == "keyframes") EXPECT_EQ(m.id, 2);
  }
  // Nothing new: nothing to send.
  EXPECT_TRUE(makeLoopMarkers(positions, {}, loops, rejected, "odom", stamp, 0.21, &shown).markers.empty());
  // A new chunk: the previous one is redrawn too, so its strip reaches the new chunk's first keyframe.
  for (int k = 0; k < 50; ++k) positions.emplace_back(502.0 + 2.0 * k, 0.0, 0.0);
  const auto next = makeLoopMarkers(positions, {}, loops, rejected, "odom", stamp, 0.21, &shown);
  EXPECT_EQ(pointsIn(next, "keyframes"), 101u);
  // Chunk 2 (keyframes 200-299) joins keyframe 300: 100 segments; chunk 3 holds keyframe 300 alone.
  EXPECT_EQ(pointsIn(next, "trajectory"), 200u);
}

TEST(Markers, SessionsAreColouredApartAndTheirTrajectoriesNeverJoin) {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::uint32_t> sessions;
  for (int k = 0; k < 30; ++k) {
    positions.emplace_back(2.0 * k, 0.0, 0.0);
    sessions.push_back(k < 20 ? 0 : 1);
  }
  const auto markers = makeLoopMarkers(positions, sessions, {}, {}, "odom", ros::Time(1.0), 0.21);
  // 29 consecutive pairs, one of them across the sessions: 28 segments.
  EXPECT_EQ(pointsIn(markers, "trajectory"), 56u);
  for (const auto& m : markers.markers) {
    if (m.ns != "keyframes") continue;
    ASSERT_EQ(m.colors.size(), m.points.size());
    EXPECT_EQ(m.colors[0].r, m.colors[19].r);
    EXPECT_NE(m.colors[19].r, m.colors[20].r);
  }
}

}  // namespace
}  // namespace scan_context_loop
