// Little-endian fixed-width encoding and bounds-checked decoding, for the files the core writes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace scan_context_loop {

namespace byte_order {
constexpr bool kLittleEndianHost = __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__;
}  // namespace byte_order

/// Appends values to a byte buffer, least significant byte first; floats as their IEEE 754 bits.
class ByteWriter {
 public:
  void u8(std::uint8_t v) { buffer_.push_back(v); }
  void u32(std::uint32_t v) { unsignedBytes(v, 4); }
  void u64(std::uint64_t v) { unsignedBytes(v, 8); }
  void i64(std::int64_t v) { u64(static_cast<std::uint64_t>(v)); }
  void f32(float v) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, 4);
    u32(bits);
  }
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    u64(bits);
  }
  void bytes(const void* data, std::size_t size) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    buffer_.insert(buffer_.end(), p, p + size);
  }
  void f32s(const float* v, std::size_t n) {
    if (byte_order::kLittleEndianHost) {
      bytes(v, n * sizeof(float));
    } else {
      for (std::size_t i = 0; i < n; ++i) f32(v[i]);
    }
  }

  const std::vector<std::uint8_t>& buffer() const { return buffer_; }
  std::size_t size() const { return buffer_.size(); }
  void clear() { buffer_.clear(); }

 private:
  void unsignedBytes(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) buffer_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  std::vector<std::uint8_t> buffer_;
};

/// Reads what ByteWriter wrote from a byte range. Every read returns false, reading nothing, when fewer
/// bytes are left than it needs.
class ByteReader {
 public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  bool u8(std::uint8_t* v) {
    const std::uint8_t* p = take(1);
    if (p) *v = *p;
    return p != nullptr;
  }
  bool u32(std::uint32_t* v) { return unsignedBytes(v, 4); }
  bool u64(std::uint64_t* v) { return unsignedBytes(v, 8); }
  bool i64(std::int64_t* v) {
    std::uint64_t u;
    if (!u64(&u)) return false;
    *v = static_cast<std::int64_t>(u);
    return true;
  }
  bool f32(float* v) {
    std::uint32_t bits;
    if (!u32(&bits)) return false;
    std::memcpy(v, &bits, 4);
    return true;
  }
  bool f64(double* v) {
    std::uint64_t bits;
    if (!u64(&bits)) return false;
    std::memcpy(v, &bits, 8);
    return true;
  }
  bool f32s(float* v, std::size_t n) {
    if (n > remaining() / sizeof(float)) return false;
    if (byte_order::kLittleEndianHost) {
      std::memcpy(v, take(n * sizeof(float)), n * sizeof(float));
      return true;
    }
    for (std::size_t i = 0; i < n; ++i) f32(&v[i]);
    return true;
  }
  /// The next `n` bytes in place, or nullptr.
  const std::uint8_t* take(std::size_t n) {
    if (n > remaining()) return nullptr;
    const std::uint8_t* p = data_ + offset_;
    offset_ += n;
    return p;
  }

  std::size_t offset() const { return offset_; }
  std::size_t remaining() const { return size_ - offset_; }

 private:
  template <typename T>
  bool unsignedBytes(T* v, int n) {
    const std::uint8_t* p = take(static_cast<std::size_t>(n));
    if (!p) return false;
    T out = 0;
    for (int i = 0; i < n; ++i) out |= static_cast<T>(p[i]) << (8 * i);
    *v = out;
    return true;
  }
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
};

}  // namespace scan_context_loop
