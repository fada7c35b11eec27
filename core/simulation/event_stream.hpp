// A run's EventSink calls as a byte stream, and back: how kessler-mpi's rank 0 hands a run's events,
// checkpoints and end to kesslerd, which replays them into the sinks an in-process run would feed. Both
// ends are the same build (the records are the core's structs, field by field, in host byte order).
//
// A record: one kind byte, the payload's length (8 bytes), the payload. The stream ends with a summary
// record (the run returned: finished, cancelled or stopped at a checkpoint) or a failure record.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "core/simulation/events.hpp"

namespace kessler {

// Writes each call as a record on a file descriptor (blocking; a pipe's reader is the back-pressure).
// A write that fails (the reader has gone) throws, which fails the run.
class EventStreamWriter final : public EventSink {
 public:
  explicit EventStreamWriter(int fd) : fd_(fd) {}
  void on_encounter(std::uint64_t seq, const Encounter& encounter) override;
  void on_burn_up(std::uint64_t seq, const BurnUp& burn_up) override;
  void on_progress(std::uint64_t seq, const Progress& progress) override;
  void on_breakup(std::uint64_t seq, const BreakupReport& breakup) override;
  void on_lifecycle(std::uint64_t seq, const LifecycleReport& event) override;
  void on_checkpoint(std::uint64_t last_seq, std::int64_t step, const std::string& bytes) override;
  void on_snapshot(const std::shared_ptr<const PopulationSnapshot>& snapshot) override;
  // The summary record carries the end (write_summary), also for a stop at a checkpoint, which has no
  // on_finished.
  void on_finished(const RunSummary&) override {}
  void on_failed(const std::string& reason) override;
  // The last record of a run that returned.
  void write_summary(const RunSummary& summary);

 private:
  void write_record(std::uint8_t kind, const std::string& payload);
  int fd_;
};

// Reads records from `fd` and hands each to `sink` as Simulation::run would: returns the run's summary
// (on_finished called first unless the run stopped at a checkpoint); on a failure record, or a stream
// that ends without a summary, calls sink.on_failed and throws std::runtime_error with the reason.
// `ended_early` says what happened to the writer when the stream ends without its last record.
RunSummary replay_event_stream(int fd, EventSink& sink, const std::function<std::string()>& ended_early);

}  // namespace kessler
