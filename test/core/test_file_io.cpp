// FileReader hands out contiguous pieces of any size across its buffer's refills; AtomicFileWriter
// leaves nothing behind unless committed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "scan_context_loop/core/file_io.h"

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

}  // namespace
}  // namespace scan_context_loop
