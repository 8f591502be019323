// rostest: the database services and relocalization. Node a maps a drive, saves its database, is reset
// and loads it back, then closes loops from a second pass into the loaded session; node b loads the saved
// map and relocalizes a second run whose odometry has its own origin, by topic and by service. Nodelets
// loaded by the tests themselves save and autosave, and keep maps they must not replace; a standalone
// node whose file-system calls fail (test/common/file_faults.h) retries its autosaves.
#include <dirent.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <gtest/gtest.h>
#include <nodelet/NodeletLoad.h>
#include <nodelet/NodeletUnload.h>
#include <std_srvs/Trigger.h>
#include <tf2_eigen/tf2_eigen.h>

#include "child_process.h"
#include "harness.h"
#include "topic_watch.h"
#include "scan_context_loop/LoadDatabase.h"
#include "scan_context_loop/Relocalize.h"
#include "scan_context_loop/SaveDatabase.h"
#include "scan_context_loop/core/database_file.h"

namespace scan_context_loop {
namespace test {
namespace {

/// Expects `pose` (T_map<-sensor) to be keyframe k's true pose within 0.3 m and 1 deg.
void expectAt(const Drive& drive, int k, const geometry_msgs::Pose& pose) {
  ASSERT_GE(k, 0);
  Eigen::Isometry3d found;
  tf2::fromMsg(pose, found);
  const Eigen::Isometry3d error = drive.truth[k].inverse() * found;
  EXPECT_LT(error.translation().norm(), 0.3) << "keyframe " << k;
  EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle(), M_PI / 180.0) << "keyframe " << k;
}

TEST(Relocalization, SaveResetLoadThenRelocalizeASecondRunInTheSavedMap) {
  ros::NodeHandle a_nh("a"), b_nh("b");
  Harness a(a_nh), b(b_nh);
  ASSERT_TRUE(a.waitForNode(30.0));
  ASSERT_TRUE(b.waitForNode(30.0));
  Collected<geometry_msgs::PoseWithCovarianceStamped> relocalizations(b_nh, "relocalization");

  const Drive drive = blockDrive(true, 7);
  const std::size_t n = drive.truth.size();
  a.publish(drive, 0, n, 15.0);
  ASSERT_TRUE(a.waitForKeyframes(n, 60.0));

  const std::string path = "/tmp/scan_context_loop_relocalization_" + std::to_string(getpid()) + ".scdb";
  SaveDatabase save;
  save.request.path = path;
  save.request.include_clouds = true;
  ASSERT_TRUE(ros::service::call("a/loop_closure/save_database", save));
  ASSERT_TRUE(save.response.success) << save.response.message;
  EXPECT_EQ(save.response.keyframes, n);

  // Saving where no file can be written: refused with the reason, nothing written, the database stays.
  SaveDatabase nowhere;
  nowhere.request.path = "/nonexistent_directory_" + std::to_string(getpid()) + "/map.scdb";
  ASSERT_TRUE(ros::service::call("a/loop_closure/save_database", nowhere));
  EXPECT_FALSE(nowhere.response.success);
  EXPECT_FALSE(nowhere.response.message.empty());
  EXPECT_EQ(nowhere.response.keyframes, n);
  EXPECT_NE(access(nowhere.request.path.c_str(), F_OK), 0);
  // A missing file: refused, the database stays.
  LoadDatabase missing;
  missing.request.path = path + ".missing";
  ASSERT_TRUE(ros::service::call("a/loop_closure/load_database", missing));
  EXPECT_FALSE(missing.response.success);
  EXPECT_EQ(missing.response.keyframes, n) << missing.response.message;
  // A file that is no database: refused, and the database stays.
  LoadDatabase bad;
  bad.request.path = "/proc/self/status";
  ASSERT_TRUE(ros::service::call("a/loop_closure/load_database", bad));
  EXPECT_FALSE(bad.response.success);
  EXPECT_EQ(bad.response.keyframes, n) << bad.response.message;

  std_srvs::Trigger reset;
  ASSERT_TRUE(ros::service::call("a/loop_closure/reset", reset));
  EXPECT_TRUE(reset.response.success);
  LoadDatabase load;
  load.request.path = path;
  ASSERT_TRUE(ros::service::call("a/loop_closure/load_database", load));
  ASSERT_TRUE(load.response.success) << load.response.message;
  EXPECT_EQ(load.response.keyframes, n);
  LoadDatabase map;
  map.request.path = path;
  ASSERT_TRUE(ros::service::call("b/loop_closure/load_database", map));
  ASSERT_TRUE(map.response.success) << map.response.message;

  // Node a: the drive again, later; every loop of the first pass's places reaches the loaded session.
  const std::size_t before = a.loops().size();
  a.base += ros::Duration(drive.times.back() + 10.0);
  a.publish(drive, 0, n / 2, 15.0);
  ASSERT_TRUE(a.waitForKeyframes(n + n / 2, 60.0));
  a.settle(3.0, 20.0);
  std::size_t into_loaded = 0;
  const auto loops = a.loops();
  for (std::size_t i = before; i < loops.size(); ++i) into_loaded += loops[i].match_session == 0 ? 1 : 0;
  EXPECT_GE(into_loaded, n / 8) << loops.size() - before << " loops after the load";

  // Node b: a second run over lap 1, its odometry starting from its own origin, 300 m and 90 deg away.
  Eigen::Isometry3d other = Eigen::Isometry3d::Identity();
  other.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  other.translation() = Eigen::Vector3d(300.0, -40.0, 0.0);
  ros::WallRate rate(15.0);
  for (std::size_t k = 0; k < n / 2 && ros::ok(); ++k) {
    nav_msgs::Odometry odom = b.odom(drive, k);
    odom.pose.pose = tf2::toMsg(other * drive.truth[k]);
    b.cloud_pub.publish(b.cloud(drive, k));
    b.odom_pub.publish(odom);
    rate.sleep();
  }
  ASSERT_TRUE(b.waitForKeyframes(n + n / 2, 60.0));
  b.settle(3.0, 20.0);
  {
    const auto relocalized = relocalizations.messages();
    EXPECT_GE(relocalized.size(), n / 8);
    for (const auto& pose : relocalized) {
      EXPECT_EQ(pose.header.frame_id, "map");
      expectAt(drive, keyframeAt(drive, b.base, pose.header.stamp), pose.pose.pose);
      EXPECT_GT(pose.pose.covariance[0], 0.0);
    }
  }

  // On request: one cloud, nothing stored.
  Relocalize where;
  where.request.cloud = b.cloud(drive, 40);
  ASSERT_TRUE(ros::service::call("b/loop_closure/relocalize", where));
  ASSERT_TRUE(where.response.found) << where.response.message;
  expectAt(drive, 40, where.response.pose.pose.pose);
  EXPECT_EQ(where.response.match_session, 0u);
  // Clouds the node cannot use: answered, not found, with the reason; the map still answers after them.
  Relocalize no_z, empty;
  no_z.request.cloud = b.cloud(drive, 40);
  no_z.request.cloud.fields.erase(no_z.request.cloud.fields.begin() + 2);
  ASSERT_TRUE(ros::service::call("b/loop_closure/relocalize", no_z));
  EXPECT_FALSE(no_z.response.found);
  EXPECT_NE(no_z.response.message.find("cloud refused"), std::string::npos) << no_z.response.message;
  empty.request.cloud = b.cloud(drive, 40);
  empty.request.cloud.width = 0;
  empty.request.cloud.row_step = 0;
  empty.request.cloud.data.clear();
  ASSERT_TRUE(ros::service::call("b/loop_closure/relocalize", empty));
  EXPECT_FALSE(empty.response.found) << empty.response.message;
  ASSERT_TRUE(ros::service::call("b/loop_closure/relocalize", where));
  EXPECT_TRUE(where.response.found) << where.response.message;
  unlink(path.c_str());
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeFile(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

bool exists(const std::string& path) {
  struct stat st;
  return ::lstat(path.c_str(), &st) == 0;
}

/// The files in /tmp whose names begin with `prefix`, but for `except`.
std::vector<std::string> tmpFiles(const std::string& prefix, const std::string& except) {
  std::vector<std::string> names;
  DIR* dir = ::opendir("/tmp");
  for (dirent* e = dir ? ::readdir(dir) : nullptr; e; e = ::readdir(dir)) {
    const std::string name = e->d_name;
    if (name.compare(0, prefix.size(), prefix) == 0 && "/tmp/" + name != except) names.push_back("/tmp/" + name);
  }
  if (dir) ::closedir(dir);
  return names;
}

/// Saves node a's database to `name` in its map directory (/tmp).
void saveFromA(const std::string& name) {
  SaveDatabase save;
  save.request.path = name;
  ASSERT_TRUE(ros::service::call("a/loop_closure/save_database", save));
  ASSERT_TRUE(save.response.success) << save.response.message;
}

// ~save_database writes only inside database_directory (/tmp for node a), never over a file that is no
// database; a replaced database is kept as <path>.bak and the file keeps its mode.
TEST(Relocalization, SavesStayInTheMapDirectoryKeepABackupAndReplaceNoOtherFile) {
  ros::NodeHandle a_nh("a");
  Harness a(a_nh);
  ASSERT_TRUE(a.waitForNode(30.0));
  const std::string id = std::to_string(getpid());
  const auto refused = [](const std::string& path, const std::string& why) {
    SaveDatabase save;
    save.request.path = path;
    EXPECT_TRUE(ros::service::call("a/loop_closure/save_database", save));
    EXPECT_FALSE(save.response.success) << path;
    EXPECT_NE(save.response.message.find(why), std::string::npos) << path << ": " << save.response.message;
  };
  refused("../scl_up_" + id + ".scdb", "\"..\"");
  EXPECT_FALSE(exists("/scl_up_" + id + ".scdb"));
  refused("/etc/scl_outside_" + id + ".scdb", "outside the map directory");
  EXPECT_FALSE(exists("/etc/scl_outside_" + id + ".scdb"));
  refused("/var/tmp/scl_outside_" + id + ".scdb", "outside the map directory");
  EXPECT_FALSE(exists("/var/tmp/scl_outside_" + id + ".scdb"));
  const std::string link = "/tmp/scl_link_" + id;
  ASSERT_EQ(::symlink("/var/tmp", link.c_str()), 0);
  refused("scl_link_" + id + "/map.scdb", "outside the map directory");
  EXPECT_FALSE(exists("/var/tmp/map.scdb"));
  ::unlink(link.c_str());
  ASSERT_EQ(::symlink(("/tmp/scl_link_target_" + id).c_str(), link.c_str()), 0);
  refused("scl_link_" + id, "symbolic link");
  EXPECT_FALSE(exists("/tmp/scl_link_target_" + id));
  ::unlink(link.c_str());
  const std::string notes = "/tmp/scl_notes_" + id + ".txt";
  writeFile(notes, "not a map\n");
  refused("scl_notes_" + id + ".txt", "not a Scan Context database");
  EXPECT_EQ(readFile(notes), "not a map\n");
  EXPECT_FALSE(exists(notes + ".bak"));
  ::unlink(notes.c_str());

  const std::string map = "/tmp/scl_map_" + id + ".scdb";
  saveFromA("scl_map_" + id + ".scdb");
  EXPECT_FALSE(exists(map + ".bak")) << "nothing was replaced";
  const std::string first = readFile(map);
  ASSERT_FALSE(first.empty());
  ASSERT_EQ(::chmod(map.c_str(), 0600), 0);
  saveFromA(map);
  EXPECT_EQ(readFile(map + ".bak"), first) << "the backup is the file the second save replaced";
  struct stat st;
  ASSERT_EQ(::stat(map.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 0600u) << "the replaced file's mode is kept";
  ::unlink(map.c_str());
  ::unlink((map + ".bak").c_str());
}

/// Loads a loop-closure nodelet named `name` into /manager with the private parameters `params` (each
/// set before the load), runs `between` while it is up, then unloads it.
void runNodelet(const std::string& name, const std::map<std::string, XmlRpc::XmlRpcValue>& params,
                const std::function<void()>& between) {
  for (const auto& p : params) ros::param::set(name + "/" + p.first, p.second);
  nodelet::NodeletLoad load;
  load.request.name = name;
  load.request.type = "scan_context_loop/LoopClosureNodelet";
  ASSERT_TRUE(ros::service::call("/manager/load_nodelet", load));
  ASSERT_TRUE(load.response.success);
  EXPECT_TRUE(ros::service::waitForService(name + "/reset", 30000));
  between();
  nodelet::NodeletUnload unload;
  unload.request.name = name;
  ASSERT_TRUE(ros::service::call("/manager/unload_nodelet", unload));
  EXPECT_TRUE(unload.response.success);
}

/// runNodelet with `database_load` and `database_save` both `map` (and `num_sectors` when non-zero).
void runNodeletOver(const std::string& name, const std::string& map, int num_sectors,
                    const std::function<void()>& between) {
  std::map<std::string, XmlRpc::XmlRpcValue> params = {{"database_load", map}, {"database_save", map}};
  if (num_sectors > 0) params["num_sectors"] = num_sectors;
  runNodelet(name, params, between);
}

/// The keyframes in the database file at `path` (read with the default settings), -1 when it does not load.
long keyframesIn(const std::string& path) {
  PriorSessions sessions;
  std::string error;
  return readDatabaseFile(path, Config(), &sessions, &error) ? static_cast<long>(sessions.keyframes.size()) : -1;
}

/// Waits until keyframesIn(path) is `count` (at most `seconds`); returns the last count seen.
long waitForFile(const std::string& path, long count, double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  long seen = keyframesIn(path);
  while (seen != count && ros::WallTime::now() < end) {
    ros::WallDuration(0.1).sleep();
    seen = keyframesIn(path);
  }
  return seen;
}

// With database_autosave_seconds the database reaches database_save while the node runs, so a crash
// loses at most that much: the file holds the keyframes processed so far, the file it replaced is kept as
// .bak, the diagnostics count the saves, and no keyframe was dropped for them. A temporary file an
// earlier run's unfinished save left beside the map is removed at start.
TEST(Relocalization, AutosavesWriteTheDatabaseWhileTheNodeRuns) {
  const std::string map = "/tmp/scl_autosave_" + std::to_string(getpid()) + ".scdb";
  ros::NodeHandle e_nh("e");
  Harness e(e_nh);
  DiagnosticsWatch diagnostics(e_nh, "e/loop_closure");
  const Drive drive = blockDrive(true, 7);
  const std::size_t n = drive.truth.size(), half = n / 2;
  const std::string abandoned = map + ".tmp.Dead00";  // what a save left when its process died
  std::ofstream(abandoned) << "an unfinished save";
  runNodelet(
      "/e/loop_closure",
      {{"database_save", map}, {"database_autosave_seconds", 0.5}, {"queue_size", 2000}, {"exclude_recent_frames", 30}},
      [&] {
        ASSERT_TRUE(e.waitForNode(30.0));
        e.publish(drive, 0, half, 15.0);
        ASSERT_TRUE(e.waitForKeyframes(half, 60.0));
        EXPECT_EQ(waitForFile(map, static_cast<long>(half), 20.0), static_cast<long>(half))
            << "no autosave of the first half while the node runs";
        e.publish(drive, half, n, 15.0);
        ASSERT_TRUE(e.waitForKeyframes(n, 60.0));
        EXPECT_EQ(waitForFile(map, static_cast<long>(n), 20.0), static_cast<long>(n))
            << "no autosave of the whole drive while the node runs";
        EXPECT_GE(keyframesIn(map + ".bak"), static_cast<long>(half)) << "the replaced autosave is kept";
        const ros::WallTime now = ros::WallTime::now();
        EXPECT_GE(diagnostics.value("database saves", now, 10.0), 2);
        EXPECT_EQ(diagnostics.value("database saves failed", now, 10.0), 0);
        EXPECT_EQ(diagnostics.value("keyframes dropped", now, 10.0), 0);
      });
  EXPECT_NE(::access(abandoned.c_str(), F_OK), 0) << "an abandoned save's temporary file is removed at start";
  EXPECT_EQ(keyframesIn(map), static_cast<long>(n)) << "the shutdown save";
  ::unlink(map.c_str());
  ::unlink((map + ".bak").c_str());
}

// A map the node cannot load at start (other settings: 30 sectors against its 60) is not saved over at
// shutdown: it stays byte for byte, and the run's database goes beside it. The same after a ~reset.
TEST(Relocalization, AMapThatFailedToLoadOrWasResetIsNeverSavedOver) {
  ros::NodeHandle a_nh("a");
  Harness a(a_nh);
  ASSERT_TRUE(a.waitForNode(30.0));
  const std::string id = std::to_string(getpid());

  const std::string other = "/tmp/scl_other_settings_" + id + ".scdb";
  saveFromA(other);
  const std::string bytes = readFile(other);
  runNodeletOver("/c/loop_closure", other, 30, [] {});
  EXPECT_EQ(readFile(other), bytes) << "the map that failed to load is kept byte for byte";
  EXPECT_FALSE(exists(other + ".bak"));
  const std::vector<std::string> beside = tmpFiles("scl_other_settings_" + id + ".", other);
  ASSERT_EQ(beside.size(), 1u) << "the shutdown save goes beside the map";
  EXPECT_NE(beside[0].find(".scdb"), std::string::npos) << beside[0];
  EXPECT_EQ(readFile(beside[0]).compare(0, 5, "SCLDB"), 0) << beside[0];

  const std::string reset_map = "/tmp/scl_reset_" + id + ".scdb";
  saveFromA(reset_map);
  const std::string reset_bytes = readFile(reset_map);
  runNodeletOver("/d/loop_closure", reset_map, 0, [] {
    std_srvs::Trigger reset;
    ASSERT_TRUE(ros::service::call("/d/loop_closure/reset", reset));
    EXPECT_TRUE(reset.response.success);
  });
  EXPECT_EQ(readFile(reset_map), reset_bytes) << "the map is kept byte for byte after a ~reset";
  EXPECT_EQ(tmpFiles("scl_reset_" + id + ".", reset_map).size(), 1u) << "the shutdown save goes beside the map";

  for (const auto& path : tmpFiles("scl_other_settings_" + id, "")) ::unlink(path.c_str());
  for (const auto& path : tmpFiles("scl_reset_" + id, "")) ::unlink(path.c_str());
}

// A map already at database_save that the node did not load (database_load misspelt, or empty) is not
// the run's to replace: it stays byte for byte over two runs, each of which saves beside it. With
// database_save_overwrite it is replaced, and kept as .bak.
TEST(Relocalization, AMapAtDatabaseSaveThatWasNotLoadedIsReplacedOnlyWhenAllowed) {
  ros::NodeHandle a_nh("a");
  Harness a(a_nh);
  ASSERT_TRUE(a.waitForNode(30.0));
  const std::string id = std::to_string(getpid()), prefix = "scl_not_loaded_" + id + ".";
  const std::string map = "/tmp/" + prefix + "scdb";
  saveFromA(prefix + "scdb");
  const std::string bytes = readFile(map);
  ASSERT_FALSE(bytes.empty());

  runNodelet("/g/loop_closure", {{"database_load", "/tmp/scl_not_laoded_" + id + ".scdb"}, {"database_save", map}},
             [] {});
  EXPECT_EQ(readFile(map), bytes) << "a misspelt database_load: the map is kept byte for byte";
  EXPECT_EQ(tmpFiles(prefix, map).size(), 1u) << "the run's database goes beside the map";
  runNodelet("/h/loop_closure", {{"database_save", map}}, [] {});
  EXPECT_EQ(readFile(map), bytes) << "no database_load: the map is kept byte for byte";
  EXPECT_FALSE(exists(map + ".bak"));
  EXPECT_EQ(tmpFiles(prefix, map).size(), 2u) << "each run's database goes beside the map";

  for (const auto& path : tmpFiles(prefix, map)) ::unlink(path.c_str());
  runNodelet("/i/loop_closure", {{"database_save", map}, {"database_save_overwrite", true}}, [] {});
  EXPECT_NE(readFile(map), bytes) << "database_save_overwrite: the map is replaced";
  EXPECT_EQ(readFile(map + ".bak"), bytes) << "and kept as .bak";
  EXPECT_EQ(tmpFiles(prefix, map), std::vector<std::string>{map + ".bak"}) << "nothing beside it";
  for (const auto& path : tmpFiles(prefix, "")) ::unlink(path.c_str());
}

/// The diagnostics' `key` of the watched node, from a status that arrived after `after`, once it is above
/// `above` (at most `seconds`); the largest seen, -1 when none came.
long waitForDiagnostic(const DiagnosticsWatch& watch, const std::string& key, long above, const ros::WallTime& after,
                       double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  long seen = -1;
  while (seen <= above && ros::WallTime::now() < end) seen = std::max(seen, watch.value(key, after, 1.0));
  return seen;
}

// An autosave that fails (fsync fails with EIO while the fault file exists: a failing or full disk) is
// tried again at the next autosave, though the database no longer changes; once the fault is gone the
// file is written. The node runs standalone, the file-fault library preloaded.
TEST(Relocalization, AFailedAutosaveIsTriedAgainUntilItIsWritten) {
  const std::string id = std::to_string(getpid()), prefix = "scl_retry_" + id + ".scdb";
  const std::string map = "/tmp/" + prefix, faults = "/tmp/scl_faults_" + id;
  ros::NodeHandle f_nh("f");
  Harness f(f_nh);
  DiagnosticsWatch diagnostics(f_nh, "f/loop_closure");
  Child node({"scan_context_loop", "loop_closure_node", "__ns:=f", "__name:=loop_closure", "_database_save:=" + map,
              "_database_autosave_seconds:=0.5", "_queue_size:=2000", "_exclude_recent_frames:=30"},
             {std::string("LD_PRELOAD=") + SCL_FILE_FAULTS_LIBRARY, "SCL_FILE_FAULTS=" + faults});
  ASSERT_GT(node.pid(), 0);
  ASSERT_TRUE(f.waitForNode(60.0)) << "the node never subscribed";
  writeFile(faults, "fsync EIO\n");
  const Drive drive = blockDrive(true, 7);
  const std::size_t n = 40;
  f.publish(drive, 0, n, 15.0);
  ASSERT_TRUE(f.waitForKeyframes(n, 60.0));
  ros::WallDuration(1.5).sleep();  // the autosaves of the whole database have begun to fail
  const long failed = waitForDiagnostic(diagnostics, "database saves failed", 0, ros::WallTime::now(), 10.0);
  EXPECT_GT(failed, 0) << "no autosave failed";
  EXPECT_GT(waitForDiagnostic(diagnostics, "database saves failed", failed, ros::WallTime::now(), 15.0), failed)
      << "the database no longer changes, and the failed autosave is not tried again";
  // Autosaves go on every 0.5 s, so one may be writing its temporary file at any moment: a failed one
  // must leave nothing, so between them nothing is there (a file left behind would always be).
  bool nothing_there = false;
  for (const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(10.0);
       !nothing_there && ros::WallTime::now() < end; ros::WallDuration(0.01).sleep()) {
    nothing_there = tmpFiles(prefix, "").empty();
  }
  EXPECT_TRUE(nothing_there) << "nothing written, and no temporary file left: " << tmpFiles(prefix, "").size();

  ::unlink(faults.c_str());
  EXPECT_EQ(waitForFile(map, static_cast<long>(n), 10.0), static_cast<long>(n))
      << "the fault is gone, and the next autosave does not write the file";
  double took = 0.0;
  EXPECT_TRUE(node.stop(SIGINT, 20.0, &took)) << "no exit after SIGINT";
  EXPECT_TRUE(node.exitedCleanly()) << node.how();
  for (const auto& path : tmpFiles(prefix, "")) ::unlink(path.c_str());
}

// The shutdown save is bounded (database_shutdown_seconds, 1 s here): on a disk so slow that it cannot
// finish in time (each pwrite waits 2 s while the fault file exists; a save makes three or more), SIGINT
// ends the node within the bound and one slow call, the write is cancelled, and nothing is left at
// database_save, neither a file nor a temporary one. Unbounded, the node would exit only once the file was
// written.
TEST(Relocalization, AShutdownSaveThatDoesNotFitIsCancelled) {
  const std::string id = std::to_string(getpid()), prefix = "scl_bounded_" + id + ".scdb";
  const std::string map = "/tmp/" + prefix, faults = "/tmp/scl_slow_" + id;
  ros::NodeHandle g_nh("g");
  Harness g(g_nh);
  Child node({"scan_context_loop", "loop_closure_node", "__ns:=g", "__name:=loop_closure", "_database_save:=" + map,
              "_database_autosave_seconds:=0", "_database_shutdown_seconds:=1.0", "_queue_size:=2000",
              "_exclude_recent_frames:=30"},
             {std::string("LD_PRELOAD=") + SCL_FILE_FAULTS_LIBRARY, "SCL_FILE_FAULTS=" + faults});
  ASSERT_GT(node.pid(), 0);
  ASSERT_TRUE(g.waitForNode(60.0)) << "the node never subscribed";
  const Drive drive = blockDrive(true, 7);
  const std::size_t n = 40;
  g.publish(drive, 0, n, 15.0);
  ASSERT_TRUE(g.waitForKeyframes(n, 60.0));
  writeFile(faults, "pwrite DELAY2000\n");
  double took = 0.0;
  EXPECT_TRUE(node.stop(SIGINT, 30.0, &took)) << "no exit after SIGINT";
  EXPECT_LT(took, 5.5) << "the shutdown save took longer than its bound and one slow write";
  EXPECT_TRUE(node.exitedCleanly()) << node.how();
  ::unlink(faults.c_str());
  EXPECT_FALSE(exists(map)) << "the save was not cancelled";
  EXPECT_TRUE(tmpFiles(prefix, "").empty()) << "the cancelled save left a temporary file";
  ::unlink(map.c_str());
}

}  // namespace
}  // namespace test
}  // namespace scan_context_loop

int main(int argc, char** argv) { return scan_context_loop::test::runRosTests(argc, argv, "test_relocalization"); }
