#include "server/run_manager.hpp"

#include <malloc.h>

#include <chrono>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/scenario/run_builder.hpp"
#include "server/conjunction_assessment.hpp"
#include "server/event_relay.hpp"
#include "server/request_validation.hpp"

namespace kessler::server {
namespace {

using Code = ServiceError::Code;

double unix_now_s() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

// The population's names, for the conjunction listings (a resumed run's are stored already).
void store_names(Store& store, std::int64_t run_id, const Population& population) {
  std::vector<std::pair<std::uint64_t, std::string>> names;
  names.reserve(population.size());
  for (std::size_t i = 0; i < population.size(); ++i)
    if (!population.name[i].empty()) names.emplace_back(population.id[i], population.name[i]);
  store.set_object_names(run_id, names);
}

// Names the objects of encounters on their way to a watcher. The run's names are read at its first
// encounter: they are stored before the run's first event.
class EncounterNamer {
 public:
  EncounterNamer(Store& store, std::int64_t run_id) : store_(store), run_id_(run_id) {}
  v1::RunEvent named(const v1::RunEvent& event) {
    if (!names_) names_ = store_.object_names(run_id_);
    v1::RunEvent out = event;
    out.mutable_encounter()->set_name1(name_of(event.encounter().id1()));
    out.mutable_encounter()->set_name2(name_of(event.encounter().id2()));
    return out;
  }

 private:
  std::string name_of(std::uint64_t id) const {
    auto it = names_->find(id);
    return it == names_->end() ? std::string() : it->second;
  }
  Store& store_;
  std::int64_t run_id_;
  std::optional<std::map<std::uint64_t, std::string>> names_;
};

v1::StateChange state_of(const v1::Run& run) {
  v1::StateChange change;
  change.set_state(run.state());
  change.set_error(run.error());
  if (run.has_summary()) *change.mutable_summary() = run.summary();
  return change;
}

// Seconds the scenario simulates, for the stats' default bin (the core's defaults when unset).
double run_length_s(const v1::Run& run) {
  if (run.has_summary() && run.summary().sim_time_s() > 0) return run.summary().sim_time_s();
  const v1::Scenario& s = run.scenario();
  if (s.has_duration_days()) return s.duration_days() * 86400.0;
  if (run.progress().total_steps() > 0 && run.progress().step() > 0)
    return run.progress().sim_time_s() * static_cast<double>(run.progress().total_steps()) /
           static_cast<double>(run.progress().step());
  return 86400.0;
}

}  // namespace

std::uint64_t strip_inline_data(v1::Scenario& scenario) {
  std::uint64_t bytes = 0;
  auto take = [&](std::string* field) {
    bytes += field->size();
    field->clear();
    field->shrink_to_fit();
  };
  v1::PopulationSource* population = scenario.mutable_population();
  if (population->has_catalog()) {
    take(population->mutable_catalog()->mutable_text());
    take(population->mutable_catalog()->mutable_satcat_csv());
    take(population->mutable_catalog()->mutable_active_list());
  }
  if (population->has_state_table()) take(population->mutable_state_table());
  if (scenario.has_traffic()) take(scenario.mutable_traffic()->mutable_launch_plan_csv());
  return bytes;
}

void tune_allocator_for_runs() {
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 64 << 20);
}

RunManager::RunManager(const ManagerOptions& options)
    : options_(options), store_(options.db_path, options.min_checkpoint_interval) {
  scheduler_ =
      std::make_unique<Scheduler>(options.runs_at_once, options.queue_limit,
                                  [this](std::int64_t id, RunControl& control) { execute(id, control); });
  for (const auto& [id, why] : store_.quarantined_runs())
    std::cerr << "kesslerd: run " << id << " quarantined: " << why << std::endl;
  store_.set_write_failure_handler(
      [this](std::int64_t id, const std::string& error) { note_store_failure(id, error); });
  // A full disk does not keep the daemon from serving reads: recovery waits until the store can write.
  try {
    recover();
  } catch (const StoreError& e) {
    store_.health().record_failure(e.what());
    recovery_pending_ = true;
  }
  start_health_thread();
}

RunManager::~RunManager() {
  shutdown();
}

void RunManager::shutdown() {
  stopping_ = true;
  stop_health_thread();
  scheduler_->shutdown(true);
  store_.flush();
  store_.set_write_failure_handler(nullptr);
}

std::shared_ptr<EventHub> RunManager::hub(std::int64_t run_id) {
  std::lock_guard lock(hubs_mutex_);
  auto it = hubs_.find(run_id);
  return it == hubs_.end() ? nullptr : it->second;
}

