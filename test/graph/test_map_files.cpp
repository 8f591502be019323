// The corrected map's files (graph/map_files.h) read back as other tools read them: the PCD with PCL's
// reader, the trajectories as evo reads TUM and KITTI files, the graph with a g2o text parser written
// here; and a failed save leaves every file it would have replaced as it was.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>

#include "../common/map_file_readers.h"
#include "../common/temp_dir.h"
#include "../common/file_faults.h"
#include "scan_context_loop/graph/keyframe_map.h"
#include "scan_context_loop/graph/map_files.h"
#include "scan_context_loop/graph/pose_graph.h"
#include "scan_context_loop/core/team_matcher.h"

namespace scan_context_loop {
namespace {

using namespace test;  // the readers
using Vector6d = Eigen::Matrix<double, 6, 1>;

Eigen::Isometry3d pose(double x, double y, double z, double yaw, double pitch, double roll) {
  return Eigen::Translation3d(x, y, z) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
}

/// A loop covariance that is neither diagonal nor isotropic: x y z roll pitch yaw, correlated.
Matrix6d loopCovariance() {
  Matrix6d a = Matrix6d::Identity();
  a(0, 1) = 0.3;
  a(2, 5) = -0.2;
  a(1, 4) = 0.1;
  Vector6d scale;
  scale << 0.02, 0.005, 0.01, 0.001, 0.002, 0.0005;
  const Matrix6d s = scale.asDiagonal();
  return s * a * a.transpose() * s;
}

/// A small solved graph: 8 keyframes around a square with a little roll and pitch, odometry that
/// drifts, one loop from the last to the first with a turned measurement and loopCovariance(); the map
/// from a wall seen by every keyframe.
class MapFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::int64_t start = 1733400000123456789;  // stamps with nanoseconds that a double would blur
    for (int k = 0; k < 8; ++k) {
      const double angle = M_PI / 4 * k;
      truth_.push_back(pose(10 * std::cos(angle), 10 * std::sin(angle), 0.1 * k, angle + M_PI / 2, 0.02, -0.01));
      stamps_.push_back(start + 500000001LL * k);
    }
    Eigen::Isometry3d odometry = truth_[0];
    for (std::size_t k = 0; k < truth_.size(); ++k) {
      if (k > 0) {
        Eigen::Isometry3d step = truth_[k - 1].inverse() * truth_[k];
        step.translation() *= 1.01;
        odometry = odometry * step * Eigen::AngleAxisd(0.003, Eigen::Vector3d::UnitZ());
      }
      ASSERT_EQ(graph_.addKeyframe(odometry), static_cast<long>(k));
    }
    const Eigen::Isometry3d loop = truth_[7].inverse() * truth_[0];
    ASSERT_TRUE(graph_.addLoop(7, 0, loop, loopCovariance()));
    ASSERT_TRUE(graph_.optimize().solved);

    KeyframeMapConfig config;
    config.voxel = 0.5;
    KeyframeMap map(config);
    std::vector<Eigen::Vector3f> wall;
    for (int i = 0; i < 40; ++i) {
      for (int j = 0; j < 10; ++j) wall.emplace_back(4.0f, -5.0f + 0.25f * i, 0.25f * j);
    }
    for (std::size_t k = 0; k < graph_.size(); ++k) map.add(k, wall);
    files_ = mapFilesOf(graph_, stamps_);
    files_.cloud = map.assemble(graph_.poses());
    files_.has_cloud = true;
    files_.voxel = config.voxel;
    ASSERT_GT(files_.cloud.size(), 100u);
  }

  /// The graph one keyframe longer and the map one point larger: every file of the set changes.
  MapFiles changedFiles() {
    graph_.addKeyframe(graph_.odometryPose(7) * Eigen::Translation3d(1.0, 0.0, 0.0));
    stamps_.push_back(stamps_.back() + 100000000);
    MapFiles changed = mapFilesOf(graph_, stamps_);
    changed.cloud = files_.cloud;
    changed.cloud.push_back(pcl::PointXYZ(1.0f, 2.0f, 3.0f));
    changed.has_cloud = true;
    return changed;
  }

  std::vector<Eigen::Isometry3d> truth_;
  std::vector<std::int64_t> stamps_;
  PoseGraph graph_;
  MapFiles files_;
};

