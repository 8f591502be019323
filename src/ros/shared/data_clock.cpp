#include "shared/data_clock.h"

namespace scan_context_loop {

void DataClock::observe(const ros::Time& stamp, const ros::Time& now) {
  if (stamp.isZero()) return;  // unstamped: says nothing about the data's time
  if (!started_) {
    started_ = true;
    newest_ = stamp;
    seen_at_ = now;
    return;
  }
  const ros::Time current = at(now);
  if (stamp > current) {
    newest_ = stamp;
    seen_at_ = now;
  } else if ((current - stamp).toSec() > kJumpBackSeconds) {
    newest_ = stamp;
    seen_at_ = now;
    last_output_ = ros::Time();  // a new timeline: the next output may be earlier than the last one
  }
}

ros::Time DataClock::at(const ros::Time& now) const {
  if (!started_) return now;
  // A clock that went back (sim time restarted) adds nothing rather than subtracting.
  const double run = now > seen_at_ ? (now - seen_at_).toSec() : 0.0;
  return newest_ + ros::Duration(run);
}

bool DataClock::next(const ros::Time& now, ros::Time* stamp) {
  const ros::Time t = at(now);
  if (!last_output_.isZero() && t <= last_output_) return false;
  last_output_ = t;
  *stamp = t;
  return true;
}

}  // namespace scan_context_loop
