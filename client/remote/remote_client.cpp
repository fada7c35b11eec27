#include "client/remote/remote_client.hpp"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>

#include <cstdlib>
#include <fstream>
#include <future>
#include <iomanip>
#include <random>
#include <sstream>
#include <stdexcept>

#include "kessler/v1/service.grpc.pb.h"

namespace kessler::cli {
namespace {

const char* code_name(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK:
      return "OK";
    case grpc::StatusCode::CANCELLED:
      return "CANCELLED";
    case grpc::StatusCode::INVALID_ARGUMENT:
      return "INVALID_ARGUMENT";
    case grpc::StatusCode::DEADLINE_EXCEEDED:
      return "DEADLINE_EXCEEDED";
    case grpc::StatusCode::NOT_FOUND:
      return "NOT_FOUND";
    case grpc::StatusCode::FAILED_PRECONDITION:
      return "FAILED_PRECONDITION";
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
      return "RESOURCE_EXHAUSTED";
    case grpc::StatusCode::UNAVAILABLE:
      return "UNAVAILABLE";
    case grpc::StatusCode::INTERNAL:
      return "INTERNAL";
    case grpc::StatusCode::UNAUTHENTICATED:
      return "UNAUTHENTICATED";
    case grpc::StatusCode::PERMISSION_DENIED:
      return "PERMISSION_DENIED";
    default:
      return "ERROR";
  }
}

CallResult result_of(const grpc::Status& status, const grpc::ClientContext& context) {
  CallResult r;
  const auto& initial = context.GetServerInitialMetadata();
  auto warning = initial.find("kessler-warning");
  if (warning != initial.end()) r.warning = std::string(warning->second.data(), warning->second.size());
  r.ok = status.ok();
  r.code = static_cast<int>(status.error_code());
  r.code_name = code_name(status.error_code());
  r.message = status.error_message();
  const auto& trailers = context.GetServerTrailingMetadata();
  auto it = trailers.find("kessler-field-path");
  if (it != trailers.end()) r.field_path = std::string(it->second.data(), it->second.size());
  return r;
}

ConnectionOptions& connection() {
  static ConnectionOptions options;
  return options;
}

std::string flag_or_env(const std::string& flag, const char* env) {
  if (!flag.empty()) return flag;
  const char* value = std::getenv(env);
  return value ? value : "";
}

std::string read_pem(const std::string& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(std::string(what) + " " + path + ": cannot read");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::shared_ptr<grpc::ChannelCredentials> channel_credentials() {
  const ConnectionOptions& o = connection();
  if (o.tls_ca.empty()) return grpc::InsecureChannelCredentials();
  grpc::SslCredentialsOptions ssl;
  ssl.pem_root_certs = read_pem(o.tls_ca, "--tls-ca");
  if (!o.tls_cert.empty()) {
    ssl.pem_cert_chain = read_pem(o.tls_cert, "--tls-cert");
    ssl.pem_private_key = read_pem(o.tls_key, "--tls-key");
  }
  return grpc::SslCredentials(ssl);
}

// The token, if any, on every call.
void authorize(grpc::ClientContext& context) {
  if (!connection().token.empty()) context.AddMetadata("authorization", "Bearer " + connection().token);
}

}  // namespace

bool set_connection_options(const ConnectionOptions& flags, std::string& error) {
  ConnectionOptions& o = connection();
  o.token = flag_or_env(flags.token, "KESSLER_TOKEN");
  o.tls_ca = flag_or_env(flags.tls_ca, "KESSLER_TLS_CA");
  o.tls_cert = flag_or_env(flags.tls_cert, "KESSLER_TLS_CERT");
  o.tls_key = flag_or_env(flags.tls_key, "KESSLER_TLS_KEY");
  if (o.tls_cert.empty() != o.tls_key.empty()) {
    error = "--tls-cert and --tls-key go together";
    return false;
  }
  if (!o.tls_cert.empty() && o.tls_ca.empty()) {
    error = "--tls-cert needs --tls-ca (the CA of the daemon's certificate)";
    return false;
  }
  try {
    channel_credentials();  // the files are readable
  } catch (const std::exception& e) {
    error = e.what();
    return false;
  }
  return true;
}

const ConnectionOptions& connection_options() {
  return connection();
}

std::string new_request_id() {
  std::random_device device;
  std::ostringstream out;
  out << std::hex << std::setfill('0');
  for (int i = 0; i < 4; ++i) out << std::setw(8) << device();
  return out.str();
}

std::string server_address(const std::string& flag_value) {
  if (!flag_value.empty()) return flag_value;
  const char* env = std::getenv("KESSLER_SERVER");
  if (env && *env) return env;
  return "127.0.0.1:50051";
}

int CallResult::exit_code() const {
  return ok ? 0 : code == 3 ? 2 : 1;
}

std::string CallResult::describe() const {
  if (code != 14) return code_name + ": " + message;
  // A TLS port hangs up on a plaintext client during the handshake ("Socket closed"), before any call
  // exists that could be answered UNAUTHENTICATED; a daemon that is not there refuses the connection.
  if (connection().tls_ca.empty() && message.find("Socket closed") != std::string::npos)
    return "UNAVAILABLE: kesslerd closed the connection (" + message +
           "); if it serves TLS, pass --tls-ca FILE (the CA that signed its certificate)";
  return "UNAVAILABLE: cannot reach kesslerd (" + message + ")";
}

struct RemoteClient::Impl {
  std::shared_ptr<grpc::Channel> channel;
  std::unique_ptr<v1::KesslerService::Stub> stub;
};

RemoteClient::RemoteClient(const std::string& address) : address_(address), impl_(std::make_unique<Impl>()) {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(512 << 20);
  args.SetMaxSendMessageSize(-1);
  impl_->channel = grpc::CreateCustomChannel(address, channel_credentials(), args);
  impl_->stub = v1::KesslerService::NewStub(impl_->channel);
}

RemoteClient::~RemoteClient() = default;

namespace {

// One unary call with the client's deadline: (stub->*method)(context, request, response).
template <class Stub, class Request, class Response>
CallResult unary(Stub& stub, grpc::Status (Stub::*method)(grpc::ClientContext*, const Request&, Response*),
                 const Request& request, Response& response) {
  grpc::ClientContext context;
  authorize(context);
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(300));
  const grpc::Status status = (stub.*method)(&context, request, &response);
  return result_of(status, context);
}

}  // namespace