v1::Scenario RunManager::read_scenario(const v1::Scenario* scenario, const std::string* text) {
  v1::Scenario out;
  if (scenario) {
    out = *scenario;
  } else if (text) {
    if (auto error = parse_scenario(*text, out))
      throw ServiceError(Code::kInvalidArgument, error->message(), error->path);
  } else {
    throw ServiceError(Code::kInvalidArgument, "scenario: missing (give scenario or scenario_text)",
                       "scenario");
  }
  check_finite_numbers(out, "");  // NaN and infinities, whichever way they came
  return out;
}

std::optional<v1::IngestReport> RunManager::admit(const v1::Scenario& scenario, int threads) {
  if (threads < 0 || threads > 1024)
    throw ServiceError(Code::kInvalidArgument, "threads: must be between 0 and 1024", "threads");
  if (auto error = validate_scenario(scenario))
    throw ServiceError(Code::kInvalidArgument, error->message(), error->path);
  // An inline population is ingested once here, so a broken catalog is refused now rather than
  // failing the run later.
  const auto source = scenario.population().source_case();
  std::optional<IngestReport> ingest;
  if (source == v1::PopulationSource::kCatalog || source == v1::PopulationSource::kStateTable) {
    BuildOptions build;
    build.threads = 1;
    if (!options_.datasets_dir.empty()) build.datasets_dir = options_.datasets_dir;
    if (!options_.traffic_dir.empty()) build.traffic_dir = options_.traffic_dir;
    FieldError error;
    if (!build_simulation(scenario, build, &error, &ingest))
      throw ServiceError(Code::kInvalidArgument, error.message(), error.path);
  }
  std::optional<std::uint64_t> ingested;
  if (ingest) ingested = ingest_outcome(*ingest).kept;
  if (auto error = check_run_limits(scenario, estimate_run(scenario, ingested), options_.limits))
    throw ServiceError(Code::kInvalidArgument, error->message(), error->path);
  require_writable();
  if (!ingest) return std::nullopt;
  return ingest_proto(*ingest);
}

v1::Run RunManager::submit(const v1::SubmitRunRequest& request, const std::string& submitter) {
  const std::string& request_id = request.request_id();
  if (!request_id.empty())
    if (auto id = store_.run_of_request(submitter, request_id)) return get(*id, false);
  const v1::Scenario scenario =
      read_scenario(request.has_scenario() ? &request.scenario() : nullptr,
                    request.has_scenario_text() ? &request.scenario_text() : nullptr);
  if (scenario.has_ensemble())
    throw ServiceError(Code::kInvalidArgument,
                       "ensemble: a scenario with an ensemble is submitted with SubmitEnsemble "
                       "(kessler submit does)",
                       "ensemble");
  std::optional<v1::IngestReport> ingest = admit(scenario, request.threads());
  // The ingest's buffers (hundreds of MB for a large inline catalog) go back to the system now.
  if (ingest) malloc_trim(0);
  if (scheduler_->queued() >= options_.queue_limit)
    throw ServiceError(Code::kResourceExhausted, "queue full: " + std::to_string(options_.queue_limit) +
                                                     " runs are waiting; try later");
  int threads = request.threads() > 0 ? request.threads() : options_.threads_per_run;
  std::unique_lock same_request(requests_mutex_, std::defer_lock);
  if (!request_id.empty()) {
    same_request.lock();  // a retry racing its first try finds the first run here
    if (auto existing = store_.run_of_request(submitter, request_id)) return get(*existing, false);
  }
  std::int64_t id = 0;
  try {
    id = store_.create_run(scenario, threads, unix_now_s(), submitter, request_id);
    if (ingest) store_.set_ingest(id, *ingest);
  } catch (const StoreError& e) {
    store_.health().record_failure(e.what());
    if (id != 0) record_finish_later(id, v1::RUN_STATE_FAILED, e.what(), nullptr);
    throw ServiceError(Code::kUnavailable, std::string("the store cannot write (") + e.what() +
                                               "); submissions are refused until it can, reads go on");
  }
  // As for resume: the answer is the run as queued, read before a free worker can start it.
  v1::Run queued = get(id, false);
  if (!scheduler_->enqueue(id)) {
    store_.delete_run(id);
    throw ServiceError(Code::kResourceExhausted, "queue full: " + std::to_string(options_.queue_limit) +
                                                     " runs are waiting; try later");
  }
  return queued;
}

