// A second session of a drive: the same world seen on another day, from another start, the other way
// along the same streets in the other lane.
#pragma once

#include <vector>

#include "scan_context_sim/city_drive.h"
#include "scan_context_sim/world.h"

namespace scan_context_loop {
namespace sim {

struct SecondSessionOptions {
  /// To the right of the second drive's direction of travel [m]: with the first drive in one lane of a
  /// two-way street, the second drives in the other.
  double lane_offset = 3.0;
  double days_later = 1.0;  ///< the second drive starts this long after the first one ended [days]
  double changed = 1.0;     ///< how much the street changed by then (LaterDrive::changed, 0 to 1)
};

/// The second drive: the first drive's path, with its clock `times` (seconds, ascending), driven from its
/// end back to its start, `lane_offset` to the right of the direction of travel, at the first drive's
/// speeds and with its stops, in reverse order; on the inside of corners sharper than the offset, the
/// points that would come nearer the first drive's path than the offset are left out, so the drive
/// turns without folding back. Its times are seconds from its own start.
TimedPath secondSessionDrive(const std::vector<PathPoint>& path, const std::vector<double>& times,
                             const SecondSessionOptions& options);

/// The second drive as a LaterDrive of the world (generateWorld) whose first drive lasted
/// `first_duration` seconds: its times on the world's clock, days_later after the first drive's end.
LaterDrive laterDrive(const TimedPath& second, double first_duration, const SecondSessionOptions& options);

}  // namespace sim
}  // namespace scan_context_loop
