// CRC-32 (IEEE 802.3, the polynomial of zlib, PNG and gzip), for checking files the core writes.
#pragma once

#include <cstddef>
#include <cstdint>

namespace scan_context_loop {

/// The CRC-32 of `size` bytes, continuing from `crc` (0 to start; pass the previous result to checksum
/// data that arrives in pieces). crc32("123456789") is 0xCBF43926.
std::uint32_t crc32(const void* data, std::size_t size, std::uint32_t crc = 0);

}  // namespace scan_context_loop
