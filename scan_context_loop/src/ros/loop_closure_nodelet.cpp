// The nodelet: a few lines around the adapter.
#include <memory>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include "scan_context_loop/ros/loop_closure_ros.h"

namespace scan_context_loop {

class LoopClosureNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    adapter_ = std::make_unique<LoopClosureRos>(getNodeHandle(), getPrivateNodeHandle(), getName());
    if (!adapter_->start()) {
      NODELET_FATAL("configuration rejected; the nodelet stays idle");
      adapter_.reset();
    }
  }
  std::unique_ptr<LoopClosureRos> adapter_;
};

}  // namespace scan_context_loop

PLUGINLIB_EXPORT_CLASS(scan_context_loop::LoopClosureNodelet, nodelet::Nodelet)
