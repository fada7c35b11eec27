// Shared by the dashboard's files: request parameters, errors as JSON, and the route tables.
#pragma once

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>

namespace kessler::server {
class RunManager;
}

namespace kessler::server::http {

// A request parameter the dashboard refuses: HTTP 400 with {"error", "parameter"}.
struct BadParameter : std::runtime_error {
  BadParameter(std::string name, const std::string& reason)
      : std::runtime_error(name + ": " + reason), parameter(std::move(name)) {}
  std::string parameter;
};

// Query parameters, checked: unknown names and malformed values are BadParameter.
class Params {
 public:
  Params(const httplib::Request& request, const std::set<std::string>& allowed);
  std::optional<std::string> text(const std::string& name) const;
  std::optional<double> number(const std::string& name) const;
  // An integer within [min, max].
  std::optional<std::int64_t> integer(const std::string& name, std::int64_t min, std::int64_t max) const;
  // "true"/"1" or "false"/"0"; absent: false.
  bool flag(const std::string& name) const;

 private:
  const httplib::Request& request_;
};

// The id in a route's first capture (\d+), as a positive int64; BadParameter(name) when out of range.
std::int64_t path_id(const httplib::Request& request, const std::string& name);

void send_json(httplib::Response& response, const nlohmann::json& body, int status = 200);
void send_error(httplib::Response& response, int status, const std::string& message,
                const std::string& parameter = "");

// Runs `body`, turning BadParameter, ServiceError and anything else into their HTTP answers.
void guarded(httplib::Response& response, const std::function<void()>& body);

// Page sizes: JSON listings at most kMaxPageSize items, a CSV download at most kMaxCsvRows rows.
inline constexpr std::int64_t kDefaultPageSize = 100;
inline constexpr std::int64_t kMaxPageSize = 1000;
inline constexpr std::int64_t kMaxCsvRows = 100000;

// Route tables (http_api.cpp, http_pages.cpp).
void add_api_routes(httplib::Server& server, RunManager& manager);
void add_page_routes(httplib::Server& server);

}  // namespace kessler::server::http
