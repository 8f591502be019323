// FileReader hands out contiguous pieces of any size across its buffer's refills; AtomicFileWriter
// leaves nothing behind unless committed, replaces only a regular file, and keeps the old file (and
// leaves no temporary file) when the file system fails it (faults injected with FileFaults); what a dead
// writer left is removed.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <future>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <fcntl.h>
#include <linux/magic.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/statfs.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include "scan_context_loop/core/file_io.h"
#include "../common/file_faults.h"
#include "../common/temp_dir.h"

namespace scan_context_loop {
namespace {

namespace fs = std::filesystem;

std::uint8_t patternAt(std::size_t i) { return static_cast<std::uint8_t>((i * 2654435761u) >> 13); }

TEST(FileReader, PiecesOfAnySizeAcrossRefillsHoldTheFileInOrder) {
  const fs::path path = fs::temp_directory_path() / ("scl_file_io_" + std::to_string(::getpid()));
  const std::size_t size = 3 * (std::size_t(1) << 20) + 12345;  // several of the reader's 1 MB refills
  {
    std::ofstream out(path, std::ios::binary);
    for (std::size_t i = 0; i < size; ++i) out.put(static_cast<char>(patternAt(i)));
  }
  FileReader reader;
  std::string error;
  ASSERT_TRUE(reader.open(path.string(), &error)) << error;
  EXPECT_EQ(reader.size(), size);
  std::size_t offset = 0;
  // Small, odd-sized, larger than the buffer, then exactly what is left.
  for (std::size_t piece : {std::size_t(7), std::size_t(1048570), std::size_t(1), std::size_t(2100000), std::size_t(3),
                            size - 7 - 1048570 - 1 - 2100000 - 3}) {
    const std::uint8_t* p = reader.take(piece);
    ASSERT_NE(p, nullptr) << "at " << offset << " taking " << piece;
    for (std::size_t i = 0; i < piece; ++i) {
      if (p[i] != patternAt(offset + i)) FAIL() << "byte " << offset + i << " differs";
    }
    offset += piece;
  }
  EXPECT_EQ(reader.take(1), nullptr) << "the file has ended";
  EXPECT_TRUE(reader.readError().empty());
  fs::remove(path);
}

/// A Unix socket bound at `path`, so that a socket file is there; -1 when it cannot be made.
int bindSocket(const std::string& path) {
  const int sock = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::snprintf(address.sun_path, sizeof(address.sun_path), "%s", path.c_str());
  if (sock >= 0 && ::bind(sock, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) == 0) return sock;
  if (sock >= 0) ::close(sock);
  return -1;
}

TEST(FileReader, RefusesFifosSocketsDevicesAndDirectoriesWithoutBlocking) {
  const fs::path dir = fs::temp_directory_path() / ("scl_file_types_" + std::to_string(::getpid()));
  fs::create_directory(dir);
  const std::string fifo = (dir / "fifo").string(), socket_path = (dir / "socket").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const int sock = bindSocket(socket_path);
  ASSERT_GE(sock, 0);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {fifo, "named pipe (FIFO)"}, {socket_path, "socket"}, {"/dev/null", "device"}, {dir.string(), "directory"}};
  for (const auto& [path, word] : cases) {
    SCOPED_TRACE(path);
    // Opened on another thread, so that a reader blocking on the FIFO fails the test instead of hanging it.
    auto opened = std::async(std::launch::async, [path = path] {
      FileReader reader;
      std::string error;
      const bool ok = reader.open(path, &error);
      return std::make_pair(ok, error);
    });
    if (opened.wait_for(std::chrono::seconds(2)) != std::future_status::ready) {
      ADD_FAILURE() << "opening blocked";
      ::close(::open(path.c_str(), O_WRONLY | O_NONBLOCK));  // a writer comes and goes: the open returns
    }
    const auto [ok, error] = opened.get();
    EXPECT_FALSE(ok);
    EXPECT_NE(error.find(path), std::string::npos) << error;
    EXPECT_NE(error.find(word), std::string::npos) << error;
  }
  ::close(sock);
  fs::remove_all(dir);
}

TEST(AtomicFileWriter, WithoutCommitNothingIsLeftAndTheTargetIsUntouched) {
  const fs::path dir = fs::temp_directory_path() / ("scl_atomic_" + std::to_string(::getpid()));
  fs::create_directory(dir);
  const std::string target = (dir / "file").string();
  std::ofstream(target) << "old";
  {
    AtomicFileWriter writer;
    std::string error;
    ASSERT_TRUE(writer.open(target, &error)) << error;
    ASSERT_TRUE(writer.write("new contents", 12, &error)) << error;
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 2) << "the temporary file";
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
  std::string text;
  std::ifstream(target) >> text;
  EXPECT_EQ(text, "old");
  fs::remove_all(dir);
}

// A cancelled write (a shutdown save past its time) stops at its next piece: the target stays as it was
// and the temporary file goes.
TEST(AtomicFileWriter, ACancelledWriteLeavesTheTargetAndNoTemporaryFile) {
  const fs::path dir = fs::temp_directory_path() / ("scl_cancel_" + std::to_string(::getpid()));
  fs::create_directory(dir);
  const std::string target = (dir / "file").string();
  std::ofstream(target) << "old";
  std::atomic<bool> cancel{false};
  for (const bool at_commit : {false, true}) {
    AtomicFileWriter writer;
    writer.cancelWhen(&cancel);
    std::string error;
    ASSERT_TRUE(writer.open(target, &error)) << error;
    ASSERT_TRUE(writer.write("new ", 4, &error)) << error;
    cancel = true;
    EXPECT_FALSE(at_commit ? writer.commit(&error) : writer.write("contents", 8, &error));
    EXPECT_NE(error.find("cancelled"), std::string::npos) << error;
    EXPECT_FALSE(writer.commit(&error)) << "a cancelled write committed";
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1) << "a temporary file is left";
    std::string text;
    std::ifstream(target) >> text;
    EXPECT_EQ(text, "old");
    cancel = false;
  }
  fs::remove_all(dir);
}

