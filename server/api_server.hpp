// The gRPC face of the daemon: KesslerService over a RunManager, plus the standard health service
// and server reflection. The only part of the server that sees gRPC.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

namespace kessler::server {

class RunManager;

class ApiServer {
 public:
  // Listens on `address` ("host:port"; port 0 picks a free one). Requests above max_message_bytes are
  // refused with RESOURCE_EXHAUSTED. Throws std::runtime_error when it cannot listen.
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
