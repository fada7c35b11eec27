#include "server/run_protos.hpp"

#include <stdexcept>
#include <string>
#include <type_traits>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>

#include "core/scenario/run_builder.hpp"

namespace kessler::server {
namespace {

void set_vector(v1::Vector3* out, const Eigen::Vector3d& v) {
  out->set_x(v.x());
  out->set_y(v.y());
  out->set_z(v.z());
}

}  // namespace

v1::IngestReport ingest_proto(const IngestReport& report) {
  const IngestOutcome outcome = ingest_outcome(report);
  v1::IngestReport out;
  out.set_records(outcome.records);
  out.set_kept(outcome.kept);
  for (const auto& [reason, count] : outcome.dropped) {
    v1::IngestDrop* drop = out.add_dropped();
    drop->set_reason(reason);
    drop->set_count(count);
  }
  for (const auto& [source, count] : outcome.drag) {
    v1::IngestDrop* drag = out.add_drag();
    drag->set_reason(source);
    drag->set_count(count);
  }
  return out;
}

v1::RunSummary to_proto(const RunSummary& s) {
  v1::RunSummary out;
  out.set_steps(s.steps);
  out.set_sim_time_s(s.sim_time_s);
  out.set_events(s.events);
  out.set_conjunctions(s.conjunctions);
  out.set_collisions(s.collisions);
  out.set_evasions(s.evasions);
  out.set_burn_ups(s.burn_ups);
  out.set_objects_initial(s.objects_initial);
  out.set_objects_final(s.objects_final);
  out.set_events_digest(s.events_digest);
  out.set_state_digest(s.state_digest);
  out.set_cancelled(s.cancelled);
  auto* t = out.mutable_timers();
  t->set_integrator_s(s.timers.integrator_s);
  t->set_burn_up_s(s.timers.burn_up_s);
  t->set_grid_s(s.timers.grid_s);
  t->set_detection_s(s.timers.detection_s);
  t->set_output_s(s.timers.output_s);
  t->set_checkpoint_s(s.timers.checkpoint_s);
  t->set_total_s(s.timers.total_s);
  return out;
}

v1::Progress to_proto(const Progress& p) {
  v1::Progress out;
  out.set_step(p.step);
  out.set_total_steps(p.total_steps);
  out.set_sim_time_s(p.sim_time_s);
  out.set_objects_alive(p.objects_alive);
  out.set_events_so_far(p.events_so_far);
  out.set_wall_s(p.wall_s);
  out.set_eta_s(p.eta_s);
  auto* by_type = out.mutable_objects_by_type();
  by_type->set_payload(p.objects_by_type.payload);
  by_type->set_rocket_body(p.objects_by_type.rocket_body);
  by_type->set_debris(p.objects_by_type.debris);
  by_type->set_unknown(p.objects_by_type.unknown);
  by_type->set_fragments(p.objects_by_type.fragments);
  return out;
}

v1::Breakup to_proto(const BreakupReport& b) {
  v1::Breakup out;
  out.set_breakup_id(b.breakup_id);
  out.set_source(b.source == BreakupSource::kCollision ? v1::BREAKUP_SOURCE_COLLISION
                                                       : v1::BREAKUP_SOURCE_SCHEDULED);
  out.set_event_index(b.event_index);
  out.set_time_s(b.time_s);
  out.set_kind(b.kind == BreakupKind::kCollision ? v1::BREAKUP_KIND_COLLISION : v1::BREAKUP_KIND_EXPLOSION);
  for (ObjectId id : b.parents) out.add_parents(id);
  out.set_catastrophic(b.catastrophic);
  out.set_specific_energy_j_per_g(b.specific_energy_j_per_g);
  out.set_fragment_count(b.fragment_count);
  out.set_fragment_mass_kg(b.fragment_mass_kg);
  out.set_first_id(b.first_id);
  out.set_last_id(b.last_id);
  out.set_remnant_id(b.remnant_id);
  return out;
}

// The core's kinds and the wire's have the same numbers.
static_assert(static_cast<int>(LifecycleEventKind::kLaunch) == v1::LIFECYCLE_KIND_LAUNCH);
static_assert(static_cast<int>(LifecycleEventKind::kEndOfLife) == v1::LIFECYCLE_KIND_END_OF_LIFE);
static_assert(static_cast<int>(LifecycleEventKind::kDisposal) == v1::LIFECYCLE_KIND_DISPOSAL);
static_assert(static_cast<int>(LifecycleEventKind::kDisposalFailed) == v1::LIFECYCLE_KIND_DISPOSAL_FAILED);
static_assert(static_cast<int>(LifecycleEventKind::kDeorbit) == v1::LIFECYCLE_KIND_DEORBIT);

v1::Lifecycle to_proto(const LifecycleReport& e) {
  v1::Lifecycle out;
  out.set_kind(static_cast<v1::LifecycleKind>(static_cast<int>(e.kind)));
  out.set_time_s(e.time_s);
  out.set_first_id(e.first_id);
  out.set_last_id(e.last_id);
  out.set_row(e.row);
  out.set_altitude_m(e.altitude_m);
  return out;
}

std::vector<StoredFragment> fragments_of(const BreakupReport& b) {
  std::vector<StoredFragment> out;
  out.reserve(b.fragments.size());
  for (const FragmentReport& f : b.fragments)
    out.push_back(
        {f.id, f.parent_id, f.characteristic_length_m, f.area_to_mass_m2_kg, f.mass_kg, f.delta_v_m_s});
  return out;
}

// Field by field as for_each_field names them, so a field added to Encounter needs only its proto field
// of the same name (and, for a new type, a branch below).
v1::Encounter to_proto(const Encounter& e) {
  v1::Encounter out;
  const google::protobuf::Descriptor* message = out.GetDescriptor();
  const google::protobuf::Reflection* reflection = out.GetReflection();
  for_each_field(e, [&](const char* name, const auto& value) {
    const google::protobuf::FieldDescriptor* field = message->FindFieldByName(name);
    if (!field) throw std::logic_error(std::string("kessler.v1.Encounter has no field ") + name);
    using T = std::remove_cvref_t<decltype(value)>;
    if constexpr (std::is_same_v<T, std::uint64_t>)
      reflection->SetUInt64(&out, field, value);
    else if constexpr (std::is_same_v<T, double>)
      reflection->SetDouble(&out, field, value);
    else if constexpr (std::is_same_v<T, EncounterKind>)
      reflection->SetEnumValue(&out, field, static_cast<int>(value));
    else if constexpr (std::is_same_v<T, Eigen::Vector3d>)
      set_vector(static_cast<v1::Vector3*>(reflection->MutableMessage(&out, field)), value);
    else
      static_assert(sizeof(T) == 0, "an Encounter field of a type the proto conversion does not know");
  });
  return out;
}

}  // namespace kessler::server
