// The CLI's connection to kesslerd: one call per RPC, errors as plain values. The only part of the CLI
// that sees gRPC (its headers stay in remote_client.cpp).
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "kessler/v1/service.pb.h"

namespace kessler::cli {

// --server, else $KESSLER_SERVER, else 127.0.0.1:50051.
std::string server_address(const std::string& flag_value);

// How every RemoteClient of the process connects: the bearer token (--token, else $KESSLER_TOKEN) and
// TLS (--tls-ca FILE, else $KESSLER_TLS_CA: the CA that signed the daemon's certificate; with
// --tls-cert/--tls-key, else $KESSLER_TLS_CERT/$KESSLER_TLS_KEY, a client certificate for mutual TLS).
// No CA: plaintext.
struct ConnectionOptions {
  std::string token;
  std::string tls_ca;
  std::string tls_cert;
  std::string tls_key;
};
// The flags' values (empty: not given) with the environment filled in. False with `error` set when a
// file cannot be read.
bool set_connection_options(const ConnectionOptions& flags, std::string& error);
const ConnectionOptions& connection_options();

// A fresh request id for a submission: 32 hex digits from std::random_device.
std::string new_request_id();

struct CallResult {
  bool ok = true;
  int code = 0;           // gRPC status code
  std::string code_name;  // "INVALID_ARGUMENT", ...
  std::string message;
  std::string field_path;  // for INVALID_ARGUMENT, when the daemon named a field
  std::string warning;     // the daemon's "kessler-warning" (e.g. serving a public address insecurely)
  bool unavailable() const { return code == 14; }
  // Worth sending again with the same request id: the daemon was away or the answer did not come.
  bool retryable() const { return code == 14 || code == 4; }
  // Exit code: 2 for a refused input (INVALID_ARGUMENT), 1 for everything else.
  int exit_code() const;
  std::string describe() const;  // "INVALID_ARGUMENT: dt_s: must be positive"
};

class RemoteClient {
 public:
  explicit RemoteClient(const std::string& address);
  ~RemoteClient();

  const std::string& address() const { return address_; }
  CallResult submit(const v1::SubmitRunRequest& request, v1::Run& out);
  CallResult get(std::int64_t run_id, v1::Run& out);
  CallResult list(const v1::ListRunsRequest& request, v1::ListRunsResponse& out);
  CallResult cancel(std::int64_t run_id, v1::Run& out);
  CallResult resume(std::int64_t run_id, v1::Run& out);
  CallResult remove(std::int64_t run_id);
  CallResult conjunctions(const v1::ListConjunctionsRequest& request, v1::ListConjunctionsResponse& out);
  CallResult conjunction_cdm(const v1::GetConjunctionCdmRequest& request, v1::ConjunctionCdm& out);
  CallResult stats(const v1::GetRunStatsRequest& request, v1::RunStats& out);
  CallResult fragments(const v1::ListFragmentsRequest& request, v1::ListFragmentsResponse& out);
  CallResult snapshots(const v1::ListSnapshotsRequest& request, v1::ListSnapshotsResponse& out);
  CallResult snapshot(const v1::GetSnapshotRequest& request, v1::GetSnapshotResponse& out);
  CallResult submit_ensemble(const v1::SubmitEnsembleRequest& request, v1::EnsembleReport& out);
  CallResult get_ensemble(const v1::GetEnsembleRequest& request, v1::EnsembleReport& out);
  CallResult list_ensembles(const v1::ListEnsemblesRequest& request, v1::ListEnsemblesResponse& out);
  CallResult cancel_ensemble(std::int64_t ensemble_id, v1::EnsembleReport& out);
  CallResult figures(const v1::GetFiguresRequest& request, v1::GetFiguresResponse& out);
  // The standard health check (grpc.health.v1.Health/Check) of `service` ("" for the whole server):
  // `status` gets SERVING, NOT_SERVING, SERVICE_UNKNOWN or UNKNOWN. A service the daemon does not
  // know is NOT_FOUND.
  CallResult health(const std::string& service, double timeout_s, std::string& status);
  // Calls on_event for each event until the stream ends; on_event returning false ends it early.
  CallResult watch(const v1::WatchRunRequest& request,
                   const std::function<bool(const v1::RunEvent&)>& on_event);

 private:
  struct Impl;
  std::string address_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace kessler::cli