CallResult RemoteClient::submit(const v1::SubmitRunRequest& request, v1::Run& out) {
  return unary(*impl_->stub, &v1::KesslerService::Stub::SubmitRun, request, out);
}

CallResult RemoteClient::submit_ensemble(const v1::SubmitEnsembleRequest& request, v1::EnsembleReport& out) {
  return unary(*impl_->stub, &v1::KesslerService::Stub::SubmitEnsemble, request, out);
}

CallResult RemoteClient::figures(const v1::GetFiguresRequest& request, v1::GetFiguresResponse& out) {
  return unary(*impl_->stub, &v1::KesslerService::Stub::GetFigures, request, out);
}

CallResult RemoteClient::get_ensemble(const v1::GetEnsembleRequest& request, v1::EnsembleReport& out) {
  return unary(*impl_->stub, &v1::KesslerService::Stub::GetEnsemble, request, out);
}

CallResult RemoteClient::list_ensembles(const v1::ListEnsemblesRequest& request,
                                        v1::ListEnsemblesResponse& out) {
  return unary(*impl_->stub, &v1::KesslerService::Stub::ListEnsembles, request, out);
}

CallResult RemoteClient::cancel_ensemble(std::int64_t ensemble_id, v1::EnsembleReport& out) {
  v1::CancelEnsembleRequest request;
  request.set_ensemble_id(ensemble_id);
  return unary(*impl_->stub, &v1::KesslerService::Stub::CancelEnsemble, request, out);
}

CallResult RemoteClient::get(std::int64_t run_id, v1::Run& out) {
  v1::GetRunRequest request;
  request.set_run_id(run_id);
  return unary(*impl_->stub, &v1::KesslerService::Stub::GetRun, request, out);
}

CallResult RemoteClient::list(const v1::ListRunsRequest& request, v1::ListRunsResponse& out) {
  return unary(*impl_->stub, &v1::KesslerService::Stub::ListRuns, request, out);
}

CallResult RemoteClient::cancel(std::int64_t run_id, v1::Run& out) {
  v1::CancelRunRequest request;
  request.set_run_id(run_id);
  return unary(*impl_->stub, &v1::KesslerService::Stub::CancelRun, request, out);
}

CallResult RemoteClient::resume(std::int64_t run_id, v1::Run& out) {
  v1::ResumeRunRequest request;
  request.set_run_id(run_id);
  return unary(*impl_->stub, &v1::KesslerService::Stub::ResumeRun, request, out);
}

