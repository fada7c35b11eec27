#include "server/api_server.hpp"

#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "kessler/v1/service.grpc.pb.h"
#include "server/request_validation.hpp"
#include "server/run_manager.hpp"

namespace kessler::server {
namespace {

grpc::Status to_status(const ServiceError& e) {
  const std::string message = capped_message(e.what());
  switch (e.code) {
    case ServiceError::Code::kInvalidArgument:
      return {grpc::StatusCode::INVALID_ARGUMENT, message};
    case ServiceError::Code::kNotFound:
      return {grpc::StatusCode::NOT_FOUND, message};
    case ServiceError::Code::kFailedPrecondition:
      return {grpc::StatusCode::FAILED_PRECONDITION, message};
    case ServiceError::Code::kResourceExhausted:
      return {grpc::StatusCode::RESOURCE_EXHAUSTED, message};
    case ServiceError::Code::kUnavailable:
      return {grpc::StatusCode::UNAVAILABLE, message};
    default:
      return {grpc::StatusCode::INTERNAL, message};
  }
}

// Every handler: who calls and whether its role allows the call, then `body(caller)`; refusals become
// their status (messages capped in length), anything else INTERNAL.
class Guard {
 public:
  Guard(std::shared_ptr<const Authenticator> auth, LimitOptions limits)
      : auth_(auth ? std::move(auth) : std::make_shared<const Authenticator>()), limits_(limits) {}
  Limits& limits() { return limits_; }

  template <typename Body>
  grpc::Status operator()(grpc::ServerContext* context, Role needed, Body&& body) {
    try {
      body(caller(context, needed));
      return grpc::Status::OK;
    } catch (const AccessError& e) {
      return {e.unauthenticated ? grpc::StatusCode::UNAUTHENTICATED : grpc::StatusCode::PERMISSION_DENIED,
              e.what()};
    } catch (const LimitError& e) {
      return {grpc::StatusCode::RESOURCE_EXHAUSTED, e.what()};
    } catch (const ServiceError& e) {
      if (!e.field_path.empty())
        context->AddTrailingMetadata("kessler-field-path", e.field_path.substr(0, kMaxFieldPath));
      return to_status(e);
    } catch (const std::exception& e) {
      return {grpc::StatusCode::INTERNAL, capped_message(std::string("internal error: ") + e.what())};
    }
  }

 private:
  static constexpr std::size_t kMaxFieldPath = 256;
  Caller caller(grpc::ServerContext* context, Role needed) const {
    const auto& metadata = context->client_metadata();
    auto it = metadata.find("authorization");
    std::optional<std::string_view> authorization;
    if (it != metadata.end()) authorization = std::string_view(it->second.data(), it->second.size());
    return admit_caller(*auth_, authorization, needed);
  }
  std::shared_ptr<const Authenticator> auth_;
  Limits limits_;
};

// Sends the daemon's warning (e.g. serving a public address without TLS) with every answer.
class WarningInterceptor final : public grpc::experimental::Interceptor {
 public:
  explicit WarningInterceptor(const std::string& warning) : warning_(warning) {}
  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(
            grpc::experimental::InterceptionHookPoints::PRE_SEND_INITIAL_METADATA))
      methods->GetSendInitialMetadata()->emplace("kessler-warning", warning_);
    methods->Proceed();
  }

 private:
  const std::string& warning_;
};

class WarningInterceptorFactory final : public grpc::experimental::ServerInterceptorFactoryInterface {
 public:
  explicit WarningInterceptorFactory(std::string warning) : warning_(std::move(warning)) {}
  grpc::experimental::Interceptor* CreateServerInterceptor(grpc::experimental::ServerRpcInfo*) override {
    return new WarningInterceptor(warning_);
  }

 private:
  std::string warning_;
};

class Service final : public v1::KesslerService::Service {
 public:
  Service(RunManager& manager, const ApiOptions& options)
      : m_(manager), guard_(options.auth, options.limits) {}

