// SHA-256, streaming, with its running state exposed so a checkpoint can carry a digest that is still
// being computed and a resumed run finishes it with the same bits. OpenSSL computes it.
#pragma once

#include <openssl/sha.h>

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

  // The running state as 144 bytes, and back (false when the bytes are not such a state). Layout, all
  // u64 little-endian: the 8 chaining words, the bytes buffered, the 64-byte block buffer, bytes hashed.
  std::string save_state() const;
  bool restore_state(std::string_view bytes);
  static constexpr std::size_t kStateBytes = 8 * 8 + 8 + 64 + 8;

 private:
  // OpenSSL's plain SHA-256 context rather than an EVP_MD_CTX: EVP keeps the running state out of
  // reach, and a checkpoint must save it and a resumed run set it back. A plain struct, so copies are
  // cheap and nothing is to be freed.
  SHA256_CTX ctx_;
  // The saved state's block buffer: every byte hashed at its offset in its block, so past the buffered
  // bytes it holds the previous block's (the checkpoint format's bytes). OpenSSL clears its own buffer
  // once a block is hashed.
  std::array<std::uint8_t, 64> block_{};
};

std::string to_hex(const std::uint8_t* bytes, std::size_t size);

}  // namespace kessler
