// Where ~save_database may write (servicePath), the map directory's default, and the file a shutdown
// save writes beside a map it must not replace.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "shared/database_paths.h"

namespace scan_context_loop {
namespace {

/// A fresh directory holding `maps/` (the map directory), removed at the end.
class MapDirectory : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string name = "/tmp/scl_database_paths_XXXXXX";
    root_ = ::mkdtemp(&name[0]);
    char resolved[4096];
    root_ = ::realpath(root_.c_str(), resolved);
    maps_ = root_ + "/maps";
    ::mkdir(maps_.c_str(), 0755);
  }
  void TearDown() override { std::system(("rm -rf '" + root_ + "'").c_str()); }
  std::string root_, maps_;
};

TEST_F(MapDirectory, ANameInsideIsTakenAndAbsolutePathsInsideToo) {
  std::string path, error;
  ASSERT_TRUE(servicePath(maps_, "map.scdb", &path, &error)) << error;
  EXPECT_EQ(path, maps_ + "/map.scdb");
  ::mkdir((maps_ + "/site").c_str(), 0755);
  ASSERT_TRUE(servicePath(maps_, "site/map.scdb", &path, &error)) << error;
  EXPECT_EQ(path, maps_ + "/site/map.scdb");
  ASSERT_TRUE(servicePath(maps_, maps_ + "/./map.scdb", &path, &error)) << error;
  EXPECT_EQ(path, maps_ + "/map.scdb");
}

TEST_F(MapDirectory, DotDotAbsolutePathsOutsideAndSymlinksOutAreRefused) {
  std::string path = "unchanged", error;
  EXPECT_FALSE(servicePath(maps_, "../x.scdb", &path, &error));
  EXPECT_NE(error.find(".."), std::string::npos) << error;
  EXPECT_FALSE(servicePath(maps_, "site/../../x.scdb", &path, &error));
  EXPECT_FALSE(servicePath(maps_, "/etc/x.scdb", &path, &error));
  EXPECT_NE(error.find("outside the map directory"), std::string::npos) << error;
  EXPECT_FALSE(servicePath(maps_, root_ + "/x.scdb", &path, &error));
  ::mkdir((root_ + "/mapsx").c_str(), 0755);
  EXPECT_FALSE(servicePath(maps_ + "/", root_ + "/mapsx/x.scdb", &path, &error)) << "a prefix is not inside";
  EXPECT_NE(error.find("outside the map directory"), std::string::npos) << error;
  // A directory link leading out of the map directory, and a final component that is a link.
  ASSERT_EQ(::symlink(root_.c_str(), (maps_ + "/out").c_str()), 0);
  EXPECT_FALSE(servicePath(maps_, "out/x.scdb", &path, &error));
  EXPECT_NE(error.find("outside the map directory"), std::string::npos) << error;
  ASSERT_EQ(::symlink((maps_ + "/target.scdb").c_str(), (maps_ + "/link.scdb").c_str()), 0);
  EXPECT_FALSE(servicePath(maps_, "link.scdb", &path, &error));
  EXPECT_NE(error.find("symbolic link"), std::string::npos) << error;
  EXPECT_FALSE(servicePath(maps_, "", &path, &error));
  EXPECT_FALSE(servicePath(maps_, "missing/x.scdb", &path, &error));
  EXPECT_EQ(path, "unchanged");
}

TEST_F(MapDirectory, ADirectoryToWriteInIsCheckedTheSameWayAndTheMessagesNameTheSetting) {
  // The pose_graph node's ~save_map: the last component names a directory inside map_directory.
  std::string path, error;
  ASSERT_TRUE(servicePath(maps_, "run1", &path, &error, "map_directory")) << error;
  EXPECT_EQ(path, maps_ + "/run1");
  EXPECT_FALSE(servicePath(maps_, root_, &path, &error, "map_directory"));
  EXPECT_NE(error.find("outside the map directory " + maps_ + " (map_directory)"), std::string::npos) << error;
  ASSERT_EQ(::symlink(root_.c_str(), (maps_ + "/linked").c_str()), 0);
  EXPECT_FALSE(servicePath(maps_, "linked", &path, &error, "map_directory"));
  EXPECT_NE(error.find("symbolic link"), std::string::npos) << error;
}

TEST_F(MapDirectory, AMissingMapDirectoryIsCreated) {
  std::string path, error;
  ASSERT_TRUE(servicePath(maps_ + "/new/deeper", "map.scdb", &path, &error)) << error;
  EXPECT_EQ(path, maps_ + "/new/deeper/map.scdb");
  struct stat st;
  EXPECT_EQ(::stat((maps_ + "/new/deeper").c_str(), &st), 0);
}

TEST(MapDirectoryDefault, TheSettingElseTheSaveElseTheLoadDirectoryElseRosHome) {
  NodeOptions options;
  ::setenv("ROS_HOME", "/home/robot/.ros", 1);
  EXPECT_EQ(mapDirectory(options), "/home/robot/.ros/scan_context_loop");
  options.database_load = "/maps/in/old.scdb";
  EXPECT_EQ(mapDirectory(options), "/maps/in");
  options.database_save = "/maps/out/new.scdb";
  EXPECT_EQ(mapDirectory(options), "/maps/out");
  options.database_directory = "/maps";
  EXPECT_EQ(mapDirectory(options), "/maps");
}

TEST_F(MapDirectory, TheFileBesideAMapTakesTheTimeAndANameNoFileHas) {
  EXPECT_EQ(besidePath(maps_ + "/map.scdb", 1700000000), maps_ + "/map.1700000000.scdb");
  EXPECT_EQ(besidePath(maps_ + "/map", 1700000000), maps_ + "/map.1700000000.scdb");
  ::close(::open((maps_ + "/map.1700000000.scdb").c_str(), O_CREAT | O_WRONLY, 0644));
  EXPECT_EQ(besidePath(maps_ + "/map.scdb", 1700000000), maps_ + "/map.1700000000-1.scdb");
  ::close(::open((maps_ + "/map.scdb").c_str(), O_CREAT | O_WRONLY, 0644));
  EXPECT_TRUE(sameFile(maps_ + "/map.scdb", maps_ + "/./map.scdb"));
  EXPECT_FALSE(sameFile(maps_ + "/map.scdb", maps_ + "/map.1700000000.scdb"));
  EXPECT_FALSE(sameFile(maps_ + "/map.scdb", maps_ + "/missing.scdb"));
}

}  // namespace
}  // namespace scan_context_loop
