// Checking sensor_msgs/PointCloud2 input and describing its points for the core without copying.
#pragma once

#include <string>

#include <sensor_msgs/PointCloud2.h>

#include "scan_context_loop/core/descriptor.h"

namespace scan_context_loop {

/// A view of the message's x, y, z (float32) for the core. Returns false with a reason, touching no
/// byte of data, when the fields are missing or not float32, the sizes disagree (point_step, row_step,
/// width, height, data.size()) or the byte order is not the host's.
bool viewCloud(const sensor_msgs::PointCloud2& msg, PointView* view, std::string* why);

}  // namespace scan_context_loop
