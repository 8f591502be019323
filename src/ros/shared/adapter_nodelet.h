// A nodelet around one of the package's ROS adapters (LoopClosureRos, PoseGraphRos): it builds the
// adapter with the nodelet's handles and name and starts it. A configuration the adapter rejects (its
// FATAL lines name each key and the fix) fails the load: the manager unloads the nodelet and runs on,
// `nodelet load` exits with a non-zero status (roslaunch reports the process dead; `required` and
// `respawn` act on it), and a standalone node exits with status 1.
#pragma once

#include <memory>
#include <stdexcept>

#include <nodelet/nodelet.h>

namespace scan_context_loop {

template <typename Adapter>
class AdapterNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    adapter_ = std::make_unique<Adapter>(getNodeHandle(), getPrivateNodeHandle(), getName());
    if (!adapter_->start()) {
      adapter_.reset();
      throw std::runtime_error("configuration rejected (the lines above name each parameter): not loaded");
    }
  }
  std::unique_ptr<Adapter> adapter_;
};

}  // namespace scan_context_loop
