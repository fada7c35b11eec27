#include "core/simulation/checkpoint.hpp"

#include <bit>
#include <cstring>
#include <stdexcept>

#include "core/simulation/sha256.hpp"

namespace kessler {
namespace {

constexpr char kMagic[8] = {'K', 'E', 'S', 'S', 'L', 'C', 'K', 'P'};
// Bounds that keep a corrupt size field from allocating the machine away.
constexpr std::uint64_t kMaxObjects = 100'000'000;
constexpr std::uint64_t kMaxString = 1u << 20;

class Writer {
 public:
  void u8(std::uint8_t v) { out_.push_back(static_cast<char>(v)); }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void u64(std::uint64_t v) {
    if constexpr (std::endian::native == std::endian::little) {
      out_.append(reinterpret_cast<const char*>(&v), 8);
    } else {
      for (int i = 0; i < 8; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i)));
    }
  }
  void i64(std::int64_t v) { u64(static_cast<std::uint64_t>(v)); }
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    u64(bits);
  }
  void str(const std::string& s) {
    u64(s.size());
    out_.append(s);
  }
  void doubles(const std::vector<double>& v) {
    if constexpr (std::endian::native == std::endian::little) {
      out_.append(reinterpret_cast<const char*>(v.data()), 8 * v.size());
    } else {
      for (double d : v) f64(d);
    }
  }
  std::string& bytes() { return out_; }

 private:
  std::string out_;
};

class Reader {
 public:
  Reader(const char* data, std::size_t size) : p_(data), end_(data + size) {}
  void need(std::size_t n, const char* what) {
    if (static_cast<std::size_t>(end_ - p_) < n)
      throw std::runtime_error(std::string("checkpoint: truncated in ") + what);
  }
  // `n` items of at least `bytes_each` bytes must still be there: a count read from the bytes is
  // checked against them before anything is allocated for it (n is at most kMaxObjects).
  void need_items(std::uint64_t n, std::size_t bytes_each, const char* what) { need(n * bytes_each, what); }
  std::uint8_t u8(const char* what) {
    need(1, what);
    return static_cast<std::uint8_t>(*p_++);
  }
  std::uint32_t u32(const char* what) {
    need(4, what);
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= std::uint32_t(static_cast<std::uint8_t>(p_[i])) << (8 * i);
    p_ += 4;
    return v;
  }
  std::uint64_t u64(const char* what) {
    need(8, what);
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= std::uint64_t(static_cast<std::uint8_t>(p_[i])) << (8 * i);
    p_ += 8;
    return v;
  }
  std::int64_t i64(const char* what) { return static_cast<std::int64_t>(u64(what)); }
  double f64(const char* what) {
    std::uint64_t bits = u64(what);
    double v;
    std::memcpy(&v, &bits, 8);
    return v;
  }
  std::string str(const char* what) {
    std::uint64_t n = u64(what);
    if (n > kMaxString) throw std::runtime_error(std::string("checkpoint: implausible length in ") + what);
    need(n, what);
    std::string s(p_, n);
    p_ += n;
    return s;
  }
  void doubles(std::vector<double>& v, std::size_t n, const char* what) {
    need(8 * n, what);
    v.resize(n);
    if (n == 0) return;  // an empty vector's data() may be null, which memcpy must not get
    if constexpr (std::endian::native == std::endian::little) {
      std::memcpy(v.data(), p_, 8 * n);
      p_ += 8 * n;
    } else {
      for (auto& d : v) d = f64(what);
    }
  }
  bool at_end() const { return p_ == end_; }

 private:
  const char* p_;
  const char* end_;
};

// An encounter's fields in for_each_field's order: the kind as one byte, everything else as in Writer.
struct WriteField {
  Writer& w;
  void operator()(const char*, std::uint64_t v) const { w.u64(v); }
  void operator()(const char*, double v) const { w.f64(v); }
  void operator()(const char*, EncounterKind kind) const { w.u8(static_cast<std::uint8_t>(kind)); }
  void operator()(const char*, const Eigen::Vector3d& v) const {
    for (int k = 0; k < 3; ++k) w.f64(v[k]);
  }
};