v1::Run RunManager::get(std::int64_t run_id) {
  return get(run_id, true);
}

v1::Run RunManager::get(const v1::GetRunRequest& request) {
  v1::Run run = get(request.run_id(), true);
  if (!request.include_inline_data())
    run.set_inline_data_omitted_bytes(strip_inline_data(*run.mutable_scenario()));
  return run;
}

v1::Run RunManager::get(std::int64_t run_id, bool with_scenario) {
  auto run = store_.get_run(run_id, with_scenario);
  if (!run) throw ServiceError(Code::kNotFound, "run " + std::to_string(run_id) + " not found");
  overlay_faults(*run);
  if (run->state() == v1::RUN_STATE_QUEUED) run->set_queue_position(scheduler_->queue_position(run_id));
  return *run;
}

v1::ListRunsResponse RunManager::list(const v1::ListRunsRequest& request, const std::string* submitter) {
  if (request.page_size() < 0)
    throw ServiceError(Code::kInvalidArgument, "page_size: must be >= 0", "page_size");
  std::vector<v1::RunState> states;
  for (int s : request.states()) states.push_back(static_cast<v1::RunState>(s));
  Page<v1::Run> page;
  try {
    page = store_.list_runs(states, request.page_size(), request.page_token(), submitter);
  } catch (const std::invalid_argument& e) {
    throw ServiceError(Code::kInvalidArgument, e.what(), "page_token");
  }
  v1::ListRunsResponse response;
  for (auto& run : page.items) {
    if (run.state() == v1::RUN_STATE_QUEUED) run.set_queue_position(scheduler_->queue_position(run.id()));
    *response.add_runs() = std::move(run);
  }
  response.set_next_page_token(page.next_token);
  return response;
}

v1::Run RunManager::cancel(std::int64_t run_id) {
  v1::Run run = get(run_id, false);
  if (is_terminal(run.state()))
    throw ServiceError(Code::kFailedPrecondition, "run " + std::to_string(run_id) + " has already ended (" +
                                                      run_state_name(run.state()) + ")");
  auto result = scheduler_->cancel(run_id);
  if (result != Scheduler::CancelResult::kSignalled) finish(run_id, v1::RUN_STATE_CANCELLED, "", nullptr);
  return get(run_id, false);
}

v1::Run RunManager::resume(std::int64_t run_id) {
  v1::Run run = get(run_id, false);
  require_not_quarantined(run_id);
  if (run.state() != v1::RUN_STATE_FAILED && run.state() != v1::RUN_STATE_CANCELLED)
    throw ServiceError(Code::kFailedPrecondition, "run " + std::to_string(run_id) + " is " +
                                                      run_state_name(run.state()) +
                                                      "; only a failed or cancelled run resumes");
  require_writable();
  if (scheduler_->queued() >= options_.queue_limit)
    throw ServiceError(Code::kResourceExhausted, "queue full: " + std::to_string(options_.queue_limit) +
                                                     " runs are waiting; try later");
  {
    std::lock_guard lock(faults_mutex_);  // an end the store could not take yet is replaced by this
    unrecorded_.erase(run_id);
  }
  try {
    store_.forget_write_failure(run_id);
    store_.set_queued(run_id);
  } catch (const StoreError& e) {
    store_.health().record_failure(e.what());
    throw ServiceError(Code::kUnavailable, std::string("the store cannot write (") + e.what() + ")");
  }
  // The answer is the run as queued: once enqueued, a free worker may start it before get() could read it.
  v1::Run queued = get(run_id, false);
  if (!scheduler_->enqueue(run_id)) {
    store_.set_finished(run_id, run.state(), unix_now_s(), run.error(), nullptr);
    throw ServiceError(Code::kResourceExhausted, "queue full: " + std::to_string(options_.queue_limit) +
                                                     " runs are waiting; try later");
  }
  return queued;
}

void RunManager::remove(std::int64_t run_id) {
  v1::Run run = get(run_id, false);
  if (!is_terminal(run.state()))
    throw ServiceError(Code::kFailedPrecondition, "run " + std::to_string(run_id) + " is " +
                                                      run_state_name(run.state()) +
                                                      "; cancel it before deleting");
  if (!store_.delete_run(run_id))
    throw ServiceError(Code::kNotFound, "run " + std::to_string(run_id) + " not found");
}

