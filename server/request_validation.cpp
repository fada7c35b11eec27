#include "server/request_validation.hpp"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/reflection.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "server/run_manager.hpp"

namespace kessler::server {
namespace {

using Code = ServiceError::Code;

[[noreturn]] void refuse(const std::string& field, const std::string& reason) {
  throw ServiceError(Code::kInvalidArgument, field + ": " + reason, field);
}

void check_page_size(int page_size) {
  if (page_size < 0) refuse("page_size", "must be >= 0 (0: the default), got " + std::to_string(page_size));
}

void check_number(double v, const std::string& field, bool positive) {
  if (!std::isfinite(v)) refuse(field, "must be a finite number");
  if (positive ? v <= 0 : v < 0) refuse(field, positive ? "must be > 0" : "must be >= 0");
}

template <typename Kappas>
void check_kappas(const Kappas& kappas, const std::string& field) {
  if (static_cast<std::size_t>(kappas.size()) > kMaxKappas)
    refuse(field,
           "at most " + std::to_string(kMaxKappas) + " thresholds, got " + std::to_string(kappas.size()));
  for (int i = 0; i < kappas.size(); ++i)
    check_number(kappas[i], field + "[" + std::to_string(i) + "]", true);
}

}  // namespace

std::string short_quote(std::string_view text, std::size_t keep) {
  std::string out;
  const std::size_t n = std::min(text.size(), keep);
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    out += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  }
  out = "'" + out + "'";
  if (text.size() > keep) out += " (and " + std::to_string(text.size() - keep) + " bytes more)";
  return out;
}

std::string capped_message(const std::string& message) {
  if (message.size() <= kMaxStatusMessage) return message;
  return message.substr(0, kMaxStatusMessage) + "... (" + std::to_string(message.size() - kMaxStatusMessage) +
         " bytes more)";
}

void check_page_token(const std::string& token, const char* field) {
  if (token.empty()) return;
  if (token.size() > 18 || token.find_first_not_of("0123456789") != std::string::npos)
    refuse(field, "not a token from a previous page: " + short_quote(token));
}

void check_request_id(const std::string& id) {
  if (id.size() > kMaxRequestIdLength)
    refuse("request_id", "at most " + std::to_string(kMaxRequestIdLength) + " characters, got " +
                             std::to_string(id.size()));
  for (char c : id)
    if (c < 0x21 || c > 0x7e) refuse("request_id", "printable ASCII without spaces only: " + short_quote(id));
}

void check_finite_numbers(const google::protobuf::Message& message, const std::string& prefix) {
  const google::protobuf::Reflection* reflection = message.GetReflection();
  std::vector<const google::protobuf::FieldDescriptor*> fields;
  reflection->ListFields(message, &fields);
  using FD = google::protobuf::FieldDescriptor;
  for (const FD* field : fields) {
    const std::string path = prefix.empty() ? field->name() : prefix + "." + field->name();
    const int n = field->is_repeated() ? reflection->FieldSize(message, field) : 1;
    for (int i = 0; i < n; ++i) {
      const std::string at = field->is_repeated() ? path + "[" + std::to_string(i) + "]" : path;
      const bool r = field->is_repeated();
      switch (field->cpp_type()) {
        case FD::CPPTYPE_DOUBLE:
          if (!std::isfinite(r ? reflection->GetRepeatedDouble(message, field, i)
                               : reflection->GetDouble(message, field)))
            refuse(at, "must be a finite number");
          break;
        case FD::CPPTYPE_FLOAT:
          if (!std::isfinite(r ? reflection->GetRepeatedFloat(message, field, i)
                               : reflection->GetFloat(message, field)))
            refuse(at, "must be a finite number");
          break;
        case FD::CPPTYPE_MESSAGE:
          check_finite_numbers(
              r ? reflection->GetRepeatedMessage(message, field, i) : reflection->GetMessage(message, field),
              at);
          break;
        default:
          break;
      }
    }
  }
}

void validate(const v1::SubmitRunRequest& request) {
  check_request_id(request.request_id());
}

void validate(const v1::SubmitEnsembleRequest& request) {
  check_request_id(request.request_id());
}

void validate(const v1::ListRunsRequest& request) {
  check_page_size(request.page_size());
  check_page_token(request.page_token());
  for (int i = 0; i < request.states_size(); ++i)
    if (!v1::RunState_IsValid(request.states(i)) || request.states(i) == v1::RUN_STATE_UNSPECIFIED)
      refuse("states[" + std::to_string(i) + "]", "not a run state: " + std::to_string(request.states(i)));
}

void validate(const v1::ListConjunctionsRequest& request) {
  check_page_size(request.page_size());
  check_page_token(request.page_token());
  if (request.has_kappa_min()) check_number(request.kappa_min(), "kappa_min", false);
  if (request.has_kappa_max()) check_number(request.kappa_max(), "kappa_max", false);
  if (request.has_time_min_s() && !std::isfinite(request.time_min_s()))
    refuse("time_min_s", "must be a finite number");
  if (request.has_time_max_s() && !std::isfinite(request.time_max_s()))
    refuse("time_max_s", "must be a finite number");
}

void validate(const v1::GetRunStatsRequest& request) {
  check_number(request.time_bin_s(), "time_bin_s", false);
  check_kappas(request.kappas(), "kappas");
}

void check_stats_size(double run_length_s, double time_bin_s, std::size_t kappas) {
  if (time_bin_s <= 0) return;  // the default: 24 bins
  const double bins = std::ceil(run_length_s / time_bin_s);
  const double cells = bins * static_cast<double>(std::max<std::size_t>(kappas, 4));
  if (bins > kMaxStatsBins || cells > kMaxStatsCells)
    refuse("time_bin_s", "too small: " + std::to_string(static_cast<std::uint64_t>(std::min(bins, 1e18))) +
                             " bins of the run (at most " + std::to_string(static_cast<int>(kMaxStatsBins)) +
                             ", and bins x kappas at most " +
                             std::to_string(static_cast<int>(kMaxStatsCells)) + ")");
}

void validate(const v1::ListFragmentsRequest& request) {
  check_page_size(request.page_size());
  check_page_token(request.page_token());
}

void validate(const v1::WatchRunRequest& request) {
  if (request.after_seq() > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
    refuse("after_seq", "above 2^63 - 1, the largest sequence number");
}

void validate(const v1::GetEnsembleRequest& request) {
  check_kappas(request.kappas(), "kappas");
}

void validate(const v1::ListEnsemblesRequest& request) {
  check_page_size(request.page_size());
  check_page_token(request.page_token());
}

}  // namespace kessler::server
