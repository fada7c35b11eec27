// The gRPC face of the daemon: KesslerService over a RunManager, plus the standard health service
// and server reflection. The only part of the server that sees gRPC.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "server/auth.hpp"
#include "server/limits.hpp"
#include "server/transport.hpp"

namespace kessler::server {

class RunManager;

struct ApiOptions {
  // Requests above this are refused with RESOURCE_EXHAUSTED; answers are bounded by it too (GetRun
  // leaves inline data out, so a run accepted can always be shown).
  std::size_t max_message_bytes = std::size_t{64} << 20;
  std::optional<TlsMaterial> tls;  // none: plaintext
  // Tokens and roles; null: every call is the anonymous admin.
  std::shared_ptr<const Authenticator> auth;
  LimitOptions limits;
  // Sent as initial metadata "kessler-warning" on every answer (health checks too) when not empty.
  std::string warning;
};

class ApiServer {
 public:
  // Listens on `address` ("host:port"; port 0 picks a free one). Throws std::runtime_error when it
  // cannot listen.
  ApiServer(RunManager& manager, const std::string& address, const ApiOptions& options);
  // Plaintext, no tokens.
  ApiServer(RunManager& manager, const std::string& address, std::size_t max_message_bytes);
  ~ApiServer();

  int port() const;
  // Stops accepting calls; calls still running get `grace_s` seconds, then are cancelled.
  void shutdown(double grace_s);
  // Blocks until shutdown.
  void wait();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace kessler::server