v1::ListConjunctionsResponse RunManager::conjunctions(const v1::ListConjunctionsRequest& request) {
  get(request.run_id(), false);  // NOT_FOUND
  require_not_quarantined(request.run_id());
  if (request.page_size() < 0)
    throw ServiceError(Code::kInvalidArgument, "page_size: must be >= 0", "page_size");
  if (request.has_kappa_min() && request.has_kappa_max() && request.kappa_min() > request.kappa_max())
    throw ServiceError(Code::kInvalidArgument, "kappa_min: above kappa_max", "kappa_min");
  if (request.has_time_min_s() && request.has_time_max_s() && request.time_min_s() > request.time_max_s())
    throw ServiceError(Code::kInvalidArgument, "time_min_s: after time_max_s", "time_min_s");
  if (const std::string& o = request.order_by();
      !o.empty() && o != "seq" && o != "tca_s" && o != "miss_distance_m" && o != "kappa")
    throw ServiceError(Code::kInvalidArgument,
                       "order_by: must be seq, tca_s, miss_distance_m or kappa, got '" + o + "'", "order_by");
  try {
    return assessed_conjunctions(store_, request);  // server/conjunction_assessment.cpp
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    throw ServiceError(Code::kInvalidArgument, message, message.substr(0, message.find(':')));
  }
}

v1::RunStats RunManager::stats(const v1::GetRunStatsRequest& request) {
  v1::Run run = get(request.run_id());
  require_not_quarantined(request.run_id());
  if (request.time_bin_s() < 0)
    throw ServiceError(Code::kInvalidArgument, "time_bin_s: must be >= 0", "time_bin_s");
  double length = run_length_s(run);
  check_stats_size(length, request.time_bin_s(), static_cast<std::size_t>(request.kappas_size()));
  v1::RunStats stats = store_.run_stats(request, length);
  stats.set_state(run.state());
  if (run.has_summary()) *stats.mutable_timers() = run.summary().timers();
  return stats;
}

v1::ListFragmentsResponse RunManager::fragments(const v1::ListFragmentsRequest& request) {
  get(request.run_id(), false);  // NOT_FOUND
  require_not_quarantined(request.run_id());
  if (request.page_size() < 0)
    throw ServiceError(Code::kInvalidArgument, "page_size: must be >= 0", "page_size");
  Page<v1::Fragment> page;
  try {
    page = store_.list_fragments(request);
  } catch (const std::invalid_argument& e) {
    throw ServiceError(Code::kInvalidArgument, e.what(), "page_token");
  }
  v1::ListFragmentsResponse response;
  for (auto& f : page.items) *response.add_fragments() = std::move(f);
  response.set_next_page_token(page.next_token);
  response.set_total(page.total);
  return response;
}

void RunManager::finish(std::int64_t run_id, v1::RunState state, const std::string& given_error,
                        const v1::RunSummary* summary) {
  {
    std::lock_guard lock(hubs_mutex_);
    mpi_retries_used_.erase(run_id);
  }
  store_.discard_waiting_checkpoint(run_id);  // an ended run resumes from nothing
  store_.flush();                             // every event is durable before the run reads as ended
  std::string error = given_error;
  if (auto failure = take_store_failure(run_id)) {  // events lost: the run failed, whatever it reached
    state = v1::RUN_STATE_FAILED;
    error = *failure;
    summary = nullptr;
  }
  try {
    store_.set_finished(run_id, state, unix_now_s(), error, summary);
  } catch (const StoreError& e) {
    store_.health().record_failure(e.what());
    record_finish_later(run_id, state, error, summary);  // written when the store can write again
  }
  std::shared_ptr<EventHub> h;
  {
    std::lock_guard lock(hubs_mutex_);
    auto it = hubs_.find(run_id);
    if (it != hubs_.end()) {
      h = it->second;
      hubs_.erase(it);
    }
  }
  if (h) {
    v1::StateChange change;
    change.set_state(state);
    change.set_error(error);
    if (summary) *change.mutable_summary() = *summary;
    h->set_state(change);
  }
}

void RunManager::execute(std::int64_t run_id, RunControl& control) {
  // A queued run waits while the store cannot write (it would only fail), and starts when it can.
  while (!store_.health().writable() && !stopping_ && !control.cancel && !control.stop_after_checkpoint &&
         !store_.probe_writable())
    std::this_thread::sleep_for(options_.store_probe_interval);
  if (!store_.health().writable()) {
    if (control.cancel) finish(run_id, v1::RUN_STATE_CANCELLED, "", nullptr);
    return;  // the daemon stops: the run stays queued in the store
  }
  try {
    execute_run(run_id, control);
  } catch (const StoreError& e) {  // the store failed a run update: the run fails, the daemon goes on
    store_.health().record_failure(e.what());
    finish(run_id, v1::RUN_STATE_FAILED, e.what(), nullptr);
  }
}

