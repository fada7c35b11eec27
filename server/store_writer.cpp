// The store's writer thread: events and checkpoints batched into transactions in the order they were
// handed over.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <set>

#include "server/store.hpp"
#include "server/store_internal.hpp"

namespace kessler::server {

using namespace detail;

namespace {

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

// ---- the writer ----

void Store::enqueue(Pending p) {
  {
    std::lock_guard lock(queue_mutex_);
    queue_.push_back(std::move(p));
    ++appended_;
  }
  queue_cv_.notify_one();
}

void Store::append_event(std::shared_ptr<const v1::RunEvent> event) {
  Pending p;
  p.event = std::move(event);
  enqueue(std::move(p));
}

void Store::append_events(const std::vector<std::shared_ptr<const v1::RunEvent>>& events) {
  if (events.empty()) return;
  {
    std::lock_guard lock(queue_mutex_);
    for (const auto& e : events) {
      Pending p;
      p.event = e;
      queue_.push_back(std::move(p));
    }
    appended_ += events.size();
  }
  queue_cv_.notify_one();
}

void Store::append_breakup(std::shared_ptr<const v1::RunEvent> event, std::vector<StoredFragment> fragments) {
  Pending p;
  p.event = std::move(event);
  p.fragments = std::make_shared<const std::vector<StoredFragment>>(std::move(fragments));
  enqueue(std::move(p));
}

void Store::append_checkpoint(std::int64_t run_id, std::uint64_t last_seq, std::int64_t step,
                              std::string bytes) {
  append_checkpoint(run_id, last_seq, step, std::make_shared<const std::string>(std::move(bytes)));
}

void Store::discard_waiting_checkpoint(std::int64_t run_id) {
  Pending p;
  p.is_checkpoint = true;
  p.discard = true;
  p.run_id = run_id;
  enqueue(std::move(p));
}

void Store::forget_write_failure(std::int64_t run_id) {
  Pending p;
  p.resume = true;
  p.run_id = run_id;
  enqueue(std::move(p));
}

void Store::append_checkpoint(std::int64_t run_id, std::uint64_t last_seq, std::int64_t step,
                              std::shared_ptr<const std::string> bytes) {
  Pending p;
  p.is_checkpoint = true;
  p.run_id = run_id;
  p.last_seq = last_seq;
  p.step = step;
  p.checkpoint = std::move(bytes);
  enqueue(std::move(p));
}

void Store::flush() {
  std::unique_lock lock(queue_mutex_);
  std::uint64_t target = appended_;
  ++flush_waiters_;  // a held checkpoint is written now
  queue_cv_.notify_one();
  flushed_cv_.wait(lock, [&] { return committed_ >= target; });
  --flush_waiters_;
}

// The writer's prepared statements, made once for its connection.
struct Store::WriterStatements {
  explicit WriterStatements(sqlite3* db)
      : event_insert(db,
                     "INSERT OR IGNORE INTO events(run_id, seq, kind, payload, id1, id2, tca_s, "
                     "miss_distance_m, kappa, encounter_kind) VALUES(?, ?, ?, ?, ?, ?, ?, ?, ?, ?)"),
        checkpoint_upsert(db,
                          "INSERT INTO checkpoints(run_id, last_seq, step, bytes) VALUES(?, ?, ?, ?) "
                          "ON CONFLICT(run_id) DO UPDATE SET last_seq = excluded.last_seq, "
                          "step = excluded.step, bytes = excluded.bytes WHERE excluded.step >= "
                          "checkpoints.step"),
        breakup_insert(db, kBreakupInsertSql),
        fragment_insert(db, kFragmentInsertSql),
        lifecycle_insert(db, kLifecycleInsertSql),
        snapshot_insert(db, kSnapshotInsertSql) {}
  Statement event_insert;
  Statement checkpoint_upsert;
  Statement breakup_insert;
  Statement fragment_insert;
  Statement lifecycle_insert;
  Statement snapshot_insert;
};

void Store::writer_loop() {
  using Clock = std::chrono::steady_clock;
  WriterStatements statements(writer_db_);
  std::vector<Pending> batch, to_write;
  // The newest checkpoint of each run not yet written, and when each run's last one was written. A
  // checkpoint waits until min_checkpoint_interval has passed since its run's last write (or a flush,
  // or the end); a newer one arriving meanwhile replaces it, unwritten: only the latest per run is
  // kept anyway, and a run resumed from an older one re-emits the same events.
  std::map<std::int64_t, Pending> held;
  std::map<std::int64_t, Clock::time_point> last_written;
  std::set<std::int64_t> failed_runs;  // runs with a batch that could not be written
  auto due_at = [&](std::int64_t run_id) {
    auto it = last_written.find(run_id);
    return it == last_written.end() ? Clock::time_point::min() : it->second + min_checkpoint_interval_;
  };
  for (;;) {
    bool force = false;
    {
      std::unique_lock lock(queue_mutex_);
      auto ready = [&] { return stopping_ || !queue_.empty() || (!held.empty() && flush_waiters_ > 0); };
      if (held.empty()) {
        queue_cv_.wait(lock, ready);
      } else {
        auto next = Clock::time_point::max();
        for (const auto& [run_id, p] : held) next = std::min(next, due_at(run_id));
        queue_cv_.wait_until(lock, next, ready);
      }
      if (queue_.empty() && held.empty() && stopping_) return;
      force = stopping_ || flush_waiters_ > 0;
      // Up to 20,000 items per transaction: large enough to amortise the commit, small enough to
      // keep the lag behind the simulation short.
      std::size_t n = std::min<std::size_t>(queue_.size(), 20000);
      batch.clear();
      batch.reserve(n);
      for (std::size_t i = 0; i < n; ++i) {
        batch.push_back(std::move(queue_.front()));
        queue_.pop_front();
      }
      // Every item taken now is in the store's view of the queue: a flush waiting for it also
      // waits for the checkpoints it holds.
      if (queue_.empty() && flush_waiters_ > 0) force = true;
    }
    const double cpu0 = thread_cpu_s();
    std::uint64_t done = 0;  // items committed or superseded by this pass
    to_write.clear();
    for (Pending& p : batch) {
      if (p.resume) {
        failed_runs.erase(p.run_id);
        ++done;
        continue;
      }
      if (!p.is_checkpoint) {
        to_write.push_back(std::move(p));
        continue;
      }
      auto it = held.find(p.run_id);
      if (p.discard) {
        if (it != held.end()) {
          held.erase(it);
          ++done;  // the dropped checkpoint
        }
        ++done;  // this item
        continue;
      }
      if (it == held.end()) {
        held.emplace(p.run_id, std::move(p));
      } else {
        if (p.step >= it->second.step) std::swap(it->second, p);
        ++done;  // the older of the two is never written
      }
    }
    const auto now = Clock::now();
    for (auto it = held.begin(); it != held.end();) {
      if (force || now >= due_at(it->first)) {
        last_written[it->first] = now;
        to_write.push_back(std::move(it->second));  // after the events before it
        it = held.erase(it);
      } else {
        ++it;
      }
    }
    // A run whose events could not be written gets nothing more written (its later checkpoints would
    // skip the lost events): it fails, or resumes from a checkpoint taken before them.
    done += static_cast<std::uint64_t>(
        std::erase_if(to_write, [&](const Pending& p) { return failed_runs.count(p.run()) > 0; }));
    if (!to_write.empty()) {
      // A failed batch (disk full, read-only, I/O error, a table gone) is rolled back and its runs
      // told; the writer goes on, and the next batch that commits marks the store writable again.
      try {
        write_batch(to_write, statements);
        health_.record_success();
      } catch (const StoreError& e) {
        for (Statement* st :
             {&statements.event_insert, &statements.checkpoint_upsert, &statements.breakup_insert,
              &statements.fragment_insert, &statements.lifecycle_insert, &statements.snapshot_insert})
          st->reset();
        sqlite3_exec(writer_db_, "ROLLBACK", nullptr, nullptr, nullptr);
        health_.record_failure(e.what());
        for (const Pending& p : to_write) failed_runs.insert(p.run());
        report_write_failure(to_write, e.what());
      }
    }
    done += to_write.size();
    const double cpu = thread_cpu_s() - cpu0;
    {
      std::lock_guard lock(queue_mutex_);
      committed_ += done;
      writer_cpu_s_ += cpu;
    }
    flushed_cv_.notify_all();
  }
}

void Store::report_write_failure(const std::vector<Pending>& batch, const std::string& error) {
  std::set<std::int64_t> runs;
  for (const Pending& p : batch) runs.insert(p.run());
  std::function<void(std::int64_t, const std::string&)> handler;
  {
    std::lock_guard lock(handler_mutex_);
    handler = write_failure_handler_;
  }
  if (handler)
    for (std::int64_t run_id : runs) handler(run_id, error);
}

void Store::write_batch(std::vector<Pending>& batch, WriterStatements& statements) {
  throw_if_failing_for_test();
  sqlite3* db = writer_db_;
  exec(db, "BEGIN IMMEDIATE");
  Statement& event_insert = statements.event_insert;
  Statement& checkpoint_upsert = statements.checkpoint_upsert;
  std::string payload;
  std::uint64_t written = 0;
  for (Pending& p : batch) {
    if (p.is_checkpoint) {
      checkpoint_upsert.bind(1, p.run_id).bind(2, p.last_seq).bind(3, p.step).bind_blob(4, *p.checkpoint);
      checkpoint_upsert.run();
      continue;
    }
    if (p.snapshot) {
      write_snapshot_row(statements.snapshot_insert, p.run_id, *p.snapshot);
      continue;
    }
    const v1::RunEvent& e = *p.event;
    int kind = e.has_progress()    ? kKindProgress
               : e.has_encounter() ? kKindEncounter
               : e.has_breakup()   ? kKindBreakup
               : e.has_lifecycle() ? kKindLifecycle
                                   : kKindBurnUp;
    payload.clear();
    e.SerializeToString(&payload);
    event_insert.bind(1, e.run_id()).bind(2, e.seq()).bind(3, kind).bind_blob(4, payload);
    if (e.has_encounter()) {
      const v1::Encounter& c = e.encounter();
      event_insert.bind(5, c.id1()).bind(6, c.id2()).bind(7, c.tca_s()).bind(8, c.miss_distance_m());
      event_insert.bind(9, c.kappa()).bind(10, static_cast<int>(c.kind()));
    } else {
      event_insert.bind_null(5).bind_null(6).bind_null(7).bind_null(8).bind_null(9).bind_null(10);
    }
    event_insert.run();
    // A re-emitted event (a resumed run) is already stored, with its breakup's or lifecycle's rows.
    if (e.has_breakup() && sqlite3_changes(db) > 0)
      write_breakup_rows(statements.breakup_insert, statements.fragment_insert, e,
                         p.fragments ? *p.fragments : std::vector<StoredFragment>{});
    if (e.has_lifecycle() && sqlite3_changes(db) > 0) write_lifecycle_row(statements.lifecycle_insert, e);
    ++written;
  }
  exec(db, "COMMIT");
  std::lock_guard lock(queue_mutex_);
  events_written_ += written;
}

double Store::writer_cpu_s() const {
  std::lock_guard lock(const_cast<std::mutex&>(queue_mutex_));
  return writer_cpu_s_;
}

std::uint64_t Store::events_written() const {
  std::lock_guard lock(const_cast<std::mutex&>(queue_mutex_));
  return events_written_;
}

}  // namespace kessler::server