TEST_F(MapFilesTest, EveryFileReadsBackWithTheReadersOfPclEvoAndG2o) {
  test::TempDir dir("scl_map_files");
  const std::string out = dir.file("run1");  // created by the save
  MapFilesReport report;
  std::string error;
  ASSERT_TRUE(writeMapFiles(out, files_, &report, &error)) << error;
  const std::vector<std::string> names = mapFileNames(true);
  ASSERT_EQ(report.files.size(), 6u);
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(report.files[i], out + "/" + names[i]);
    struct stat st;
    ASSERT_EQ(::stat(report.files[i].c_str(), &st), 0) << report.files[i];
    EXPECT_EQ(static_cast<std::uint64_t>(st.st_size), report.bytes[i]) << names[i];
  }
  EXPECT_EQ(report.keyframes, 8u);
  EXPECT_EQ(report.loops, 1u);
  EXPECT_EQ(report.points, files_.cloud.size());
  const std::string summary = report.summary();
  EXPECT_NE(summary.find("map.pcd"), std::string::npos) << summary;
  EXPECT_NE(summary.find(std::to_string(files_.cloud.size()) + " points, voxel-filtered at 0.50 m"), std::string::npos)
      << summary;
  std::printf("%s\n", summary.c_str());

  // map.pcd: PCL's reader, every point as written.
  pcl::PointCloud<pcl::PointXYZ> cloud;
  ASSERT_EQ(pcl::io::loadPCDFile(out + "/map.pcd", cloud), 0);
  ASSERT_EQ(cloud.size(), files_.cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    ASSERT_EQ(cloud[i].x, files_.cloud[i].x);
    ASSERT_EQ(cloud[i].y, files_.cloud[i].y);
    ASSERT_EQ(cloud[i].z, files_.cloud[i].z);
  }

  // TUM: the corrected and the odometry poses, stamps to the nanosecond.
  const Tum corrected = readTum(out + "/corrected_tum.txt"), odometry = readTum(out + "/odometry_tum.txt");
  ASSERT_EQ(corrected.poses.size(), graph_.size());
  ASSERT_EQ(odometry.poses.size(), graph_.size());
  EXPECT_EQ(corrected.stamp_text[0], "1733400000.123456789");
  EXPECT_EQ(corrected.stamp_text[3], "1733400001.623456792");
  EXPECT_EQ(odometry.stamp_text, corrected.stamp_text);
  for (std::size_t k = 0; k < graph_.size(); ++k) {
    EXPECT_LT(poseDifference(corrected.poses[k], graph_.pose(k)), 1e-12) << k;
    EXPECT_LT(poseDifference(odometry.poses[k], graph_.odometryPose(k)), 1e-12) << k;
  }
  // The correction shows: the loop pulled the last keyframe away from where the odometry put it.
  EXPECT_GT((corrected.poses[7].translation() - odometry.poses[7].translation()).norm(), 0.1);

  // KITTI: 12 numbers a line, as many lines as times.txt, the same stamps.
  const std::vector<Eigen::Isometry3d> kitti = readKitti(out + "/corrected_kitti.txt");
  const auto times = rows(out + "/times.txt");
  ASSERT_EQ(kitti.size(), graph_.size());
  ASSERT_EQ(times.size(), kitti.size());
  for (std::size_t k = 0; k < kitti.size(); ++k) {
    EXPECT_LT(poseDifference(kitti[k], graph_.pose(k)), 1e-12) << k;
    ASSERT_EQ(times[k].size(), 1u);
    EXPECT_EQ(times[k][0], corrected.stamp_text[k]);
  }

  // g2o: a vertex per keyframe at its estimate, the first fixed, an edge per factor with its measurement.
  const G2o g2o = readG2o(out + "/pose_graph.g2o");
  ASSERT_EQ(g2o.vertices.size(), graph_.size());
  for (std::size_t k = 0; k < graph_.size(); ++k) {
    ASSERT_EQ(g2o.vertices.count(static_cast<long>(k)), 1u);
    EXPECT_LT(poseDifference(g2o.vertices.at(static_cast<long>(k)), graph_.pose(k)), 1e-12);
  }
  EXPECT_EQ(g2o.fixed, std::vector<long>{0});
  const auto& factors = graph_.factors();
  ASSERT_EQ(g2o.edges.size(), factors.size());
  ASSERT_EQ(factors.size(), 8u);  // 7 odometry steps and the loop
  for (std::size_t i = 0; i < factors.size(); ++i) {
    const G2o::Edge& edge = g2o.edges[i];
    EXPECT_EQ(edge.a, static_cast<long>(factors[i].a));
    EXPECT_EQ(edge.b, static_cast<long>(factors[i].b));
    EXPECT_LT(poseDifference(edge.measurement, factors[i].measurement), 1e-12);
    const Eigen::LLT<Matrix6d> llt(edge.information);
    EXPECT_EQ(llt.info(), Eigen::Success) << "edge " << i << ": the information is not positive definite";
  }
  // The loop's information: its covariance inverted and moved into g2o's error, [R_Z^T t ; vec(q)]
  // against this graph's [t ; 2 vec(q)] (map_files.h), i.e. Omega = K^T C^-1 K, K = diag(R_Z, 2 I).
  const G2o::Edge& loop = g2o.edges.back();
  ASSERT_EQ(loop.a, 7);
  ASSERT_EQ(loop.b, 0);
  Matrix6d k = Matrix6d::Zero();
  k.topLeftCorner<3, 3>() = factors.back().measurement.linear();
  k.bottomRightCorner<3, 3>() = 2.0 * Eigen::Matrix3d::Identity();
  const Matrix6d expected = k.transpose() * loopCovariance().inverse() * k;
  EXPECT_LT((loop.information - expected).cwiseAbs().maxCoeff(), 1e-9 * expected.cwiseAbs().maxCoeff());
  // An odometry edge (isotropic translation noise): D C^-1 D with D = diag(1, 1, 1, 2, 2, 2).
  Vector6d d;
  d << 1, 1, 1, 2, 2, 2;
  const Matrix6d odometry_expected = d.asDiagonal() * factors[0].covariance.inverse() * d.asDiagonal();
  EXPECT_LT((g2o.edges[0].information - odometry_expected).cwiseAbs().maxCoeff(),
            1e-9 * odometry_expected.cwiseAbs().maxCoeff());

  // And what it means: g2o's chi2 of each edge (its own error, at the file's vertices) is the cost this
  // graph gives the factor, so g2o and this graph minimise the same thing.
  for (std::size_t i = 0; i < factors.size(); ++i) {
    const G2o::Edge& edge = g2o.edges[i];
    const Eigen::Isometry3d estimate = g2o.vertices.at(edge.a).inverse() * g2o.vertices.at(edge.b);
    const Eigen::Isometry3d delta = edge.measurement.inverse() * estimate;
    Eigen::Quaterniond q(delta.linear());
    if (q.w() < 0) q.coeffs() *= -1.0;
    Vector6d g2o_error;
    g2o_error << delta.translation(), q.vec();
    const double chi2 = g2o_error.dot(edge.information * g2o_error);
    Vector6d residual;  // this graph's (pose_graph.h)
    const Eigen::Quaterniond q_ab(estimate.linear()), q_measured(factors[i].measurement.linear());
    residual << estimate.translation() - factors[i].measurement.translation(),
        2.0 * (q_measured.conjugate() * q_ab).vec();
    const double cost = residual.dot(factors[i].covariance.inverse() * residual);
    EXPECT_NEAR(chi2, cost, 1e-6 * cost + 1e-12) << "edge " << i;
    if (factors[i].loop) {
      EXPECT_GT(cost, 1e-3) << "the loop's residual is too small to tell anything";
    }
  }
}

