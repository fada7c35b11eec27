// A population snapshot (core/simulation/snapshots.hpp) as the store keeps it: one compressed blob.
//
// Layout: "KSNP", format version (u32), object count (u64), step (i64), sim time (f64 bits), size of the
// uncompressed payload (u64), then the payload deflated by zlib. The payload holds the columns one after
// the other: ids as differences from the previous id (u64, two's complement), types, statuses (a byte
// each), then the eight 32-bit float columns (radius, mass, a, e, i, RAAN, argument of perigee, mean
// anomaly), each byte-shuffled (every value's first byte, then every second byte...) so that deflate
// finds the runs the shared exponents make. All integers little-endian.
#pragma once

#include <string>

#include "core/simulation/snapshots.hpp"

namespace kessler::server {

std::string encode_snapshot(const PopulationSnapshot& snapshot);
// Throws std::runtime_error("snapshot: ...") for bytes that are not an encoded snapshot.
PopulationSnapshot decode_snapshot(const std::string& bytes);

}  // namespace kessler::server
