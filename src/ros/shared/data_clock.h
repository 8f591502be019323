// The data's time, for outputs that are not tied to one message (the backend's tf map -> odom). A bag
// replayed without --clock carries stamps far from ros::Time::now(), and RViz (or any tf user) looks
// the transform up at the stamps of the data it shows: stamped with the clock, it is never found. The
// clock here is the newest data stamp seen, advanced by the time the ROS clock has run since it was seen:
// live, or in a replay with sim time, that is the clock itself; in a replay on the wall clock, it is the
// bag's time. It never goes back, except when the data jump back (a new bag, a looped one).
#pragma once

#include <ros/time.h>

namespace scan_context_loop {

class DataClock {
 public:
  /// Data older than the clock by more than this is a jump back (a new or looped bag): the clock restarts
  /// there. Older data within it (messages of other topics that arrive a little late) leave it alone.
  static constexpr double kJumpBackSeconds = 10.0;

  /// A message stamped `stamp` arrived when the ROS clock read `now`.
  void observe(const ros::Time& stamp, const ros::Time& now);

  /// True once a message was observed.
  bool started() const { return started_; }

  /// The data's time when the ROS clock reads `now`: the newest stamp plus the clock's run since.
  ros::Time at(const ros::Time& now) const;

  /// The stamp for the next output at `now`, or false when it would not be after the previous one (the
  /// clock stood still, a paused replay): tf2 refuses a second transform at the same stamp.
  bool next(const ros::Time& now, ros::Time* stamp);

 private:
  bool started_ = false;
  ros::Time newest_;         ///< the newest data stamp (or where the clock restarted)
  ros::Time seen_at_;        ///< the ROS clock when newest_ was seen
  ros::Time last_output_;    ///< the last stamp next() handed out
};

}  // namespace scan_context_loop