CallResult RemoteClient::remove(std::int64_t run_id) {
  v1::DeleteRunRequest request;
  request.set_run_id(run_id);
  v1::DeleteRunResponse out;
  return unary(*impl_->stub, &v1::KesslerService::Stub::DeleteRun, request, out);
}

CallResult RemoteClient::conjunctions(const v1::ListConjunctionsRequest& request,
                                      v1::ListConjunctionsResponse& out) {
  return unary(*impl_->stub, &v1::KesslerService::Stub::ListConjunctions, request, out);
}

CallResult RemoteClient::conjunction_cdm(const v1::GetConjunctionCdmRequest& request,
                                         v1::ConjunctionCdm& out) {
  return unary(*impl_->stub, &v1::KesslerService::Stub::GetConjunctionCdm, request, out);
}

CallResult RemoteClient::stats(const v1::GetRunStatsRequest& request, v1::RunStats& out) {
  return unary(*impl_->stub, &v1::KesslerService::Stub::GetRunStats, request, out);
}

CallResult RemoteClient::fragments(const v1::ListFragmentsRequest& request, v1::ListFragmentsResponse& out) {
  return unary(*impl_->stub, &v1::KesslerService::Stub::ListFragments, request, out);
}

CallResult RemoteClient::snapshots(const v1::ListSnapshotsRequest& request, v1::ListSnapshotsResponse& out) {
  return unary(*impl_->stub, &v1::KesslerService::Stub::ListSnapshots, request, out);
}

CallResult RemoteClient::snapshot(const v1::GetSnapshotRequest& request, v1::GetSnapshotResponse& out) {
  return unary(*impl_->stub, &v1::KesslerService::Stub::GetSnapshot, request, out);
}

CallResult RemoteClient::health(const std::string& service, double timeout_s, std::string& status) {
  // The health proto's stubs are not part of the build: its two one-field messages are written and
  // read here on the wire (HealthCheckRequest.service = 1, HealthCheckResponse.status = 1).
  std::string request;
  if (!service.empty()) {
    google::protobuf::io::StringOutputStream stream(&request);
    google::protobuf::io::CodedOutputStream out(&stream);
    out.WriteTag((1 << 3) | 2);
    out.WriteVarint32(static_cast<std::uint32_t>(service.size()));
    out.WriteString(service);
  }
  grpc::Slice slice(request);
  grpc::ByteBuffer in(&slice, 1), out;
  grpc::GenericStub generic(impl_->channel);
  grpc::ClientContext context;
  authorize(context);
  context.set_deadline(std::chrono::system_clock::now() +
                       std::chrono::milliseconds(static_cast<long>(timeout_s * 1000)));
  std::promise<grpc::Status> done;
  generic.UnaryCall(&context, "/grpc.health.v1.Health/Check", grpc::StubOptions(), &in, &out,
                    [&](grpc::Status s) { done.set_value(std::move(s)); });
  grpc::Status call = done.get_future().get();
  CallResult result = result_of(call, context);
  if (!result.ok) return result;
  std::vector<grpc::Slice> slices;
  std::string bytes;
  if (out.Dump(&slices).ok())
    for (const auto& s : slices) bytes.append(reinterpret_cast<const char*>(s.begin()), s.size());
  google::protobuf::io::CodedInputStream reader(reinterpret_cast<const std::uint8_t*>(bytes.data()),
                                                static_cast<int>(bytes.size()));
  std::uint64_t value = 0;  // absent: UNKNOWN (0)
  while (std::uint32_t tag = reader.ReadTag()) {
    if (tag != (1 << 3) || !reader.ReadVarint64(&value)) break;
  }
  static const char* const kNames[] = {"UNKNOWN", "SERVING", "NOT_SERVING", "SERVICE_UNKNOWN"};
  status = value < 4 ? kNames[value] : "UNKNOWN";
  return result;
}

CallResult RemoteClient::watch(const v1::WatchRunRequest& request,
                               const std::function<bool(const v1::RunEvent&)>& on_event) {
  grpc::ClientContext context;
  authorize(context);
  auto reader = impl_->stub->WatchRun(&context, request);
  v1::RunEvent event;
  while (reader->Read(&event)) {
    if (!on_event(event)) {
      context.TryCancel();
      break;
    }
  }
  auto status = reader->Finish();
  if (status.error_code() == grpc::StatusCode::CANCELLED) status = grpc::Status::OK;
  return result_of(status, context);
}

}  // namespace kessler::cli
