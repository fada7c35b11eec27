// Checks of a request's own fields before any work or allocation: page tokens and sizes, numbers
// (NaN and infinities refused everywhere), enum numbers, the size of what GetRunStats would build.
// Each throws ServiceError kInvalidArgument naming the field; messages quote at most a short prefix
// of bad input.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "kessler/v1/service.pb.h"

namespace kessler::server {

// GetRunStats and GetEnsemble: at most this many kappa thresholds; a stats answer at most this many
// time bins, and bins x kappas at most kMaxStatsCells (about 16 bytes each).
inline constexpr std::size_t kMaxKappas = 64;
inline constexpr double kMaxStatsBins = 100000;
inline constexpr double kMaxStatsCells = 1000000;
// A request id (SubmitRun, SubmitEnsemble): at most this many printable ASCII characters.
inline constexpr std::size_t kMaxRequestIdLength = 128;
// Status messages are cut to this many bytes (a quoted 1 MB field would not fit in the trailers).
inline constexpr std::size_t kMaxStatusMessage = 1024;

// `text` quoted whole when short, else its first characters and how many more.
std::string short_quote(std::string_view text, std::size_t keep = 40);
// `message` cut to kMaxStatusMessage bytes with a note of what was left out.
std::string capped_message(const std::string& message);

void validate(const v1::SubmitRunRequest& request);
void validate(const v1::SubmitEnsembleRequest& request);
void validate(const v1::ListRunsRequest& request);
void validate(const v1::ListConjunctionsRequest& request);
void validate(const v1::GetRunStatsRequest& request);
void validate(const v1::ListFragmentsRequest& request);
void validate(const v1::WatchRunRequest& request);
void validate(const v1::GetEnsembleRequest& request);
void validate(const v1::ListEnsemblesRequest& request);
// The number of time bins a stats answer for a run of `run_length_s` would have, refused (with the
// kappas' count) when above the bounds.
void check_stats_size(double run_length_s, double time_bin_s, std::size_t kappas);

// A page token: empty, or the decimal digits of a previous page's token (no sign, point or suffix).
void check_page_token(const std::string& token, const char* field = "page_token");
void check_request_id(const std::string& id);
// Every double and float field of `message` (nested ones too) finite, else kInvalidArgument with the
// path of the first that is not (prefix "" for a scenario: paths as validate_scenario's).
void check_finite_numbers(const google::protobuf::Message& message, const std::string& prefix);

}  // namespace kessler::server