  grpc::Status SubmitRun(grpc::ServerContext* c, const v1::SubmitRunRequest* r, v1::Run* out) override {
    return guard_(c, Role::kSubmit, [&](const Caller& who) {
      validate(*r);
      guard_.limits().take_request(who);
      // A retry of a submission already made returns its run, whatever the limits say now.
      if (r->request_id().empty() || !m_.store().run_of_request(who.name, r->request_id()))
        guard_.limits().check_runs(who, m_.store().active_runs_of(who.name), 1);
      *out = m_.submit(*r, who.name);
    });
  }
  grpc::Status GetRun(grpc::ServerContext* c, const v1::GetRunRequest* r, v1::Run* out) override {
    return guard_(c, Role::kRead, [&](const Caller& who) {
      check_run_owner(who, r->run_id());
      *out = m_.get(*r);
    });
  }
  grpc::Status ListRuns(grpc::ServerContext* c, const v1::ListRunsRequest* r,
                        v1::ListRunsResponse* out) override {
    return guard_(c, Role::kRead, [&](const Caller& who) {
      validate(*r);
      *out = m_.list(*r, who.owns_only() ? &who.name : nullptr);
    });
  }
  grpc::Status CancelRun(grpc::ServerContext* c, const v1::CancelRunRequest* r, v1::Run* out) override {
    return guard_(c, Role::kSubmit, [&](const Caller& who) {
      check_run_owner(who, r->run_id());
      *out = m_.cancel(r->run_id());
    });
  }
  grpc::Status ResumeRun(grpc::ServerContext* c, const v1::ResumeRunRequest* r, v1::Run* out) override {
    return guard_(c, Role::kSubmit, [&](const Caller& who) {
      check_run_owner(who, r->run_id());
      guard_.limits().take_request(who);
      guard_.limits().check_runs(who, m_.store().active_runs_of(who.name), 1);
      *out = m_.resume(r->run_id());
    });
  }
  grpc::Status DeleteRun(grpc::ServerContext* c, const v1::DeleteRunRequest* r,
                         v1::DeleteRunResponse*) override {
    return guard_(c, Role::kSubmit, [&](const Caller& who) {
      check_run_owner(who, r->run_id());
      m_.remove(r->run_id());
    });
  }
  grpc::Status WatchRun(grpc::ServerContext* c, const v1::WatchRunRequest* r,
                        grpc::ServerWriter<v1::RunEvent>* writer) override {
    return guard_(c, Role::kRead, [&](const Caller& who) {
      validate(*r);
      check_run_owner(who, r->run_id());
      Limits::Watch slot(guard_.limits(), who);
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
    return guard_(c, Role::kRead, [&](const Caller& who) {
      validate(*r);
      check_run_owner(who, r->run_id());
      guard_.limits().take_request(who);
      *out = m_.conjunctions(*r);
    });
  }
  grpc::Status GetConjunctionCdm(grpc::ServerContext* c, const v1::GetConjunctionCdmRequest* r,
                                 v1::ConjunctionCdm* out) override {
    return guard_(c, Role::kRead, [&](const Caller& who) {
      check_run_owner(who, r->run_id());
      guard_.limits().take_request(who);
      *out = m_.conjunction_cdm(*r);
    });
  }
  grpc::Status GetRunStats(grpc::ServerContext* c, const v1::GetRunStatsRequest* r,
                           v1::RunStats* out) override {
    return guard_(c, Role::kRead, [&](const Caller& who) {
      validate(*r);
      check_run_owner(who, r->run_id());
      guard_.limits().take_request(who);
      *out = m_.stats(*r);
    });
  }
  grpc::Status ListFragments(grpc::ServerContext* c, const v1::ListFragmentsRequest* r,
                             v1::ListFragmentsResponse* out) override {
    return guard_(c, Role::kRead, [&](const Caller& who) {
      validate(*r);
      check_run_owner(who, r->run_id());
      guard_.limits().take_request(who);
      *out = m_.fragments(*r);
    });
  }
  grpc::Status ListSnapshots(grpc::ServerContext* c, const v1::ListSnapshotsRequest* r,
                             v1::ListSnapshotsResponse* out) override {
    return guard_(c, Role::kRead, [&](const Caller& who) {
      check_run_owner(who, r->run_id());
      *out = m_.list_snapshots(*r);
    });
  }
  grpc::Status GetSnapshot(grpc::ServerContext* c, const v1::GetSnapshotRequest* r,
                           v1::GetSnapshotResponse* out) override {
    return guard_(c, Role::kRead, [&](const Caller& who) {
      check_run_owner(who, r->run_id());
      guard_.limits().take_request(who);
      *out = m_.get_snapshot(*r);
    });
  }
  grpc::Status SubmitEnsemble(grpc::ServerContext* c, const v1::SubmitEnsembleRequest* r,
                              v1::EnsembleReport* out) override {
    return guard_(c, Role::kSubmit, [&](const Caller& who) {
      validate(*r);
      guard_.limits().take_request(who);
      if (r->request_id().empty() || !m_.store().ensemble_of_request(who.name, r->request_id()))
        guard_.limits().check_runs(who, m_.store().active_runs_of(who.name),
                                   std::max<std::uint64_t>(r->members(), 1));
      *out = m_.submit_ensemble(*r, who.name);
    });
  }
  grpc::Status GetEnsemble(grpc::ServerContext* c, const v1::GetEnsembleRequest* r,
                           v1::EnsembleReport* out) override {
    return guard_(c, Role::kRead, [&](const Caller& who) {
      validate(*r);
      check_ensemble_owner(who, r->ensemble_id());
      guard_.limits().take_request(who);
      *out = m_.get_ensemble(*r);
    });
  }
  grpc::Status ListEnsembles(grpc::ServerContext* c, const v1::ListEnsemblesRequest* r,
                             v1::ListEnsemblesResponse* out) override {
    return guard_(c, Role::kRead, [&](const Caller& who) {
      validate(*r);
      *out = m_.list_ensembles(*r, who.owns_only() ? &who.name : nullptr);
    });
  }
  grpc::Status CancelEnsemble(grpc::ServerContext* c, const v1::CancelEnsembleRequest* r,
                              v1::EnsembleReport* out) override {
    return guard_(c, Role::kSubmit, [&](const Caller& who) {
      check_ensemble_owner(who, r->ensemble_id());
      *out = m_.cancel_ensemble(r->ensemble_id());
    });
  }
  grpc::Status GetFigures(grpc::ServerContext* c, const v1::GetFiguresRequest* r,
                          v1::GetFiguresResponse* out) override {
    return guard_(c, Role::kRead, [&](const Caller& who) {
      if (r->has_ensemble_id())
        check_ensemble_owner(who, r->ensemble_id());
      else
        check_run_owner(who, r->run_id());
      for (const std::int64_t id : r->compare_run_ids()) check_run_owner(who, id);
      guard_.limits().take_request(who);
      *out = m_.figures(*r);
    });
  }

 private:
  // A submit token reaches only its own runs: another's is PERMISSION_DENIED.
  void check_run_owner(const Caller& who, std::int64_t run_id) {
    if (!who.owns_only()) return;
    auto owner = m_.store().run_submitter(run_id);
    if (!owner)
      throw ServiceError(ServiceError::Code::kNotFound, "run " + std::to_string(run_id) + " not found");
    if (*owner != who.name)
      throw AccessError(false, "run " + std::to_string(run_id) + " was submitted by another token; token '" +
                                   who.name + "' (role submit) reaches only its own runs");
  }
  void check_ensemble_owner(const Caller& who, std::int64_t ensemble_id) {
    if (!who.owns_only()) return;
    auto owner = m_.store().ensemble_submitter(ensemble_id);
    if (!owner)
      throw ServiceError(ServiceError::Code::kNotFound,
                         "ensemble " + std::to_string(ensemble_id) + " not found");
    if (*owner != who.name)
      throw AccessError(false, "ensemble " + std::to_string(ensemble_id) +
                                   " was submitted by another token; token '" + who.name +
                                   "' (role submit) reaches only its own ensembles");
  }

  RunManager& m_;
  Guard guard_;
};

}  // namespace

struct ApiServer::Impl {
  Impl(RunManager& m, const ApiOptions& options) : manager(m), service(m, options) {}
  RunManager& manager;
  Service service;
  std::unique_ptr<grpc::Server> server;
  int port = 0;
};

namespace {

std::shared_ptr<grpc::ServerCredentials> credentials_of(const std::optional<TlsMaterial>& tls) {
  if (!tls) return grpc::InsecureServerCredentials();
  grpc::SslServerCredentialsOptions ssl(tls->client_ca_pem.empty()
                                            ? GRPC_SSL_DONT_REQUEST_CLIENT_CERTIFICATE
                                            : GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY);
  ssl.pem_root_certs = tls->client_ca_pem;
  ssl.pem_key_cert_pairs.push_back({tls->key_pem, tls->cert_pem});
  return grpc::SslServerCredentials(ssl);
}

ApiOptions plaintext(std::size_t max_message_bytes) {
  ApiOptions options;
  options.max_message_bytes = max_message_bytes;
  return options;
}

}  // namespace

ApiServer::ApiServer(RunManager& manager, const std::string& address, std::size_t max_message_bytes)
    : ApiServer(manager, address, plaintext(max_message_bytes)) {}

ApiServer::ApiServer(RunManager& manager, const std::string& address, const ApiOptions& options)
    : impl_(std::make_unique<Impl>(manager, options)) {
  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  builder.AddListeningPort(address, credentials_of(options.tls), &impl_->port);
  // Deliberate bounds both ways: a request above them is refused before it is read whole, and no
  // answer can exceed what a request could bring (GetRun leaves inline data out).
  builder.SetMaxReceiveMessageSize(static_cast<int>(options.max_message_bytes));
  builder.SetMaxSendMessageSize(static_cast<int>(options.max_message_bytes));
  if (!options.warning.empty()) {
    std::vector<std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface>> interceptors;
    interceptors.push_back(std::make_unique<WarningInterceptorFactory>(options.warning));
    builder.experimental().SetInterceptorCreators(std::move(interceptors));
  }
  builder.RegisterService(&impl_->service);
  impl_->server = builder.BuildAndStart();
  if (!impl_->server || impl_->port == 0) throw std::runtime_error("cannot listen on " + address);
  // The whole server ("") and the API by name, so probes that name the service get an answer too.
  impl_->server->GetHealthCheckService()->SetServingStatus(v1::KesslerService::service_full_name(), true);
  impl_->server->GetHealthCheckService()->SetServingStatus(true);
  // The API is NOT_SERVING while the store cannot write (submissions are refused); "" stays SERVING,
  // as reads go on.
  grpc::Server* server = impl_->server.get();
  manager.set_store_health_listener([server](bool writable) {
    server->GetHealthCheckService()->SetServingStatus(v1::KesslerService::service_full_name(), writable);
  });
}

ApiServer::~ApiServer() {
  impl_->manager.set_store_health_listener(nullptr);
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