// A large save goes to disk while it is written: every piece but the last two is on disk and out of the
// page cache before commit(), so its fsync has little left to flush (other processes' disk writes
// never wait behind the whole file), and the file is whole.
TEST(AtomicFileWriter, WritesBehindSoThatCommitHasLittleLeftToFlush) {
  test::TempDir dir("scl_write_behind");
  struct statfs fs_info;
  ASSERT_EQ(::statfs(dir.file("").c_str(), &fs_info), 0);
  if (fs_info.f_type == TMPFS_MAGIC)
    GTEST_SKIP() << "the temporary directory is in memory (tmpfs): no disk to write to";
  const std::string path = dir.file("big");
  const std::size_t piece = std::size_t(1) << 20, total = 4 * AtomicFileWriter::kWriteBehindBytes;
  AtomicFileWriter writer;
  std::string error;
  ASSERT_TRUE(writer.open(path, &error)) << error;
  std::vector<std::uint8_t> data(piece);
  for (std::size_t at = 0; at < total; at += piece) {
    for (std::size_t i = 0; i < piece; ++i) data[i] = patternAt(at + i);
    ASSERT_TRUE(writer.write(data.data(), piece, &error)) << error;
  }
  const std::vector<std::string> entries = dir.entries();
  ASSERT_EQ(entries.size(), 1u) << "the temporary file alone, before commit";
  const int fd = ::open(dir.file(entries[0]).c_str(), O_RDONLY | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  void* map = ::mmap(nullptr, total, PROT_READ, MAP_SHARED, fd, 0);
  ASSERT_NE(map, MAP_FAILED);
  const std::size_t page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE)),
                    settled = 2 * AtomicFileWriter::kWriteBehindBytes;
  std::vector<unsigned char> resident(total / page);
  ASSERT_EQ(::mincore(map, total, resident.data()), 0);
  std::size_t cached = 0;
  for (std::size_t p = 0; p < settled / page; ++p) cached += resident[p] & 1u;
  ::munmap(map, total);
  ::close(fd);
  EXPECT_LT(cached, settled / page / 20) << cached << " of the first " << settled / page
                                         << " pages still in the page cache: nothing was written behind";
  ASSERT_TRUE(writer.commit(&error)) << error;
  std::ifstream in(path, std::ios::binary);
  std::size_t at = 0, wrong = 0;
  for (char c; in.get(c); ++at) wrong += static_cast<std::uint8_t>(c) != patternAt(at);
  EXPECT_EQ(at, total);
  EXPECT_EQ(wrong, 0u);
}

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Writes `bytes` to `path` through an AtomicFileWriter, keeping `path`.bak when `backup`; commit's result.
bool save(const std::string& path, const std::string& bytes, bool backup, std::string* error) {
  AtomicFileWriter writer;
  if (!writer.open(path, error)) return false;
  if (backup) writer.keepBackup(path + ".bak");
  return writer.write(bytes.data(), bytes.size(), error) && writer.commit(error);
}