TEST_F(MapFilesTest, WithoutACloudThereIsNoPcd) {
  test::TempDir dir("scl_map_files");
  files_.has_cloud = false;
  MapFilesReport report;
  std::string error;
  ASSERT_TRUE(writeMapFiles(dir.file("run"), files_, &report, &error)) << error;
  EXPECT_EQ(report.files.size(), 5u);
  EXPECT_FALSE(std::ifstream(dir.file("run/map.pcd")).good());
  EXPECT_EQ(report.summary().find("map.pcd"), std::string::npos);
  EXPECT_TRUE(report.removed_stale_cloud.empty());
}

TEST_F(MapFilesTest, ASaveWithoutACloudRemovesTheOlderPcd) {
  test::TempDir dir("scl_map_files");
  const std::string out = dir.file("run");
  std::string error;
  ASSERT_TRUE(writeMapFiles(out, files_, nullptr, &error)) << error;
  ASSERT_TRUE(std::ifstream(out + "/map.pcd").good());
  files_.has_cloud = false;
  MapFilesReport report;
  ASSERT_TRUE(writeMapFiles(out, files_, &report, &error)) << error;
  EXPECT_FALSE(std::ifstream(out + "/map.pcd").good()) << "an older map.pcd stays beside the new trajectory";
  EXPECT_EQ(report.removed_stale_cloud, out + "/map.pcd");
  EXPECT_NE(report.summary().find("removed the older map.pcd"), std::string::npos) << report.summary();
  EXPECT_EQ(report.files.size(), 5u);
}

