// Request parameters and error answers of the dashboard.
#include <google/protobuf/util/json_util.h>

#include <cmath>
#include <cstdlib>

#include "server/run_manager.hpp"
// (after run_manager.hpp: see http_server.cpp)
#include "server/http/http_internal.hpp"

namespace kessler::server::http {

Params::Params(const httplib::Request& request, const std::set<std::string>& allowed) : request_(request) {
  for (const auto& [name, value] : request.params)
    if (!allowed.count(name)) throw BadParameter(name, "unknown parameter");
}

std::optional<std::string> Params::text(const std::string& name) const {
  if (!request_.has_param(name)) return std::nullopt;
  return request_.get_param_value(name);
}

std::optional<double> Params::number(const std::string& name) const {
  auto t = text(name);
  if (!t) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(t->c_str(), &end);
  if (t->empty() || *end != '\0' || !std::isfinite(v))
    throw BadParameter(name, "must be a number, got '" + *t + "'");
  return v;
}

std::optional<std::int64_t> Params::integer(const std::string& name, std::int64_t min,
                                            std::int64_t max) const {
  auto t = text(name);
  if (!t) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(t->c_str(), &end, 10);
  if (t->empty() || *end != '\0' || errno == ERANGE || v < min || v > max)
    throw BadParameter(name, "must be an integer " + std::to_string(min) + ".." + std::to_string(max) +
                                 ", got '" + *t + "'");
  return v;
}

bool Params::flag(const std::string& name) const {
  auto t = text(name);
  if (!t) return false;
  if (*t == "true" || *t == "1") return true;
  if (*t == "false" || *t == "0") return false;
  throw BadParameter(name, "must be true or false, got '" + *t + "'");
}

std::int64_t path_id(const httplib::Request& request, const std::string& name) {
  const std::string text = request.matches[1];
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || v <= 0)
    throw BadParameter(name, "must be a positive integer, got '" + text + "'");
  return v;
}

void send_json(httplib::Response& response, const nlohmann::json& body, int status) {
  response.status = status;
  response.set_content(body.dump(), "application/json");
}

void send_error(httplib::Response& response, int status, const std::string& message,
                const std::string& parameter) {
  nlohmann::json body = {{"error", message}};
  if (!parameter.empty()) body["parameter"] = parameter;
  send_json(response, body, status);
}

void guarded(httplib::Response& response, const std::function<void()>& body) {
  try {
    body();
  } catch (const BadParameter& e) {
    send_error(response, 400, e.what(), e.parameter);
  } catch (const ServiceError& e) {
    using Code = ServiceError::Code;
    const int status = e.code == Code::kInvalidArgument      ? 400
                       : e.code == Code::kNotFound           ? 404
                       : e.code == Code::kFailedPrecondition ? 409
                       : e.code == Code::kResourceExhausted  ? 429
                       : e.code == Code::kUnavailable        ? 503
                                                             : 500;
    send_error(response, status, e.what(), e.field_path);
  } catch (const std::exception& e) {
    send_error(response, 500, std::string("internal error: ") + e.what());
  }
}

}  // namespace kessler::server::http
