#include "server/api_server.hpp"

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>

#include <chrono>
#include <stdexcept>

#include "kessler/v1/service.grpc.pb.h"
#include "server/run_manager.hpp"

namespace kessler::server {
namespace {

grpc::Status to_status(const ServiceError& e) {
  switch (e.code) {
    case ServiceError::Code::kInvalidArgument:
      return {grpc::StatusCode::INVALID_ARGUMENT, e.what()};
    case ServiceError::Code::kNotFound:
      return {grpc::StatusCode::NOT_FOUND, e.what()};
    case ServiceError::Code::kFailedPrecondition:
      return {grpc::StatusCode::FAILED_PRECONDITION, e.what()};
    case ServiceError::Code::kResourceExhausted:
      return {grpc::StatusCode::RESOURCE_EXHAUSTED, e.what()};
    case ServiceError::Code::kUnavailable:
      return {grpc::StatusCode::UNAVAILABLE, e.what()};
    default:
      return {grpc::StatusCode::INTERNAL, e.what()};
  }
}

// Every handler: run `body`, turn refusals into their status and anything else into INTERNAL.
template <typename Body>
grpc::Status guarded(grpc::ServerContext* context, Body&& body) {
  try {
    body();
    return grpc::Status::OK;
  } catch (const ServiceError& e) {
    if (!e.field_path.empty()) context->AddTrailingMetadata("kessler-field-path", e.field_path);
    return to_status(e);
  } catch (const std::exception& e) {
    return {grpc::StatusCode::INTERNAL, std::string("internal error: ") + e.what()};
  }
}

class Service final : public v1::KesslerService::Service {
 public:
  explicit Service(RunManager& manager) : m_(manager) {}

  grpc::Status SubmitRun(grpc::ServerContext* c, const v1::SubmitRunRequest* r, v1::Run* out) override {
    return guarded(c, [&] { *out = m_.submit(*r); });
  }
  grpc::Status GetRun(grpc::ServerContext* c, const v1::GetRunRequest* r, v1::Run* out) override {
    return guarded(c, [&] { *out = m_.get(r->run_id()); });
  }
  grpc::Status ListRuns(grpc::ServerContext* c, const v1::ListRunsRequest* r,
                        v1::ListRunsResponse* out) override {
    return guarded(c, [&] { *out = m_.list(*r); });
  }
  grpc::Status CancelRun(grpc::ServerContext* c, const v1::CancelRunRequest* r, v1::Run* out) override {
    return guarded(c, [&] { *out = m_.cancel(r->run_id()); });
  }
  grpc::Status DeleteRun(grpc::ServerContext* c, const v1::DeleteRunRequest* r,
                         v1::DeleteRunResponse*) override {
    return guarded(c, [&] { m_.remove(r->run_id()); });
  }
  grpc::Status WatchRun(grpc::ServerContext* c, const v1::WatchRunRequest* r,
                        grpc::ServerWriter<v1::RunEvent>* writer) override {
    return guarded(c, [&] {
      // Headers first: a stream whose first message carries a buffer hint would hold them back with it,
      // and the client would wait for both.
      writer->SendInitialMetadata();
      m_.watch(
          *r,
          [&](const v1::RunEvent& e, bool more) {
            return writer->Write(e, more ? grpc::WriteOptions().set_buffer_hint() : grpc::WriteOptions());
          },
          [&] { return c->IsCancelled(); });
    });
  }
  grpc::Status ListConjunctions(grpc::ServerContext* c, const v1::ListConjunctionsRequest* r,
                                v1::ListConjunctionsResponse* out) override {
    return guarded(c, [&] { *out = m_.conjunctions(*r); });
  }
  grpc::Status GetRunStats(grpc::ServerContext* c, const v1::GetRunStatsRequest* r,
                           v1::RunStats* out) override {
    return guarded(c, [&] { *out = m_.stats(*r); });
  }
  grpc::Status ListFragments(grpc::ServerContext* c, const v1::ListFragmentsRequest* r,
                             v1::ListFragmentsResponse* out) override {
    return guarded(c, [&] { *out = m_.fragments(*r); });
  }
  grpc::Status ListSnapshots(grpc::ServerContext* c, const v1::ListSnapshotsRequest* r,
                             v1::ListSnapshotsResponse* out) override {
    return guarded(c, [&] { *out = m_.list_snapshots(*r); });
  }
  grpc::Status GetSnapshot(grpc::ServerContext* c, const v1::GetSnapshotRequest* r,
                           v1::GetSnapshotResponse* out) override {
    return guarded(c, [&] { *out = m_.get_snapshot(*r); });
  }
  grpc::Status SubmitEnsemble(grpc::ServerContext* c, const v1::SubmitEnsembleRequest* r,
                              v1::EnsembleReport* out) override {
    return guarded(c, [&] { *out = m_.submit_ensemble(*r); });
  }
  grpc::Status GetEnsemble(grpc::ServerContext* c, const v1::GetEnsembleRequest* r,
                           v1::EnsembleReport* out) override {
    return guarded(c, [&] { *out = m_.get_ensemble(*r); });
  }
  grpc::Status ListEnsembles(grpc::ServerContext* c, const v1::ListEnsemblesRequest* r,
                             v1::ListEnsemblesResponse* out) override {
    return guarded(c, [&] { *out = m_.list_ensembles(*r); });
  }
  grpc::Status CancelEnsemble(grpc::ServerContext* c, const v1::CancelEnsembleRequest* r,
                              v1::EnsembleReport* out) override {
    return guarded(c, [&] { *out = m_.cancel_ensemble(r->ensemble_id()); });
  }

 private:
  RunManager& m_;
};

}  // namespace

struct ApiServer::Impl {
  explicit Impl(RunManager& manager) : service(manager) {}
  Service service;
  std::unique_ptr<grpc::Server> server;
  int port = 0;
};

ApiServer::ApiServer(RunManager& manager, const std::string& address, std::size_t max_message_bytes)
    : impl_(std::make_unique<Impl>(manager)) {
  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  builder.AddListeningPort(address, grpc::InsecureServerCredentials(), &impl_->port);
  builder.SetMaxReceiveMessageSize(static_cast<int>(max_message_bytes));
  builder.SetMaxSendMessageSize(static_cast<int>(max_message_bytes));
  builder.RegisterService(&impl_->service);
  impl_->server = builder.BuildAndStart();
  if (!impl_->server || impl_->port == 0) throw std::runtime_error("cannot listen on " + address);
  // The whole server ("") and the API by name, so probes that name the service get an answer too.
  impl_->server->GetHealthCheckService()->SetServingStatus(v1::KesslerService::service_full_name(), true);
  impl_->server->GetHealthCheckService()->SetServingStatus(true);
}

ApiServer::~ApiServer() {
  shutdown(1.0);
}

int ApiServer::port() const {
  return impl_->port;
}

void ApiServer::shutdown(double grace_s) {
  if (!impl_->server) return;
  impl_->server->GetHealthCheckService()->SetServingStatus(false);
  impl_->server->Shutdown(std::chrono::system_clock::now() +
                          std::chrono::milliseconds(static_cast<long>(grace_s * 1000)));
}

void ApiServer::wait() {
  if (impl_->server) impl_->server->Wait();
}

}  // namespace kessler::server
