// The web dashboard of kesslerd (--http HOST:PORT, off by default): HTML pages for the runs and
// ensembles list and a run's page (live progress by polling, conjunctions, figures), over a small
// JSON API under /api/. It reads through the RunManager, as the gRPC API does, with no path of its own
// to the store. The charting scripts are compiled in (web/), so nothing is fetched at run time.
//
// Authentication: every request passes through authorize() in http_server.cpp before routing; it
// admits all requests today. The gRPC API's authentication belongs there when it exists.
#pragma once

#include <memory>
#include <string>

namespace kessler::server {

class RunManager;

class HttpServer {
 public:
  // Listens on `address` ("host:port"; port 0 picks a free one) and serves on its own threads.
  // Throws std::runtime_error when the address is malformed or cannot be bound.
  HttpServer(RunManager& manager, const std::string& address);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  int port() const;
  // Stops accepting and waits for the serving thread.
  void shutdown();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace kessler::server
