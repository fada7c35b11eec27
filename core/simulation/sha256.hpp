// SHA-256 (FIPS 180-4), streaming, with its running state exposed so a checkpoint can carry a digest
// that is still being computed and a resumed run finishes it with the same bits.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace kessler {

class Sha256 {
 public:
  Sha256() { reset(); }
  void reset();
  void update(const void* data, std::size_t size);
  void update(std::string_view text) { update(text.data(), text.size()); }
  // Fixed-width values in little-endian byte order (the core's checkpoint and digest byte order).
  void update_u64(std::uint64_t value);
  void update_f64(double value);  // the bit pattern, so -0.0 and 0.0 differ and every bit counts
  // The digest of everything so far; the running state is left untouched (more can follow).
  std::array<std::uint8_t, 32> digest() const;
  std::string hex_digest() const;

  // The running state as 144 bytes, and back (false when the bytes are not such a state).
  std::string save_state() const;
  bool restore_state(std::string_view bytes);
  static constexpr std::size_t kStateBytes = 8 * 8 + 8 + 64 + 8;

 private:
  void compress(const std::uint8_t* block);
  std::array<std::uint32_t, 8> h_{};
  std::array<std::uint8_t, 64> buffer_{};
  std::uint64_t buffered_ = 0;     // bytes in buffer_
  std::uint64_t total_bytes_ = 0;  // bytes hashed so far
};

std::string to_hex(const std::uint8_t* bytes, std::size_t size);

}  // namespace kessler
