// A nodelet around one of the package's ROS adapters (LoopClosureRos, PoseGraphRos): it builds the
// adapter with the nodelet's handles and name and starts it; a configuration the adapter rejects leaves
// the nodelet idle and its manager running.
#pragma once

#include <memory>

#include <nodelet/nodelet.h>

namespace scan_context_loop {

template <typename Adapter>
class AdapterNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    adapter_ = std::make_unique<Adapter>(getNodeHandle(), getPrivateNodeHandle(), getName());
    if (!adapter_->start()) {
      NODELET_FATAL("configuration rejected; the nodelet stays idle");
      adapter_.reset();
    }
  }
  std::unique_ptr<Adapter> adapter_;
};

}  // namespace scan_context_loop
