#include "shared/frame_ids.h"

namespace scan_context_loop {

std::string normaliseFrameId(const std::string& frame_id) {
  const std::size_t first = frame_id.find_first_not_of('/');
  return first == std::string::npos ? std::string() : frame_id.substr(first);
}

void normaliseFrameIds(NodeOptions* options) {
  for (std::string* frame : {&options->fixed_frame, &options->sensor_frame, &options->map_frame}) {
    *frame = normaliseFrameId(*frame);
  }
}

}  // namespace scan_context_loop
