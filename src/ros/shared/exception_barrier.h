// The worker's exception barrier: one keyframe or task that throws must not end the node.
#pragma once

#include <functional>
#include <string>

namespace scan_context_loop {

/// Runs `work` and catches whatever it throws (PCL's registration may throw, an allocation may fail).
/// Returns true when it returned; false when it threw, with the exception's what() in `what` (or a
/// note that it was not a std::exception).
bool runCatching(const std::function<void()>& work, std::string* what);

}  // namespace scan_context_loop
