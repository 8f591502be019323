// FileReader hands out contiguous pieces of any size across its buffer's refills; AtomicFileWriter
// leaves nothing behind unless committed.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <future>
#include <filesystem>
#include <fstream>
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
  for (std::size_t piece : {std::size_t(7), std::size_t(1048570), std::size_t(1), std::size_t(2100000),
                            std::size_t(3), size - 7 - 1048570 - 1 - 2100000 - 3}) {
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

TEST(FileReader, RefusesFifosSocketsDevicesAndDirectoriesWithoutBlocking) {
  const fs::path dir = fs::temp_directory_path() / ("scl_file_types_" + std::to_string(::getpid()));
  fs::create_directory(dir);
  const std::string fifo = (dir / "fifo").string(), socket_path = (dir / "socket").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const int sock = ::socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::snprintf(address.sun_path, sizeof(address.sun_path), "%s", socket_path.c_str());
  ASSERT_EQ(::bind(sock, reinterpret_cast<const sockaddr*>(&address), sizeof(address)), 0);
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

// A large save goes to disk while it is written: every piece but the last two is on disk and out of the
// page cache before commit(), so its fsync (and the journal commit other processes' writes wait for)
// has little left to flush, and the file is whole.
TEST(AtomicFileWriter, WritesBehindSoThatCommitHasLittleLeftToFlush) {
  test::TempDir dir("scl_write_behind");
  struct statfs fs_info;
  ASSERT_EQ(::statfs(dir.file("").c_str(), &fs_info), 0);
  if (fs_info.f_type == TMPFS_MAGIC) GTEST_SKIP() << "the temporary directory is in memory (tmpfs): no disk to write to";
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
  const std::size_t page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE)), settled = 2 * AtomicFileWriter::kWriteBehindBytes;
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

}  // namespace
}  // namespace scan_context_loop
