// The pose_graph nodelet: a few lines around the adapter.
#include <memory>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include "scan_context_loop/ros/pose_graph_ros.h"

namespace scan_context_loop {

class PoseGraphNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    adapter_ = std::make_unique<PoseGraphRos>(getNodeHandle(), getPrivateNodeHandle(), getName());
    if (!adapter_->start()) {
      NODELET_FATAL("configuration rejected; the nodelet stays idle");
      adapter_.reset();
    }
  }
  std::unique_ptr<PoseGraphRos> adapter_;
};

}  // namespace scan_context_loop

PLUGINLIB_EXPORT_CLASS(scan_context_loop::PoseGraphNodelet, nodelet::Nodelet)