TEST_F(MapFilesTest, AFailedSaveReportsTheTemporaryFilesItRemoved) {
  test::TempDir dir("scl_map_files");
  const std::string out = dir.file("run");
  ASSERT_EQ(::mkdir(out.c_str(), 0755), 0);
  std::ofstream(out + "/times.txt.tmp.Ab12Cd") << std::string(100, 'x');  // a killed save's
  ASSERT_EQ(::mkdir((out + "/pose_graph.g2o").c_str(), 0755), 0);         // this save fails there
  MapFilesReport report;
  std::string error;
  EXPECT_FALSE(writeMapFiles(out, files_, &report, &error));
  ASSERT_EQ(report.abandoned.size(), 1u);
  EXPECT_EQ(report.abandoned[0].path, out + "/times.txt.tmp.Ab12Cd");
  EXPECT_EQ(report.abandoned[0].bytes, 100u);
  EXPECT_TRUE(report.files.empty());
  EXPECT_FALSE(std::ifstream(out + "/times.txt.tmp.Ab12Cd").good());
}

TEST_F(MapFilesTest, ADirectoryThatCannotBeWrittenFailsWithTheReasonAndWritesNothing) {
  test::TempDir dir("scl_map_files");
  std::string error;
  // /proc/1 is a directory that no one, root included, creates files in.
  EXPECT_FALSE(writeMapFiles("/proc/1", files_, nullptr, &error));
  EXPECT_NE(error.find("cannot create a temporary file in /proc/1"), std::string::npos) << error;
  // A directory under a regular file cannot be created.
  std::ofstream(dir.file("plain")) << "x";
  error.clear();
  EXPECT_FALSE(writeMapFiles(dir.file("plain/run"), files_, nullptr, &error));
  EXPECT_NE(error.find("cannot create the directory " + dir.file("plain/run")), std::string::npos) << error;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"plain"});
  // Input that does not hold together is refused before anything is written.
  files_.stamps_ns[3] = files_.stamps_ns[2];
  error.clear();
  EXPECT_FALSE(writeMapFiles(dir.file("run"), files_, nullptr, &error));
  EXPECT_NE(error.find("do not increase at keyframe 3"), std::string::npos) << error;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"plain"});
}

TEST_F(MapFilesTest, AFailedSaveKeepsTheFilesItWouldHaveReplacedWhole) {
  test::TempDir dir("scl_map_files");
  const std::string out = dir.file("run");
  std::string error;
  ASSERT_TRUE(writeMapFiles(out, files_, nullptr, &error)) << error;
  std::map<std::string, std::string> before;
  for (const auto& name : mapFileNames(true)) before[name] = readText(out + "/" + name);

  // The next save, of a changed graph, fails at its last file (a directory stands where it goes) after
  // the other five were written: none of them may have replaced its file, and no temporary file stays.
  ASSERT_EQ(std::remove((out + "/pose_graph.g2o").c_str()), 0);
  ASSERT_EQ(::mkdir((out + "/pose_graph.g2o").c_str(), 0755), 0);
  const MapFiles changed = changedFiles();
  EXPECT_FALSE(writeMapFiles(out, changed, nullptr, &error));
  EXPECT_NE(error.find("is a directory"), std::string::npos) << error;
  for (const auto& name : mapFileNames(true)) {
    if (name != "pose_graph.g2o") {
      EXPECT_EQ(readText(out + "/" + name), before[name]) << name << " changed";
    }
  }
  std::vector<std::string> entries;
  for (const auto& e : std::filesystem::directory_iterator(out)) entries.push_back(e.path().filename().string());
  EXPECT_EQ(entries.size(), 6u) << "a temporary file was left behind";

  // Once the way is clear the same save goes through and replaces them all.
  ASSERT_EQ(::rmdir((out + "/pose_graph.g2o").c_str()), 0);
  ASSERT_TRUE(writeMapFiles(out, changed, nullptr, &error)) << error;
  EXPECT_EQ(readTum(out + "/corrected_tum.txt").poses.size(), 9u);
  pcl::PointCloud<pcl::PointXYZ> cloud;
  ASSERT_EQ(pcl::io::loadPCDFile(out + "/map.pcd", cloud), 0);
  EXPECT_EQ(cloud.size(), files_.cloud.size() + 1);
}

