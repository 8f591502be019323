#include "scan_context_loop/core/pcl_refinement.h"

#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/ndt.h>

namespace scan_context_loop {

namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr pointsOf(const VoxelCloud& cloud) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr out(new pcl::PointCloud<pcl::PointXYZ>);
  out->reserve(cloud.size());
  for (const auto& m : cloud.means) out->push_back(pcl::PointXYZ(m.x(), m.y(), m.z()));
  return out;
}

}  // namespace

bool refineWithPcl(const VoxelCloud& query, const VoxelCloud& match, const VerificationConfig& config,
                   Eigen::Isometry3d* pose) {
  pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> gicp;
  pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
  pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ> ndt;
  pcl::Registration<pcl::PointXYZ, pcl::PointXYZ>* registration = &gicp;
  if (config.method == RegistrationMethod::kIcp) registration = &icp;
  if (config.method == RegistrationMethod::kNdt) {
    ndt.setStepSize(0.5);
    ndt.setResolution(static_cast<float>(config.ndt_resolution));
    registration = &ndt;
  }
  registration->setInputSource(pointsOf(match));
  registration->setInputTarget(pointsOf(query));
  registration->setMaximumIterations(2 * config.max_iterations);
  registration->setTransformationEpsilon(1e-6);
  registration->setMaxCorrespondenceDistance(config.coarse_correspondence);
  pcl::PointCloud<pcl::PointXYZ> aligned;
  registration->align(aligned, pose->matrix().cast<float>());
  if (!registration->hasConverged()) return false;
  pose->matrix() = registration->getFinalTransformation().cast<double>();
  return true;
}

}  // namespace scan_context_loop
