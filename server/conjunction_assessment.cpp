#include "server/conjunction_assessment.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "core/assessment/assess_encounter.hpp"
#include "core/assessment/cdm_export.hpp"
#include "core/assessment/covariance_model.hpp"
#include "core/scenario/run_builder.hpp"
#include "server/run_manager.hpp"

namespace kessler::server {

namespace {

Eigen::Vector3d vector_of(const v1::Vector3& v) {
  return {v.x(), v.y(), v.z()};
}

Encounter core_encounter(const v1::Encounter& e) {
  Encounter out;
  out.id1 = e.id1();
  out.id2 = e.id2();
  out.tca_s = e.tca_s();
  out.miss_distance_m = e.miss_distance_m();
  out.relative_speed_m_s = e.relative_speed_m_s();
  out.kappa = e.kappa();
  out.kind = static_cast<EncounterKind>(e.kind());
  out.r1_m = vector_of(e.r1_m());
  out.v1_m_s = vector_of(e.v1_m_s());
  out.r2_m = vector_of(e.r2_m());
  out.v2_m_s = vector_of(e.v2_m_s());
  return out;
}

// The model's inputs: the type from the catalog name; element sets taken as current at the scenario
// epoch (the run does not keep their ages), so the age at TCA is tca_s.
assessment::ObjectContext context_of(const std::string& name) {
  return {assessment::object_type_from_name(name), 0.0};
}

enum class SortKey { kSeq, kPc, kPcMax, kMiss };

SortKey sort_key_of(const std::string& sort) {
  if (sort.empty() || sort == "seq") return SortKey::kSeq;
  if (sort == "pc") return SortKey::kPc;
  if (sort == "pc_max") return SortKey::kPcMax;
  if (sort == "miss") return SortKey::kMiss;
  throw std::invalid_argument("sort: must be seq, pc, pc_max or miss, got '" + sort + "'");
}

// Largest first, events without a value last, then by sequence number.
bool descending(bool has_a, double a, bool has_b, double b, std::uint64_t seq_a, std::uint64_t seq_b) {
  if (has_a != has_b) return has_a;
  if (has_a && a != b) return a > b;
  return seq_a < seq_b;
}

void sort_rows(std::vector<v1::Encounter>& rows, SortKey key) {
  auto less = [key](const v1::Encounter& a, const v1::Encounter& b) {
    switch (key) {
      case SortKey::kPc:
        return descending(a.has_pc(), a.pc(), b.has_pc(), b.pc(), a.seq(), b.seq());
      case SortKey::kPcMax:
        return descending(a.has_pc_max(), a.pc_max(), b.has_pc_max(), b.pc_max(), a.seq(), b.seq());
      case SortKey::kMiss:
        if (a.miss_distance_m() != b.miss_distance_m()) return a.miss_distance_m() < b.miss_distance_m();
        return a.seq() < b.seq();
      case SortKey::kSeq:
        break;
    }
    return a.seq() < b.seq();
  };
  std::sort(rows.begin(), rows.end(), less);
}

}  // namespace

void fill_assessment(v1::Encounter& e) {
  const assessment::Assessment a =
      assessment::assess_encounter(core_encounter(e), context_of(e.name1()), context_of(e.name2()));
  e.clear_pc();
  e.clear_pc_max();
  if (a.pc_computed) e.set_pc(a.pc);
  if (std::isfinite(a.pc_max)) {
    e.set_pc_max(a.pc_max);
    e.set_pc_max_sigma_m(a.pc_max_sigma_m);
  }
  e.set_pc_method(std::string(assessment::method_name(a.method)));
  e.set_covariance_source(std::string(assessment::source_name(a.covariance_source)));
  e.set_short_encounter(a.short_encounter);
}

v1::ListConjunctionsResponse assessed_conjunctions(Store& store, const v1::ListConjunctionsRequest& request) {
  const SortKey key = sort_key_of(request.sort());
  if (key != SortKey::kSeq && !request.order_by().empty())
    throw std::invalid_argument("sort: give sort (by assessment) or order_by (by column), not both");
  if (request.has_pc_min() && !(request.pc_min() >= 0.0 && request.pc_min() <= 1.0))
    throw std::invalid_argument("pc_min: must be in [0, 1]");
  v1::ListConjunctionsResponse response;
  if (!request.has_pc_min() && key == SortKey::kSeq) {
    Page<v1::Encounter> page = store.list_conjunctions(request);
    for (auto& c : page.items) {
      fill_assessment(c);
      *response.add_conjunctions() = std::move(c);
    }
    response.set_next_page_token(page.next_token);
    response.set_total(page.total);
    return response;
  }
  std::int64_t offset = 0;
  if (!request.page_token().empty()) {
    try {
      offset = std::stoll(request.page_token());
    } catch (...) {
      throw std::invalid_argument("page_token: not a token from a previous page");
    }
  }
  // Every match, assessed, filtered and sorted; then the page.
  v1::ListConjunctionsRequest all = request;
  all.set_page_size(100000);
  all.clear_page_token();
  std::vector<v1::Encounter> rows;
  for (;;) {
    Page<v1::Encounter> page = store.list_conjunctions(all);
    for (auto& c : page.items) {
      fill_assessment(c);
      if (!request.has_pc_min() || (c.has_pc() && c.pc() >= request.pc_min())) rows.push_back(std::move(c));
    }
    if (page.next_token.empty()) break;
    all.set_page_token(page.next_token);
  }
  if (key != SortKey::kSeq) sort_rows(rows, key);  // else the store's order (seq, or order_by)
  const std::size_t page_size =
      static_cast<std::size_t>(request.page_size() <= 0 ? 1000 : std::min(request.page_size(), 100000));
  const std::size_t begin =
      std::min(rows.size(), static_cast<std::size_t>(std::max<std::int64_t>(offset, 0)));
  const std::size_t end = std::min(rows.size(), begin + page_size);
  for (std::size_t i = begin; i < end; ++i) *response.add_conjunctions() = std::move(rows[i]);
  if (end < rows.size()) response.set_next_page_token(std::to_string(end));
  response.set_total(rows.size());
  return response;
}

v1::ConjunctionCdm conjunction_cdm(const v1::Encounter& e, std::int64_t run_id, const UtcEpoch& start_epoch,
                                   const std::string& format) {
  const std::string kind = format.empty() ? "kvn" : format;
  if (kind != "kvn" && kind != "xml")
    throw std::invalid_argument("format: must be kvn or xml, got '" + format + "'");
  assessment::CdmExportOptions options;
  options.message_id = "KESSLER_RUN" + std::to_string(run_id) + "_SEQ" + std::to_string(e.seq());
  options.scenario_epoch = start_epoch;
  const double now_s =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  options.creation_date = UtcEpoch::from_calendar(1970, 1, 1, 0, 0, 0.0).plus_seconds(std::floor(now_s));
  const assessment::Cdm cdm =
      assessment::cdm_from_encounter(core_encounter(e), {e.id1(), e.name1(), context_of(e.name1())},
                                     {e.id2(), e.name2(), context_of(e.name2())}, options);
  v1::ConjunctionCdm out;
  out.set_seq(e.seq());
  out.set_format(kind);
  out.set_file_name("run" + std::to_string(run_id) + "_seq" + std::to_string(e.seq()) +
                    (kind == "xml" ? ".xml" : ".cdm"));
  out.set_text(kind == "xml" ? assessment::write_cdm_xml(cdm) : assessment::write_cdm_kvn(cdm));
  return out;
}

v1::ConjunctionCdm RunManager::conjunction_cdm(const v1::GetConjunctionCdmRequest& request) {
  const v1::Run run = get(request.run_id());  // NOT_FOUND
  const std::optional<v1::Encounter> encounter = store_.conjunction(request.run_id(), request.seq());
  if (!encounter)
    throw ServiceError(ServiceError::Code::kNotFound, "run " + std::to_string(request.run_id()) +
                                                          " has no conjunction with seq " +
                                                          std::to_string(request.seq()));
  try {
    return server::conjunction_cdm(*encounter, request.run_id(),
                                   to_simulation_config(run.scenario()).start_epoch, request.format());
  } catch (const std::invalid_argument& e) {
    throw ServiceError(ServiceError::Code::kInvalidArgument, e.what(), "format");
  }
}

}  // namespace kessler::server
