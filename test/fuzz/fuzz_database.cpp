// Fuzz target: the database file parser (readDatabase over the bytes in memory, as readDatabaseFile
// reads a file), then LoopDetector::appendSessions and a query against what was loaded.
//
// Input bytes: u8 mode (1: the header's payload size and both checksums are set to agree with the
// bytes, so that mutated records get past the checksums to the record checks; 2: after loading, the
// fixed cloud is located among the loaded keyframes), then the file. Files must match
// smallConfig(kDatabaseChoice) (fuzz_seeds writes such files).
#include "fuzz_input.h"
#include "scan_context_loop/core/crc32.h"
#include "scan_context_loop/core/database_file.h"
#include "scan_context_loop/core/detector.h"

namespace scan_context_loop::fuzz {

namespace {

// The header's layout (doc/database_file.md): the payload size, its CRC and the header's CRC end it.
constexpr std::size_t kHeaderBytes = 91, kPayloadSizeAt = 75, kPayloadCrcAt = 83, kHeaderCrcAt = 87;

void putU32(std::vector<std::uint8_t>* file, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) (*file)[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
}

void fixChecksums(std::vector<std::uint8_t>* file) {
  if (file->size() < kHeaderBytes) return;
  const std::uint64_t payload = file->size() - kHeaderBytes;
  for (int i = 0; i < 8; ++i) (*file)[kPayloadSizeAt + i] = static_cast<std::uint8_t>(payload >> (8 * i));
  putU32(file, kPayloadCrcAt, crc32(file->data() + kHeaderBytes, payload));
  putU32(file, kHeaderCrcAt, crc32(file->data(), kHeaderCrcAt));
}

}  // namespace

int databaseFile(const std::uint8_t* data, std::size_t size) {
  FuzzBytes in(data, size);
  const std::uint8_t mode = in.take<std::uint8_t>();
  std::vector<std::uint8_t> file = in.rest();
  if (mode & 1) fixChecksums(&file);
  LoopDetector detector(smallConfig(kDatabaseChoice));
  MemoryReader reader(file.data(), file.size());
  PriorSessions sessions;
  std::string error;
  if (!readDatabase(&reader, "fuzz input", detector.config(), &sessions, &error)) return 0;
  if (!detector.appendSessions(std::move(sessions), &error)) return 0;
  if (mode & 2) detector.locate(fixedCloud());
  return 0;
}

}  // namespace scan_context_loop::fuzz