struct ReadField {
  Reader& r;
  static constexpr const char* kWhat = "closest-encounter table";
  void operator()(const char*, std::uint64_t& v) const { v = r.u64(kWhat); }
  void operator()(const char*, double& v) const { v = r.f64(kWhat); }
  void operator()(const char*, EncounterKind& kind) const {
    const std::uint8_t v = r.u8(kWhat);
    if (v > 2) throw std::runtime_error("checkpoint: unknown encounter kind in closest-encounter table");
    kind = static_cast<EncounterKind>(v);
  }
  void operator()(const char*, Eigen::Vector3d& v) const {
    for (int k = 0; k < 3; ++k) v[k] = r.f64(kWhat);
  }
};

}  // namespace

std::string encode_checkpoint(const CheckpointState& s) {
  Writer w;
  w.str(s.config_key);
  w.i64(s.step);
  w.i64(s.total_steps);
  w.u64(s.next_seq);
  w.u64(s.seed);
  for_each_counter(static_cast<const RunCounters&>(s), [&](const char*, std::uint64_t v) { w.u64(v); });
  w.f64(s.wall_s);
  w.str(s.events_digest_state);
  w.u64(s.closest_per_pair.size());
  for (const auto& e : s.closest_per_pair) for_each_field(e, WriteField{w});
  const Population& p = s.population;
  w.u64(p.size());
  for (auto id : p.id) w.u64(id);
  for (const auto& name : p.name) w.str(name);
  for (const auto* v : {&p.state.x, &p.state.y, &p.state.z, &p.state.vx, &p.state.vy, &p.state.vz,
                        &p.radius_m, &p.mass_kg, &p.drag_area_to_mass_m2_kg, &p.srp_area_to_mass_m2_kg})
    w.doubles(*v);
  for (auto status : p.status) w.u8(static_cast<std::uint8_t>(status));
  w.u64(s.breakups.next_fragment_id);
  for (auto type : p.type) w.u8(static_cast<std::uint8_t>(type));
  for (auto group : p.separation_group) w.u64(group);
  w.u64(s.breakups.next_breakup_id);
  w.u64(s.breakups.separating.size());
  for (const SeparatingBreakup& b : s.breakups.separating) {
    w.u64(b.group);
    w.f64(b.until_s);
  }
  w.u64(s.traffic.next_launch);
  w.u64(s.traffic.active.size());
  for (const ActiveLife& a : s.traffic.active) {
    w.u64(a.id);
    w.f64(a.end_of_life_s);
    w.f64(a.drag_area_to_mass_m2_kg);
    w.u8(a.keeps_station ? 1 : 0);
  }

  const std::string& payload = w.bytes();
  Sha256 sum;
  sum.update(payload);
  auto digest = sum.digest();
  Writer out;
  out.bytes().append(kMagic, sizeof kMagic);
  out.u32(kCheckpointVersion);
  out.u64(payload.size());
  out.bytes().append(payload);
  out.bytes().append(reinterpret_cast<const char*>(digest.data()), digest.size());
  return std::move(out.bytes());
}

namespace {
// Version 3's population types, separation groups and breakup bookkeeping.
void read_breakups(Reader& r, CheckpointState& s) {
  Population& p = s.population;
  for (auto& type : p.type) {
    const std::uint8_t v = r.u8("object types");
    if (v > static_cast<std::uint8_t>(ObjectType::kDebris))
      throw std::runtime_error("checkpoint: unknown object type");
    type = static_cast<ObjectType>(v);
  }
  for (auto& group : p.separation_group) {
    const std::uint64_t v = r.u64("separation groups");
    if (v > 0xFFFFFFFFu) throw std::runtime_error("checkpoint: implausible separation group");
    group = static_cast<BreakupId>(v);
  }
  const std::uint64_t next = r.u64("breakup counter");
  if (next == 0 || next > 0xFFFFFFFFu) throw std::runtime_error("checkpoint: implausible breakup counter");
  s.breakups.next_breakup_id = static_cast<BreakupId>(next);
  const std::uint64_t separating = r.u64("separating breakups");
  if (separating > next) throw std::runtime_error("checkpoint: implausible separating breakups");
  for (std::uint64_t k = 0; k < separating; ++k) {
    SeparatingBreakup b;
    b.group = static_cast<BreakupId>(r.u64("separating breakups"));
    b.until_s = r.f64("separating breakups");
    s.breakups.separating.push_back(b);
  }
}
// Version 4's traffic state.
void read_traffic(Reader& r, CheckpointState& s) {
  s.traffic.next_launch = r.u64("launch counter");
  const std::uint64_t active = r.u64("active lifecycles");
  if (active > kMaxObjects) throw std::runtime_error("checkpoint: implausible active lifecycles");
  r.need_items(active, 25, "active lifecycles");
  s.traffic.active.resize(active);
  for (ActiveLife& a : s.traffic.active) {
    a.id = r.u64("active lifecycles");
    a.end_of_life_s = r.f64("active lifecycles");
    a.drag_area_to_mass_m2_kg = r.f64("active lifecycles");
    a.keeps_station = r.u8("active lifecycles") != 0;
  }
}
}  // namespace

