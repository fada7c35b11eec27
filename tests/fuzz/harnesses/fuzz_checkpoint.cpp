// Checkpoint bytes (core/simulation/checkpoint.hpp). The input is a format version (one byte) and a
// payload, which the harness frames with the header and the SHA-256 a checkpoint carries, so the
// payload decoder itself is explored (random bytes would all stop at the checksum); an input whose
// first byte is 0xFF goes in unframed, for the header checks. Refused with std::runtime_error, or
// decoded, and then encoded again.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

#include "core/simulation/checkpoint.hpp"
#include "core/simulation/sha256.hpp"

namespace {

std::string framed(std::uint32_t version, const char* payload, std::size_t size) {
  std::string out = "KESSLCKP";
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((version >> (8 * i)) & 0xFF));
  for (int i = 0; i < 8; ++i)
    out.push_back(static_cast<char>((static_cast<std::uint64_t>(size) >> (8 * i)) & 0xFF));
  out.append(payload, size);
  kessler::Sha256 sum;
  sum.update(payload, size);
  const auto digest = sum.digest();
  out.append(reinterpret_cast<const char*>(digest.data()), digest.size());
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const char* rest = reinterpret_cast<const char*>(data + 1);
  const std::string bytes = data[0] == 0xFF ? std::string(rest, size - 1) : framed(data[0], rest, size - 1);
  try {
    const kessler::CheckpointState state = kessler::decode_checkpoint(bytes);
    (void)kessler::encode_checkpoint(state);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