// A FIFO, a socket or a device where the file should be is not the writer's to replace: open() refuses
// it, naming the path and what it is, and creates nothing.
TEST(AtomicFileWriter, ATargetThatIsNoRegularFileIsRefusedAndLeftAlone) {
  test::TempDir dir("scl_atomic_types");
  const std::string fifo = dir.file("fifo"), socket_path = dir.file("socket");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const int sock = bindSocket(socket_path);
  ASSERT_GE(sock, 0);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {fifo, "named pipe (FIFO)"}, {socket_path, "socket"}, {"/dev/null", "device"}, {dir.file(""), "directory"}};
  for (const auto& [path, word] : cases) {
    SCOPED_TRACE(path);
    AtomicFileWriter writer;
    std::string error;
    EXPECT_FALSE(writer.open(path, &error));
    EXPECT_NE(error.find(path), std::string::npos) << error;
    EXPECT_NE(error.find(word), std::string::npos) << error;
  }
  ::close(sock);
  struct stat st;
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  ASSERT_EQ(::lstat(socket_path.c_str(), &st), 0);
  EXPECT_TRUE(S_ISSOCK(st.st_mode));
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"fifo", "socket"})) << "no temporary file";
}

// A replaced file keeps its mode, but its owner can always read and write the new one: a map saved over
// a mode 000 file must load in the next run. (Root reads a mode 000 file anyway: the bits are checked.)
TEST(AtomicFileWriter, AReplacedFileKeepsItsModeWithReadAndWriteForItsOwner) {
  test::TempDir dir("scl_atomic_mode");
  const std::string path = dir.file("map");
  for (const auto& [before, after] : std::vector<std::pair<mode_t, mode_t>>{{0, 0600}, {0444, 0644}, {0640, 0640}}) {
    SCOPED_TRACE(before);
    std::ofstream(path) << "old";
    ASSERT_EQ(::chmod(path.c_str(), before), 0);
    std::string error;
    ASSERT_TRUE(save(path, "new", false, &error)) << error;
    struct stat st;
    ASSERT_EQ(::stat(path.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 07777, after);
    EXPECT_EQ(readAll(path), "new");
  }
}

/// Faults injected into the file-system calls of a save, cleared after each test.
class SaveFaults : public ::testing::Test {
 protected:
  void SetUp() override { std::ofstream(path_, std::ios::binary) << old_; }
  void TearDown() override { test::FileFaults::clear(); }
  /// The old file is there as it was, and no temporary file is left (nor a backup, unless `backup`).
  void expectOldFileAlone(bool backup) {
    EXPECT_EQ(readAll(path_), old_);
    std::vector<std::string> expected = {"map"};
    if (backup) expected.push_back("map.bak");
    EXPECT_EQ(dir_.entries(), expected);
  }
  test::TempDir dir_{"scl_save_faults"};
  const std::string path_ = dir_.file("map"), old_ = "the old map";
};

// vfat and exFAT have no hard links (link fails with EPERM), some file systems say EOPNOTSUPP: the backup
// is then a copy of the old file, and the save goes on.
TEST_F(SaveFaults, WithoutHardLinksTheBackupIsACopyOfTheOldFile) {
  for (const int error : {EPERM, EOPNOTSUPP, EXDEV, EMLINK}) {
    SCOPED_TRACE(std::strerror(error));
    SetUp();
    ::unlink((path_ + ".bak").c_str());
    test::FileFaults::fail("link", error);
    std::string why;
    EXPECT_TRUE(save(path_, "the new map", true, &why)) << why;
    EXPECT_GE(test::FileFaults::failures("link"), 1);
    EXPECT_EQ(readAll(path_), "the new map");
    EXPECT_EQ(readAll(path_ + ".bak"), old_);
    EXPECT_EQ(dir_.entries(), (std::vector<std::string>{"map", "map.bak"})) << "no temporary file";
    test::FileFaults::clear();
  }
}

// Any other link error (EIO, ENOSPC) fails the save before anything is replaced.
TEST_F(SaveFaults, AFailedLinkOfTheBackupFailsTheSaveAndKeepsTheOldFile) {
  test::FileFaults::fail("link", EIO);
  std::string why;
  EXPECT_FALSE(save(path_, "the new map", true, &why));
  EXPECT_NE(why.find(path_ + ".bak"), std::string::npos) << why;
  EXPECT_NE(why.find(std::strerror(EIO)), std::string::npos) << why;
  expectOldFileAlone(false);
}

// A write-behind that reports EIO: since Linux 4.14 the report clears the error, so the fsync after it
// succeeds; the writer must remember it and refuse to rename a file with lost pages over the old one.
TEST_F(SaveFaults, AWriteErrorDuringTheWriteBehindFailsTheCommit) {
  const std::string big(AtomicFileWriter::kWriteBehindBytes + 1000, 'x');
  test::FileFaults::fail("sync_file_range", EIO);
  std::string why;
  EXPECT_FALSE(save(path_, big, true, &why));
  EXPECT_GE(test::FileFaults::failures("sync_file_range"), 1) << "no write-behind";
  EXPECT_NE(why.find(path_ + ".tmp."), std::string::npos) << why;
  EXPECT_NE(why.find(std::strerror(EIO)), std::string::npos) << why;
  expectOldFileAlone(false);
  // ENOSYS, EINVAL, ESPIPE: no sync_file_range here; nothing was lost, and the save goes on.
  for (const int unsupported : {ENOSYS, EINVAL, ESPIPE}) {
    SCOPED_TRACE(std::strerror(unsupported));
    test::FileFaults::fail("sync_file_range", unsupported);
    EXPECT_TRUE(save(path_, big, false, &why)) << why;
    EXPECT_EQ(readAll(path_).size(), big.size());
  }
}

// A failed fsync keeps the old file and leaves no temporary file; a failed rename (here the backup's,
// the first) too.
TEST_F(SaveFaults, AFailedFlushOrRenameKeepsTheOldFile) {
  test::FileFaults::fail("fsync", EIO);
  std::string why;
  EXPECT_FALSE(save(path_, "the new map", true, &why));
  EXPECT_NE(why.find(std::strerror(EIO)), std::string::npos) << why;
  expectOldFileAlone(false);
  test::FileFaults::clear();
  test::FileFaults::fail("rename", EIO);
  EXPECT_FALSE(save(path_, "the new map", true, &why));
  EXPECT_NE(why.find(path_), std::string::npos) << why;
  EXPECT_GE(test::FileFaults::failures("rename"), 1);
  expectOldFileAlone(false);
}

// A save whose process died leaves its temporary file (up to a gigabyte) beside the map for good:
// removeAbandonedTemporaries() removes those of the map and of its backup's link, and nothing else: not
// a writer's that is still writing, another file's, a name mkstemp would not make, or a symlink.
TEST(AtomicFileWriter, WhatADeadWriterLeftIsRemovedAndNothingElse) {
  test::TempDir dir("scl_abandoned");
  const std::string map = dir.file("map.scdb");
  std::ofstream(map) << "the map";
  std::ofstream(dir.file("map.scdb.tmp.Ab12Cd")) << std::string(1000, 'x');  // its writer died
  std::ofstream(dir.file("map.scdb.bak.tmp.Zz9900")) << "a backup's link";
  std::ofstream(dir.file("map.scdb.tmp.Ab12")) << "not a name mkstemp makes";
  std::ofstream(dir.file("other.scdb.tmp.Ab12Cd")) << "another file's";
  std::ofstream(dir.file("elsewhere")) << "a symlink's target";
  ASSERT_EQ(::symlink(dir.file("elsewhere").c_str(), dir.file("map.scdb.tmp.Link00").c_str()), 0);

  AtomicFileWriter alive;  // writing while the removal runs
  std::string error;
  ASSERT_TRUE(alive.open(map, &error)) << error;
  ASSERT_TRUE(alive.write("the new map", 11, &error)) << error;

  const std::vector<AbandonedFile> removed = removeAbandonedTemporaries(map);
  std::vector<std::string> paths;
  for (const AbandonedFile& file : removed) paths.push_back(file.path);
  std::sort(paths.begin(), paths.end());
  EXPECT_EQ(paths, (std::vector<std::string>{dir.file("map.scdb.bak.tmp.Zz9900"), dir.file("map.scdb.tmp.Ab12Cd")}));
  for (const AbandonedFile& file : removed) {
    if (file.path == dir.file("map.scdb.tmp.Ab12Cd")) EXPECT_EQ(file.bytes, 1000u);
  }
  EXPECT_EQ(dir.entries().size(), 6u) << "the map, the live writer's file, the three others and the symlink";

  ASSERT_TRUE(alive.commit(&error)) << "the live writer's file was left to it: " << error;
  std::string text;
  std::getline(std::ifstream(map), text);
  EXPECT_EQ(text, "the new map");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"elsewhere", "map.scdb", "map.scdb.tmp.Ab12",
                                                     "map.scdb.tmp.Link00", "other.scdb.tmp.Ab12Cd"}));
  EXPECT_TRUE(removeAbandonedTemporaries(dir.file("missing/map.scdb")).empty());
}

}  // namespace
}  // namespace scan_context_loop