/// Each map file's bytes in `directory` ("" for a file that is missing).
std::map<std::string, std::string> setIn(const std::string& directory) {
  std::map<std::string, std::string> set;
  for (const auto& name : mapFileNames(true)) {
    std::ifstream in(directory + "/" + name, std::ios::binary);
    set[name] = in ? std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()) : "";
  }
  return set;
}

// A save killed at any of its renames (a SIGKILL, a power cut) leaves the directory holding the old set
// whole or the new set whole, never some files of each; the next save removes what the dead one left.
TEST_F(MapFilesTest, ASaveKilledAtAnyRenameLeavesOneWholeSet) {
  test::TempDir dir("scl_map_files");
  const std::string out = dir.file("run");
  std::string error;
  ASSERT_TRUE(writeMapFiles(out, files_, nullptr, &error)) << error;
  std::ofstream(out + "/notes.txt") << "the user's own file";
  const std::map<std::string, std::string> before = setIn(out);
  const MapFiles changed = changedFiles();
  ASSERT_TRUE(writeMapFiles(dir.file("reference"), changed, nullptr, &error)) << error;
  const std::map<std::string, std::string> after = setIn(dir.file("reference"));
  for (const auto& [name, bytes] : after) ASSERT_NE(bytes, before.at(name)) << name << " is the same in both sets";

  // How many renames a save over an existing set makes.
  test::FileFaults::clear();
  ASSERT_TRUE(writeMapFiles(dir.file("reference"), changed, nullptr, &error)) << error;
  const int renames = test::FileFaults::calls("rename");
  ASSERT_GE(renames, 6);
  for (int k = 1; k <= renames; ++k) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      test::FileFaults::clear();
      test::FileFaults::killAt("rename", k);
      std::string child_error;
      writeMapFiles(out, changed, nullptr, &child_error);
      ::_exit(3);  // not killed: the test below says so
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "the save was not killed at rename " << k;
    const std::map<std::string, std::string> left = setIn(out);
    EXPECT_TRUE(left == before || left == after)
        << "killed at rename " << k << " of " << renames << ": the directory holds files of both sets";
    EXPECT_EQ(readText(out + "/notes.txt"), "the user's own file") << "killed at rename " << k;
    // Back to the old set for the next round; this save also clears what the dead one left.
    ASSERT_TRUE(writeMapFiles(out, files_, nullptr, &error)) << error;
    ASSERT_EQ(setIn(out), before);
  }
  test::FileFaults::clear();
  ASSERT_TRUE(writeMapFiles(out, changed, nullptr, &error)) << error;
  EXPECT_EQ(setIn(out), after);
  EXPECT_EQ(readText(out + "/notes.txt"), "the user's own file");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"reference", "run"})) << "a dead save's directory is left";
}

}  // namespace
}  // namespace scan_context_loop

