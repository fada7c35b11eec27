// The core's results in wire form: what a run reports (summary, progress, encounters, breakups,
// lifecycle events, the ingest of its catalog), converted once for the store, the event hub and the API.
#pragma once

#include <vector>

#include "core/catalog/ingest.hpp"
#include "core/simulation/events.hpp"
#include "core/simulation/simulation.hpp"
#include "kessler/v1/service.pb.h"
#include "server/store.hpp"

namespace kessler::server {

v1::RunSummary to_proto(const RunSummary& summary);
v1::Encounter to_proto(const Encounter& encounter);
v1::Progress to_proto(const Progress& progress);
v1::Lifecycle to_proto(const LifecycleReport& event);
// The breakup without its fragments (the event), and its fragments as the store keeps them.
v1::Breakup to_proto(const BreakupReport& breakup);
std::vector<StoredFragment> fragments_of(const BreakupReport& breakup);
// What ingesting the catalog kept and dropped, by reason.
v1::IngestReport ingest_proto(const IngestReport& report);

}  // namespace kessler::server
