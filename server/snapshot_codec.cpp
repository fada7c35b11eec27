#include "server/snapshot_codec.hpp"

#include <zlib.h>

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace kessler::server {

namespace {

static_assert(std::endian::native == std::endian::little, "the snapshot format is little-endian");

constexpr char kMagic[4] = {'K', 'S', 'N', 'P'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderSize = 4 + 4 + 8 + 8 + 8 + 8;
// Level 1: the shuffled columns compress almost as well as at level 6, several times faster.
constexpr int kDeflateLevel = 1;

template <class T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

template <class T>
T get(const std::string& in, std::size_t& at) {
  if (at + sizeof(T) > in.size()) throw std::runtime_error("snapshot: truncated");
  T value;
  std::memcpy(&value, in.data() + at, sizeof(T));
  at += sizeof(T);
  return value;
}

// The float columns in the format's order (S: PopulationSnapshot, const or not).
template <class S>
auto float_columns(S& s) {
  return std::array{&s.radius_m,        &s.mass_kg,  &s.semi_major_axis_m,       &s.eccentricity,
                    &s.inclination_rad, &s.raan_rad, &s.argument_of_perigee_rad, &s.mean_anomaly_rad};
}

void put_shuffled(std::string& out, const std::vector<float>& column) {
  const std::size_t n = column.size();
  const std::size_t at = out.size();
  out.resize(at + 4 * n);
  const auto* bytes = reinterpret_cast<const unsigned char*>(column.data());
  for (std::size_t b = 0; b < 4; ++b)
    for (std::size_t i = 0; i < n; ++i) out[at + b * n + i] = static_cast<char>(bytes[4 * i + b]);
}

void get_shuffled(const std::string& in, std::size_t& at, std::vector<float>& column) {
  const std::size_t n = column.size();
  if (at + 4 * n > in.size()) throw std::runtime_error("snapshot: truncated payload");
  auto* bytes = reinterpret_cast<unsigned char*>(column.data());
  for (std::size_t b = 0; b < 4; ++b)
    for (std::size_t i = 0; i < n; ++i) bytes[4 * i + b] = static_cast<unsigned char>(in[at + b * n + i]);
  at += 4 * n;
}

std::string payload_of(const PopulationSnapshot& s) {
  const std::size_t n = s.size();
  std::string out;
  out.reserve(n * (8 + 2 + 32));
  ObjectId previous = 0;
  for (ObjectId id : s.id) {
    put<std::uint64_t>(out, id - previous);
    previous = id;
  }
  for (ObjectType t : s.type) out.push_back(static_cast<char>(t));
  for (ObjectStatus st : s.status) out.push_back(static_cast<char>(st));
  for (const std::vector<float>* column : float_columns(s)) put_shuffled(out, *column);
  return out;
}

}  // namespace

std::string encode_snapshot(const PopulationSnapshot& s) {
  const std::string payload = payload_of(s);
  uLongf packed_size = compressBound(static_cast<uLong>(payload.size()));
  std::string out;
  out.append(kMagic, 4);
  put<std::uint32_t>(out, kVersion);
  put<std::uint64_t>(out, s.size());
  put<std::int64_t>(out, s.step);
  put<std::uint64_t>(out, std::bit_cast<std::uint64_t>(s.sim_time_s));
  put<std::uint64_t>(out, payload.size());
  out.resize(kHeaderSize + packed_size);
  const int rc = compress2(reinterpret_cast<Bytef*>(out.data() + kHeaderSize), &packed_size,
                           reinterpret_cast<const Bytef*>(payload.data()), static_cast<uLong>(payload.size()),
                           kDeflateLevel);
  if (rc != Z_OK) throw std::runtime_error("snapshot: deflate failed (" + std::to_string(rc) + ")");
  out.resize(kHeaderSize + packed_size);
  return out;
}

PopulationSnapshot decode_snapshot(const std::string& bytes) {
  if (bytes.size() < kHeaderSize || std::memcmp(bytes.data(), kMagic, 4) != 0)
    throw std::runtime_error("snapshot: not a snapshot");
  std::size_t at = 4;
  if (get<std::uint32_t>(bytes, at) != kVersion) throw std::runtime_error("snapshot: unknown format version");
  const auto n = get<std::uint64_t>(bytes, at);
  PopulationSnapshot s;
  s.step = get<std::int64_t>(bytes, at);
  s.sim_time_s = std::bit_cast<double>(get<std::uint64_t>(bytes, at));
  const auto payload_size = get<std::uint64_t>(bytes, at);
  if (payload_size != n * (8 + 2 + 32)) throw std::runtime_error("snapshot: payload size does not match");
  std::string payload(payload_size, '\0');
  uLongf unpacked = static_cast<uLongf>(payload_size);
  const int rc = uncompress(reinterpret_cast<Bytef*>(payload.data()), &unpacked,
                            reinterpret_cast<const Bytef*>(bytes.data() + kHeaderSize),
                            static_cast<uLong>(bytes.size() - kHeaderSize));
  if (rc != Z_OK || unpacked != payload_size) throw std::runtime_error("snapshot: corrupt payload");
  s.resize(n);
  at = 0;
  ObjectId id = 0;
  for (std::size_t i = 0; i < n; ++i) {
    id += get<std::uint64_t>(payload, at);
    s.id[i] = id;
  }
  for (std::size_t i = 0; i < n; ++i) s.type[i] = static_cast<ObjectType>(payload[at++]);
  for (std::size_t i = 0; i < n; ++i) s.status[i] = static_cast<ObjectStatus>(payload[at++]);
  for (std::vector<float>* column : float_columns(s)) get_shuffled(payload, at, *column);
  return s;
}

}  // namespace kessler::server