namespace scan_context_loop {
namespace {

TEST(TeamMapFiles, EachRobotsTrajectoryAndFrameInItsOwnFilesTheGraphInOne) {
  // Two robots whose keyframes interleave (stamps increase per robot, not overall), and a third with no
  // loop to the others: its frame is its own (not joined).
  PoseGraph graph;
  std::vector<std::int64_t> stamps;
  for (int k = 0; k < 6; ++k) {
    graph.addKeyframe(pose(2.0 * k, 0, 0, 0, 0, 0), 0);
    stamps.push_back(1000000000LL * k);
    graph.addKeyframe(pose(2.0 * k, 0, 0, 0, 0, 0), 1);
    stamps.push_back(1000000000LL * k + 5);
    graph.addKeyframe(pose(1.0 * k, 0, 0, 0, 0, 0), 2);
    stamps.push_back(1000000000LL * k + 7);
  }
  // b's first keyframe (index 1) lies on a's keyframe 3 (index 9, at a's x = 6 m), turned 90 deg.
  Matrix6d covariance = 0.01 * Matrix6d::Identity();
  const Eigen::Isometry3d b_to_a = pose(0, 0, 0, M_PI / 2, 0, 0);  // T_b0<-a3: a3 sits on b0, turned
  ASSERT_TRUE(graph.addLoop(1, 9, b_to_a, covariance));
  ASSERT_TRUE(graph.optimize().solved);
  MapFiles files = mapFilesOf(graph, stamps, {"a", "b", "c_2"});
  ASSERT_EQ(files.robots.size(), 3u);
  EXPECT_TRUE(files.robots[0].joined && files.robots[1].joined);
  EXPECT_FALSE(files.robots[2].joined);
  EXPECT_EQ(files.held, (std::vector<std::size_t>{0, 2}));

  test::TempDir dir("scl_team_map_files");
  MapFilesReport report;
  std::string error;
  ASSERT_TRUE(writeMapFiles(dir.file("team"), files, &report, &error)) << error;
  const std::vector<std::string> names = mapFileNames(false, {"a", "b", "c_2"});
  ASSERT_EQ(names.size(), 14u);
  ASSERT_EQ(report.files.size(), names.size());
  EXPECT_EQ(names[4], "corrected_tum_b.txt");
  EXPECT_EQ(names[12], "frames.txt");
  for (const std::string& robot : {"a", "b", "c_2"}) {
    const std::size_t c = robot[0] - 'a';
    const Tum corrected = readTum(dir.file("team/corrected_tum_" + robot + ".txt"));
    const Tum odometry = readTum(dir.file("team/odometry_tum_" + robot + ".txt"));
    ASSERT_EQ(corrected.poses.size(), 6u) << robot;
    ASSERT_EQ(readKitti(dir.file("team/corrected_kitti_" + robot + ".txt")).size(), 6u);
    ASSERT_EQ(rows(dir.file("team/times_" + robot + ".txt")).size(), 6u);
    for (std::size_t k = 0; k < 6; ++k) {
      EXPECT_LT(poseDifference(corrected.poses[k], graph.pose(3 * k + c)), 1e-12) << robot << k;
      EXPECT_LT(poseDifference(odometry.poses[k], graph.odometryPose(3 * k + c)), 1e-12) << robot << k;
    }
  }
  // frames.txt: robot, joined, T_map<-odom; b's is where the loop put it (its first keyframe on a's 3rd).
  const auto frames = rows(dir.file("team/frames.txt"));
  ASSERT_EQ(frames.size(), 3u);
  for (std::size_t c = 0; c < 3; ++c) {
    ASSERT_EQ(frames[c].size(), 14u);
    EXPECT_EQ(frames[c][0], files.robots[c].id);
    EXPECT_EQ(frames[c][1], c < 2 ? "1" : "0");
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    for (int i = 0; i < 12; ++i) m(i / 4, i % 4) = std::stod(frames[c][2 + i]);
    EXPECT_LT((m - graph.frame(c).matrix()).cwiseAbs().maxCoeff(), 1e-12);
  }
  EXPECT_LT((graph.frame(1).translation() - Eigen::Vector3d(6, 0, 0)).norm(), 0.05);
  // The g2o file: every robot's keyframes and factors, the unjoined robot's gauge held with the anchor's.
  const G2o g2o = readG2o(dir.file("team/pose_graph.g2o"));
  EXPECT_EQ(g2o.vertices.size(), 18u);
  EXPECT_EQ(g2o.edges.size(), 3u * 5u + 1u);
  EXPECT_EQ(g2o.fixed, (std::vector<long>{0, 2}));

  // A robot whose stamps go back, or a robot id that would leave the directory, is refused.
  MapFiles back = files;
  std::swap(back.robots[1].keyframes[2], back.robots[1].keyframes[3]);
  EXPECT_FALSE(writeMapFiles(dir.file("back"), back, &report, &error));
  EXPECT_NE(error.find("robot b: keyframe stamps do not increase"), std::string::npos) << error;
  MapFiles named = files;
  named.robots[0].id = "../a";
  EXPECT_FALSE(writeMapFiles(dir.file("named"), named, &report, &error));
  EXPECT_NE(error.find(std::string("is not ") + kRobotIdRule), std::string::npos) << error;
}

}  // namespace
}  // namespace scan_context_loop
