#include "scan_context_loop/core/crc32.h"

#include <array>

namespace scan_context_loop {

namespace {

/// Sixteen bytes a step ("slicing"): table[0] is the byte-wise table of the reflected polynomial
/// 0xEDB88320, table[k][b] the CRC of byte b followed by k zero bytes. Sixteen independent lookups a step
/// run about twice as fast as eight.
constexpr int kSlices = 16;
using Tables = std::array<std::array<std::uint32_t, 256>, kSlices>;

Tables makeTables() {
  Tables t{};
  for (std::uint32_t b = 0; b < 256; ++b) {
    std::uint32_t c = b;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? (c >> 1) ^ 0xEDB88320u : c >> 1;
    t[0][b] = c;
  }
  for (std::uint32_t b = 0; b < 256; ++b) {
    for (int k = 1; k < kSlices; ++k) t[k][b] = (t[k - 1][b] >> 8) ^ t[0][t[k - 1][b] & 0xFFu];
  }
  return t;
}

}  // namespace

std::uint32_t crc32(const void* data, std::size_t size, std::uint32_t crc) {
  static const Tables t = makeTables();
  const auto* p = static_cast<const std::uint8_t*>(data);
  std::uint32_t c = ~crc;
  // Byte by byte within a step, so the result does not depend on the host's byte order; the running
  // CRC enters through the step's first four bytes.
  for (; size >= kSlices; size -= kSlices, p += kSlices) {
    std::uint32_t next = 0;
    for (int k = 0; k < 4; ++k) next ^= t[kSlices - 1 - k][((c >> (8 * k)) ^ p[k]) & 0xFFu];
    for (int k = 4; k < kSlices; ++k) next ^= t[kSlices - 1 - k][p[k]];
    c = next;
  }
  for (; size > 0; --size, ++p) c = (c >> 8) ^ t[0][(c ^ *p) & 0xFFu];
  return ~c;
}

}  // namespace scan_context_loop
