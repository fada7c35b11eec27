// The dashboard's server: cpp-httplib on its own thread, one place for authentication (authorize),
// JSON errors for everything refused, 404 for unknown paths.
#include "server/http/http_server.hpp"

#include <cstdlib>
#include <stdexcept>
#include <thread>

// Eigen (through run_manager.hpp) before httplib.h: resolv.h's _res macro breaks Eigen's headers.
#include "server/run_manager.hpp"
// (keep this order)
#include "server/http/http_internal.hpp"

namespace kessler::server {
namespace {

// The one gate every request passes before routing. Returns false after filling `response` with the
// refusal (e.g. 401 with a JSON error). Admits everything: the daemon has no authentication yet; when
// the gRPC API gets tokens, check the same token here (e.g. an Authorization: Bearer header).
bool authorize(const httplib::Request& /*request*/, httplib::Response& /*response*/) {
  return true;
}

std::pair<std::string, int> split_address(const std::string& address) {
  const auto colon = address.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == address.size())
    throw std::runtime_error("--http needs HOST:PORT, got '" + address + "'");
  char* end = nullptr;
  const long port = std::strtol(address.c_str() + colon + 1, &end, 10);
  if (*end != '\0' || port < 0 || port > 65535)
    throw std::runtime_error("--http: port must be 0..65535, got '" + address.substr(colon + 1) + "'");
  return {address.substr(0, colon), static_cast<int>(port)};
}

}  // namespace

struct HttpServer::Impl {
  httplib::Server server;
  std::thread thread;
  int port = 0;
};

HttpServer::HttpServer(RunManager& manager, const std::string& address) : impl_(std::make_unique<Impl>()) {
  auto [host, port] = split_address(address);
  httplib::Server& s = impl_->server;
  // Requests carry their parameters in the query; a body is never needed.
  s.set_payload_max_length(std::size_t{64} * 1024);
  s.set_pre_routing_handler([](const httplib::Request& request, httplib::Response& response) {
    return authorize(request, response) ? httplib::Server::HandlerResponse::Unhandled
                                        : httplib::Server::HandlerResponse::Handled;
  });
  http::add_api_routes(s, manager);
  http::add_page_routes(s);
  // Called for every answer >= 400: those without a body yet are unknown paths or methods.
  s.set_error_handler(
      httplib::Server::HandlerWithResponse([](const httplib::Request& request, httplib::Response& response) {
        if (response.body.empty()) {
          if (response.status == 404)
            http::send_error(response, 404, "no such path: " + request.path);
          else
            http::send_error(response, response.status, "request refused");
        }
        return httplib::Server::HandlerResponse::Handled;
      }));
  s.set_exception_handler(
      [](const httplib::Request&, httplib::Response& response, const std::exception_ptr&) {
        http::send_error(response, 500, "internal error");
      });
  if (port == 0) {
    impl_->port = s.bind_to_any_port(host);
    if (impl_->port <= 0) throw std::runtime_error("--http: cannot listen on " + address);
  } else {
    if (!s.bind_to_port(host, port)) throw std::runtime_error("--http: cannot listen on " + address);
    impl_->port = port;
  }
  impl_->thread = std::thread([this] { impl_->server.listen_after_bind(); });
}

HttpServer::~HttpServer() {
  shutdown();
}

int HttpServer::port() const {
  return impl_->port;
}

void HttpServer::shutdown() {
  impl_->server.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

}  // namespace kessler::server
