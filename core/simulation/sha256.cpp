// The SHA256_* functions are deprecated in OpenSSL 3 in favour of EVP, which has no way to save and
// restore a running digest (sha256.hpp); they remain in every OpenSSL 3 release.
#define OPENSSL_SUPPRESS_DEPRECATED

#include "core/simulation/sha256.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace kessler {
namespace {

void put_le(std::string& out, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
std::uint64_t get_le(const char* p) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(static_cast<std::uint8_t>(p[i])) << (8 * i);
  return v;
}

void check(int ok, const char* what) {
  if (ok != 1) throw std::runtime_error(std::string("sha256: OpenSSL's ") + what + " failed");
}

}  // namespace

void Sha256::reset() {
  check(SHA256_Init(&ctx_), "SHA256_Init");
  block_.fill(0);
}

void Sha256::update(const void* data, std::size_t size) {
  if (size == 0) return;
  // Only the last 64 bytes can stay in block_; ctx_.num is where the first byte of `data` falls.
  const std::size_t keep = std::min<std::size_t>(size, 64);
  const auto* tail = static_cast<const std::uint8_t*>(data) + (size - keep);
  const std::size_t at = (ctx_.num + (size - keep)) % 64;
  const std::size_t first = std::min(keep, 64 - at);
  std::memcpy(block_.data() + at, tail, first);
  std::memcpy(block_.data(), tail + first, keep - first);
  check(SHA256_Update(&ctx_, data, size), "SHA256_Update");
}

void Sha256::update_u64(std::uint64_t value) {
  std::uint8_t bytes[8];
  for (int i = 0; i < 8; ++i) bytes[i] = static_cast<std::uint8_t>(value >> (8 * i));
  update(bytes, 8);
}

void Sha256::update_f64(double value) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, 8);
  update_u64(bits);
}

std::array<std::uint8_t, 32> Sha256::digest() const {
  SHA256_CTX copy = ctx_;
  std::array<std::uint8_t, 32> out{};
  check(SHA256_Final(out.data(), &copy), "SHA256_Final");
  return out;
}

std::string Sha256::hex_digest() const {
  auto d = digest();
  return to_hex(d.data(), d.size());
}

// OpenSSL keeps the length in bits (Nh:Nl) and the buffered bytes count in `num`.
std::string Sha256::save_state() const {
  std::string out;
  for (auto word : ctx_.h) put_le(out, word);
  put_le(out, ctx_.num);
  out.append(reinterpret_cast<const char*>(block_.data()), block_.size());
  const std::uint64_t bits = (static_cast<std::uint64_t>(ctx_.Nh) << 32) | ctx_.Nl;
  put_le(out, bits / 8);
  return out;
}

bool Sha256::restore_state(std::string_view bytes) {
  static_assert(sizeof(SHA256_CTX::data) == 64);
  if (bytes.size() != kStateBytes) return false;
  const char* p = bytes.data();
  std::array<std::uint32_t, 8> h{};
  for (auto& word : h) {
    std::uint64_t v = get_le(p);
    if (v > 0xffffffffULL) return false;
    word = static_cast<std::uint32_t>(v);
    p += 8;
  }
  std::uint64_t buffered = get_le(p);
  p += 8;
  if (buffered >= 64) return false;
  const char* block = p;
  p += 64;
  std::uint64_t total = get_le(p);
  if (total % 64 != buffered) return false;
  reset();
  for (int i = 0; i < 8; ++i) ctx_.h[i] = h[i];
  std::memcpy(block_.data(), block, 64);
  std::memcpy(ctx_.data, block, buffered);
  ctx_.num = static_cast<unsigned int>(buffered);
  ctx_.Nl = static_cast<SHA_LONG>(total * 8);
  ctx_.Nh = static_cast<SHA_LONG>((total * 8) >> 32);
  return true;
}

std::string to_hex(const std::uint8_t* bytes, std::size_t size) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  out.reserve(2 * size);
  for (std::size_t i = 0; i < size; ++i) {
    out.push_back(digits[bytes[i] >> 4]);
    out.push_back(digits[bytes[i] & 15]);
  }
  return out;
}

}  // namespace kessler
