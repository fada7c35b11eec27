#include "core/simulation/event_stream.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <type_traits>

namespace kessler {
namespace {

enum Kind : std::uint8_t {
  kEncounter = 1,
  kBurnUp,
  kProgress,
  kBreakup,
  kLifecycle,
  kCheckpoint,
  kSummary,
  kFailed,
  kSnapshot,
};

// Plain structs go over as their bytes: the same build reads them.
static_assert(std::is_trivially_copyable_v<BurnUp>);
static_assert(std::is_trivially_copyable_v<Progress>);
static_assert(std::is_trivially_copyable_v<LifecycleReport>);
static_assert(std::is_trivially_copyable_v<FragmentReport>);
static_assert(std::is_trivially_copyable_v<RunCounters>);
static_assert(std::is_trivially_copyable_v<PhaseTimers>);

class Out {
 public:
  template <class T>
  Out& put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof(T));
    return *this;
  }
  Out& put(const Eigen::Vector3d& v) { return put(v.x()).put(v.y()).put(v.z()); }
  Out& put_string(const std::string& s) {
    put(static_cast<std::uint64_t>(s.size()));
    bytes_ += s;
    return *this;
  }
  template <class T>
  Out& put_vector(const std::vector<T>& v) {
    put(static_cast<std::uint64_t>(v.size()));
    for (const T& item : v) put(item);
    return *this;
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

class In {
 public:
  explicit In(const std::string& bytes) : bytes_(bytes) {}
  template <class T>
  In& get(T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    take(&value, sizeof(T));
    return *this;
  }
  In& get(Eigen::Vector3d& v) { return get(v.x()).get(v.y()).get(v.z()); }
  In& get_string(std::string& s) {
    std::uint64_t n = 0;
    get(n);
    if (n > bytes_.size() - at_) throw std::runtime_error("event stream: a string runs past its record");
    s.assign(bytes_, at_, n);
    at_ += n;
    return *this;
  }
  template <class T>
  In& get_vector(std::vector<T>& v) {
    std::uint64_t n = 0;
    get(n);
    if (n > (bytes_.size() - at_) / sizeof(T))
      throw std::runtime_error("event stream: a list runs past its record");
    v.resize(n);
    for (T& item : v) get(item);
    return *this;
  }

 private:
  void take(void* out, std::size_t n) {
    if (n > bytes_.size() - at_) throw std::runtime_error("event stream: a record shorter than its contents");
    std::memcpy(out, bytes_.data() + at_, n);
    at_ += n;
  }
  const std::string& bytes_;
  std::size_t at_ = 0;
};

void put_summary(Out& out, const RunSummary& s) {
  out.put(static_cast<const RunCounters&>(s)).put(s.steps).put(s.sim_time_s).put(s.objects_final);
  out.put_string(s.events_digest).put_string(s.state_digest).put(s.timers);
  out.put(static_cast<std::uint8_t>(s.cancelled)).put(static_cast<std::uint8_t>(s.stopped_at_checkpoint));
}

RunSummary get_summary(In& in) {
  RunSummary s;
  std::uint8_t cancelled = 0, stopped = 0;
  in.get(static_cast<RunCounters&>(s)).get(s.steps).get(s.sim_time_s).get(s.objects_final);
  in.get_string(s.events_digest).get_string(s.state_digest).get(s.timers).get(cancelled).get(stopped);
  s.cancelled = cancelled != 0;
  s.stopped_at_checkpoint = stopped != 0;
  return s;
}

void put_breakup(Out& out, const BreakupReport& b) {
  out.put(b.breakup_id).put(b.source).put(b.event_index).put(b.time_s).put(b.kind).put_vector(b.parents);
  out.put(static_cast<std::uint8_t>(b.catastrophic)).put(b.specific_energy_j_per_g).put(b.fragment_count);
  out.put(b.fragment_mass_kg).put(b.first_id).put(b.last_id).put(b.remnant_id).put_vector(b.fragments);
}

BreakupReport get_breakup(In& in) {
  BreakupReport b;
  std::uint8_t catastrophic = 0;
  in.get(b.breakup_id).get(b.source).get(b.event_index).get(b.time_s).get(b.kind).get_vector(b.parents);
  in.get(catastrophic).get(b.specific_energy_j_per_g).get(b.fragment_count);
  in.get(b.fragment_mass_kg).get(b.first_id).get(b.last_id).get(b.remnant_id).get_vector(b.fragments);
  b.catastrophic = catastrophic != 0;
  return b;
}

// Whole reads; false at the end of the stream before the first byte.
bool read_fully(int fd, void* out, std::size_t n) {
  auto* p = static_cast<char*>(out);
  std::size_t done = 0;
  while (done < n) {
    ssize_t got = ::read(fd, p + done, n - done);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw std::runtime_error(std::string("event stream: cannot read: ") + std::strerror(errno));
    if (got == 0) {
      if (done == 0) return false;
      throw std::runtime_error("event stream: cut off inside a record");
    }
    done += static_cast<std::size_t>(got);
  }
  return true;
}

}  // namespace

void EventStreamWriter::write_record(std::uint8_t kind, const std::string& payload) {
  std::string record(1, static_cast<char>(kind));
  const std::uint64_t size = payload.size();
  record.append(reinterpret_cast<const char*>(&size), sizeof size);
  record += payload;
  std::size_t done = 0;
  while (done < record.size()) {
    ssize_t n = ::write(fd_, record.data() + done, record.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0)
      throw std::runtime_error(std::string("cannot write the event stream: ") + std::strerror(errno));
    done += static_cast<std::size_t>(n);
  }
}

void EventStreamWriter::on_encounter(std::uint64_t seq, const Encounter& encounter) {
  Out out;
  out.put(seq);
  for_each_field(encounter, [&](const char*, const auto& value) { out.put(value); });
  write_record(kEncounter, out.bytes());
}

void EventStreamWriter::on_burn_up(std::uint64_t seq, const BurnUp& burn_up) {
  write_record(kBurnUp, Out().put(seq).put(burn_up).bytes());
}

void EventStreamWriter::on_progress(std::uint64_t seq, const Progress& progress) {
  write_record(kProgress, Out().put(seq).put(progress).bytes());
}

void EventStreamWriter::on_breakup(std::uint64_t seq, const BreakupReport& breakup) {
  Out out;
  out.put(seq);
  put_breakup(out, breakup);
  write_record(kBreakup, out.bytes());
}

void EventStreamWriter::on_lifecycle(std::uint64_t seq, const LifecycleReport& event) {
  write_record(kLifecycle, Out().put(seq).put(event).bytes());
}

void EventStreamWriter::on_checkpoint(std::uint64_t last_seq, std::int64_t step, const std::string& bytes) {
  write_record(kCheckpoint, Out().put(last_seq).put(step).put_string(bytes).bytes());
}

// Every column of a snapshot, once, in one order: f(column).
template <class S, class F>
void for_each_column(S& s, F&& f) {
  f(s.id), f(s.type), f(s.status), f(s.radius_m), f(s.mass_kg), f(s.semi_major_axis_m), f(s.eccentricity);
  f(s.inclination_rad), f(s.raan_rad), f(s.argument_of_perigee_rad), f(s.mean_anomaly_rad);
}

void EventStreamWriter::on_snapshot(const std::shared_ptr<const PopulationSnapshot>& snapshot) {
  Out out;
  out.put(snapshot->step).put(snapshot->sim_time_s);
  for_each_column(*snapshot, [&](const auto& column) { out.put_vector(column); });
  write_record(kSnapshot, out.bytes());
}

void EventStreamWriter::on_failed(const std::string& reason) {
  write_record(kFailed, Out().put_string(reason).bytes());
}

void EventStreamWriter::write_summary(const RunSummary& summary) {
  Out out;
  put_summary(out, summary);
  write_record(kSummary, out.bytes());
}

namespace {

// Hands one event or checkpoint record to the sink.
void replay_record(std::uint8_t kind, In& in, EventSink& sink) {
  std::uint64_t seq = 0;
  in.get(seq);
  switch (kind) {
    case kEncounter: {
      Encounter e;
      for_each_field(e, [&](const char*, auto& value) { in.get(value); });
      sink.on_encounter(seq, e);
      return;
    }
    case kBurnUp: {
      BurnUp b;
      in.get(b);
      sink.on_burn_up(seq, b);
      return;
    }
    case kProgress: {
      Progress p;
      in.get(p);
      sink.on_progress(seq, p);
      return;
    }
    case kBreakup:
      sink.on_breakup(seq, get_breakup(in));
      return;
    case kLifecycle: {
      LifecycleReport l;
      in.get(l);
      sink.on_lifecycle(seq, l);
      return;
    }
    case kCheckpoint: {
      std::int64_t step = 0;
      std::string bytes;
      in.get(step).get_string(bytes);
      sink.on_checkpoint(seq, step, bytes);
      return;
    }
  }
  throw std::runtime_error("event stream: unknown record kind " + std::to_string(kind));
}

}  // namespace

RunSummary replay_event_stream(int fd, EventSink& sink, const std::function<std::string()>& ended_early) {
  std::string payload;
  for (;;) {
    std::uint8_t kind = 0;
    std::uint64_t size = 0;
    std::string failure;
    try {
      if (!read_fully(fd, &kind, 1) || !read_fully(fd, &size, sizeof size)) {
        failure = ended_early();
      } else {
        payload.resize(size);
        if (size > 0 && !read_fully(fd, payload.data(), size))
          throw std::runtime_error("event stream: cut off");
      }
    } catch (const std::exception& e) {
      // What ended the writer comes first: a stream cut inside a record is its consequence.
      failure = ended_early() + "; " + e.what();
    }
    if (failure.empty() && kind == kFailed) In(payload).get_string(failure);
    if (!failure.empty()) {
      sink.on_failed(failure);
      throw std::runtime_error(failure);
    }
    In in(payload);
    if (kind == kSnapshot) {
      auto snapshot = std::make_shared<PopulationSnapshot>();
      in.get(snapshot->step).get(snapshot->sim_time_s);
      for_each_column(*snapshot, [&](auto& column) { in.get_vector(column); });
      sink.on_snapshot(snapshot);
      continue;
    }
    if (kind == kSummary) {
      RunSummary summary = get_summary(in);
      if (!summary.stopped_at_checkpoint) sink.on_finished(summary);
      return summary;
    }
    replay_record(kind, in, sink);
  }
}

}  // namespace kessler