void RunManager::execute_run(std::int64_t run_id, RunControl& control) {
  auto run = store_.get_run(run_id);
  if (!run || run->state() != v1::RUN_STATE_QUEUED) return;  // cancelled or deleted meanwhile
  store_.flush();
  auto h = std::make_shared<EventHub>(store_.max_seq(run_id), options_.hub_capacity);
  {
    std::lock_guard lock(hubs_mutex_);
    hubs_[run_id] = h;
  }
  store_.set_running(run_id, unix_now_s());
  v1::StateChange running;
  running.set_state(v1::RUN_STATE_RUNNING);
  h->set_state(running);

  BuildOptions build;
  build.threads = run->threads();
  if (!options_.datasets_dir.empty()) build.datasets_dir = options_.datasets_dir;
  if (!options_.traffic_dir.empty()) build.traffic_dir = options_.traffic_dir;
  build.adjust_config = options_.adjust_config;
  FieldError error;
  std::unique_ptr<Simulation> simulation;
  std::optional<IngestReport> ingest;
  std::optional<StoredCheckpoint> checkpoint;
  try {
    checkpoint = store_.latest_checkpoint(run_id);
    simulation = checkpoint ? resume_simulation(run->scenario(), checkpoint->bytes, build, &error)
                            : build_simulation(run->scenario(), build, &error, &ingest);
    if (ingest) store_.set_ingest(run_id, ingest_proto(*ingest));
    if (simulation) store_names(store_, run_id, simulation->population());
  } catch (const std::exception& e) {
    error.reason = e.what();
  }
  if (!simulation) {
    finish(run_id, v1::RUN_STATE_FAILED, error.message().empty() ? "cannot build the run" : error.message(),
           nullptr);
    return;
  }
  // The simulation thread hands events to the relay and goes on; the relay feeds hub and store.
  auto relay = std::make_unique<EventRelay>(run_id, *h, store_, options_.relay_gather,
                                            options_.min_checkpoint_interval, &control);
  EventLimitSink limited(*relay, control, options_.limits.max_events);
  RunSummary summary;
  try {
    if (options_.mpi.launcher.empty()) {
      summary = simulation->run(limited, control);
    } else {  // built above for its checks, ingest and names; the ranks compute it
      simulation.reset();
      RanksRun ranks{
          run_id, &run->scenario(), nullptr, 0, run->threads(), options_.datasets_dir, options_.traffic_dir};
      if (checkpoint) ranks.checkpoint = &checkpoint->bytes, ranks.checkpoint_step = checkpoint->step;
      summary = run_on_ranks(options_.mpi, ranks, limited, control);
    }
  } catch (const MpiJobLost& e) {
    relay->drain();
    relay_cpu_s_.fetch_add(relay->cpu_s());
    if (!requeue_lost_job(run_id, control, e.what())) finish(run_id, v1::RUN_STATE_FAILED, e.what(), nullptr);
    return;
  } catch (const std::exception& e) {
    relay->drain();
    relay_cpu_s_.fetch_add(relay->cpu_s());
    finish(run_id, v1::RUN_STATE_FAILED, relay->failure().empty() ? e.what() : relay->failure(), nullptr);
    return;
  }
  relay->drain();  // every event in the hub and queued in the store before the run ends
  relay_cpu_s_.fetch_add(relay->cpu_s());
  if (limited.exceeded()) {
    finish(run_id, v1::RUN_STATE_FAILED, limited.failure(), nullptr);
    return;
  }
  if (control.stop_after_checkpoint && !control.cancel && summary.cancelled) {
    // Daemon shutdown: the run stays "running" in the store and resumes at the next start.
    store_.flush();
    std::lock_guard lock(hubs_mutex_);
    hubs_.erase(run_id);
    return;
  }
  v1::RunSummary out = to_proto(summary);
  finish(run_id, control.cancel ? v1::RUN_STATE_CANCELLED : v1::RUN_STATE_SUCCEEDED, "", &out);
}

