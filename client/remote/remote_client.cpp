#include "client/remote/remote_client.hpp"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>

#include <cstdlib>
#include <future>

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
    default:
      return "ERROR";
  }
}

CallResult result_of(const grpc::Status& status, const grpc::ClientContext& context) {
  CallResult r;
  r.ok = status.ok();
  r.code = static_cast<int>(status.error_code());
  r.code_name = code_name(status.error_code());
  r.message = status.error_message();
  const auto& trailers = context.GetServerTrailingMetadata();
  auto it = trailers.find("kessler-field-path");
  if (it != trailers.end()) r.field_path = std::string(it->second.data(), it->second.size());
  return r;
}

}  // namespace

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
  if (code == 14) return "UNAVAILABLE: cannot reach kesslerd (" + message + ")";
  return code_name + ": " + message;
}

struct RemoteClient::Impl {
  std::shared_ptr<grpc::Channel> channel;
  std::unique_ptr<v1::KesslerService::Stub> stub;
};

RemoteClient::RemoteClient(const std::string& address) : address_(address), impl_(std::make_unique<Impl>()) {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(512 << 20);
  args.SetMaxSendMessageSize(-1);
  impl_->channel = grpc::CreateCustomChannel(address, grpc::InsecureChannelCredentials(), args);
  impl_->stub = v1::KesslerService::NewStub(impl_->channel);
}

RemoteClient::~RemoteClient() = default;

namespace {

// One unary call with the client's deadline: (stub->*method)(context, request, response).
template <class Stub, class Request, class Response>
CallResult unary(Stub& stub, grpc::Status (Stub::*method)(grpc::ClientContext*, const Request&, Response*),
                 const Request& request, Response& response) {
  grpc::ClientContext context;
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

CallResult RemoteClient::get_ensemble(const v1::GetEnsembleRequest& request, v1::EnsembleReport& out) {
  return unary(*impl_->stub, &v1::KesslerService::Stub::GetEnsemble, request, out);
}

CallResult RemoteClient::list_ensembles(const v1::ListEnsemblesRequest& request, v1::ListEnsemblesResponse& out) {
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