CheckpointState decode_checkpoint(const std::string& bytes) {
  if (bytes.size() < sizeof kMagic + 4 + 8 + 32 || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw std::runtime_error("checkpoint: not a kessler checkpoint (bad header)");
  Reader head(bytes.data() + sizeof kMagic, 12);
  std::uint32_t version = head.u32("header");
  if (version < kOldestCheckpointVersion || version > kCheckpointVersion)
    throw std::runtime_error(
        "checkpoint: format version " + std::to_string(version) + " is not supported (this build reads " +
        std::to_string(kOldestCheckpointVersion) + " to " + std::to_string(kCheckpointVersion) + ")");
  std::uint64_t size = head.u64("header");
  const std::size_t offset = sizeof kMagic + 12;
  if (size != bytes.size() - offset - 32)
    throw std::runtime_error("checkpoint: truncated or padded (payload size does not match)");
  Sha256 sum;
  sum.update(bytes.data() + offset, size);
  auto digest = sum.digest();
  if (std::memcmp(digest.data(), bytes.data() + offset + size, 32) != 0)
    throw std::runtime_error("checkpoint: checksum mismatch (corrupt bytes)");

  Reader r(bytes.data() + offset, size);
  CheckpointState s;
  s.config_key = r.str("config key");
  s.step = r.i64("step");
  s.total_steps = r.i64("total steps");
  s.next_seq = r.u64("sequence");
  s.seed = r.u64("seed");
  for_each_counter(static_cast<RunCounters&>(s),
                   [&](const char*, std::uint64_t& v) { v = r.u64("counters"); });
  s.wall_s = r.f64("wall time");
  s.events_digest_state = r.str("events digest");
  std::uint64_t pairs = r.u64("closest-encounter table");
  if (pairs > kMaxObjects) throw std::runtime_error("checkpoint: implausible closest-encounter table size");
  r.need_items(pairs, 8, "closest-encounter table");
  s.closest_per_pair.reserve(pairs);
  for (std::uint64_t i = 0; i < pairs; ++i) for_each_field(s.closest_per_pair.emplace_back(), ReadField{r});
  std::uint64_t n = r.u64("population size");
  if (n > kMaxObjects) throw std::runtime_error("checkpoint: implausible population size");
  r.need_items(n, 88, "population");  // an id and ten doubles (8 bytes each), at least
  Population& p = s.population;
  p.id.resize(n);
  for (auto& id : p.id) id = r.u64("ids");
  p.name.resize(n);
  for (auto& name : p.name) name = r.str("names");
  for (auto* v : {&p.state.x, &p.state.y, &p.state.z, &p.state.vx, &p.state.vy, &p.state.vz, &p.radius_m,
                  &p.mass_kg, &p.drag_area_to_mass_m2_kg, &p.srp_area_to_mass_m2_kg})
    r.doubles(*v, n, "population arrays");
  p.status.resize(n);
  for (auto& status : p.status) {
    std::uint8_t v = r.u8("statuses");
    if (v > 1) throw std::runtime_error("checkpoint: unknown object status");
    status = static_cast<ObjectStatus>(v);
  }
  p.type.assign(n, ObjectType::kUnknown);
  p.separation_group.assign(n, 0);
  if (version >= 2) s.breakups.next_fragment_id = r.u64("fragment id counter");
  if (version >= 3) read_breakups(r, s);
  if (version >= 4) read_traffic(r, s);
  if (!r.at_end()) throw std::runtime_error("checkpoint: trailing bytes at the end");
  if (s.step < 0 || s.step > s.total_steps || s.next_seq == 0)
    throw std::runtime_error("checkpoint: inconsistent step counter or sequence number");
  return s;
}

}  // namespace kessler