bool RunManager::requeue_lost_job(std::int64_t run_id, const RunControl& control, const std::string& why) {
  if (control.cancel || control.stop_after_checkpoint || stopping_) return false;
  int retry = 0;
  {
    std::lock_guard lock(hubs_mutex_);
    int& used = mpi_retries_used_[run_id];
    if (used >= options_.mpi.retries) {
      mpi_retries_used_.erase(run_id);
      return false;
    }
    retry = ++used;
  }
  std::cerr << "kesslerd: run " << run_id
            << ": MPI job lost; computing the run again from its last checkpoint (retry " << retry << " of "
            << options_.mpi.retries << "): " << why << std::endl;
  // As after a daemon restart: the run waits in the queue, its events and checkpoint stay, and its next
  // job resumes from that checkpoint (the events it computes again are stored once).
  store_.flush();
  store_.set_queued(run_id);
  {
    std::lock_guard lock(hubs_mutex_);
    hubs_.erase(run_id);
  }
  scheduler_->enqueue(run_id, true);
  return true;
}

void RunManager::watch(const v1::WatchRunRequest& request, const WriteEvent& write,
                       const std::function<bool()>& stop) {
  const std::int64_t id = request.run_id();
  v1::Run run = get(id, false);  // NOT_FOUND before the stream starts
  require_not_quarantined(id);
  std::uint64_t cursor = request.after_seq();
  const bool no_progress = request.no_progress();
  constexpr std::size_t kBatch = 1000;

  v1::RunState sent_state = v1::RUN_STATE_UNSPECIFIED;
  // A terminal state is the stream's last message, after every event: the loop sends it when it ends.
  auto send_state = [&](const v1::StateChange& change) {
    if (change.state() == sent_state) return true;
    sent_state = change.state();
    v1::RunEvent event;
    event.set_run_id(id);
    *event.mutable_state() = change;
    return write(event, false);
  };
  // `more`: another event follows at once, so the transport may hold this one and send them together.
  EncounterNamer namer(store_, id);
  auto send = [&](const v1::RunEvent& event, bool more) {
    cursor = event.seq();
    if (no_progress && event.has_progress()) return true;
    return event.has_encounter() ? write(namer.named(event), more) : write(event, more);
  };
  auto send_from_store = [&]() -> int {  // events sent, or -1 when the client went away
    auto events = store_.read_events(id, cursor, static_cast<int>(kBatch), false);
    for (std::size_t i = 0; i < events.size(); ++i)
      if (!send(events[i], i + 1 < events.size())) return -1;
    return static_cast<int>(events.size());
  };

  const v1::StateChange opening = [&] {
    if (auto h = hub(id)) return h->state();
    return state_of(run);
  }();
  if (!is_terminal(opening.state()) && !send_state(opening)) return;
  // The daemon stopping ends the stream as UNAVAILABLE, so clients reconnect after the restart.
  auto check_stopping = [&] {
    if (stopping_)
      throw ServiceError(Code::kUnavailable, "kesslerd is shutting down; reconnect with after_seq");
  };
  while (!stop()) {
    check_stopping();
    std::shared_ptr<EventHub> h = hub(id);
    if (!h) {
      // Not live: queued, ended, or between the two. The store has every event.
      int sent = send_from_store();
      if (sent < 0) return;
      if (sent > 0) continue;
      auto now = store_.get_run(id, false);
      if (!now) return;  // deleted meanwhile
      if (is_terminal(now->state())) {
        // The hub may have gone between our two looks: read once more before the final state.
        if (send_from_store() != 0) continue;
        send_state(state_of(*now));
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      continue;
    }
    std::uint64_t version = h->state_version();
    // A terminal state must reach the client after every event, never before. So the looks go state,
    // then closed, then events: a hub closes only after its last event, so an empty read after a closed
    // look means nothing is left; and a state taken before an open look is not terminal. (In any other
    // order the run could publish its last events and close between two looks.)
    v1::StateChange state = h->state();
    const bool closed = h->closed();
    auto read = h->read_after(cursor, kBatch);
    if (read.behind) {
      // Fell out of the window (or reconnected with an old number): catch up from the store, which
      // may lag the hub by one writer batch.
      int sent = send_from_store();
      if (sent < 0) return;
      if (sent == 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
      continue;
    }
    if (!read.events.empty()) {
      for (std::size_t i = 0; i < read.events.size(); ++i)
        if (!send(*read.events[i], i + 1 < read.events.size())) return;
      continue;
    }
    if (closed) {
      send_state(h->state());
      return;
    }
    if (!send_state(state)) return;
    // The relay publishes a few milliseconds of events at a time, so one wake-up brings a batch.
    h->wait(cursor, version, std::chrono::milliseconds(200));
  }
}

}  // namespace kessler::server
