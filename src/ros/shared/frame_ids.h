// Frame ids as tf2 names them. tf1 wrote "/camera_init" (A-LOAM, LeGO-LOAM still do); tf2 stores such a
// transform without the '/', but refuses a lookup of a name that starts with one. The node normalises
// every frame id it reads, once, where it reads it, and publishes only normalised names.
#pragma once

#include <string>

#include "scan_context_loop/core/node_options.h"

namespace scan_context_loop {

/// `frame_id` without its leading '/' characters ("/camera_init" -> "camera_init"); the rest unchanged.
std::string normaliseFrameId(const std::string& frame_id);

/// The frame parameters of the options (fixed_frame, sensor_frame, map_frame) normalised.
void normaliseFrameIds(NodeOptions* options);

}  // namespace scan_context_loop
