// Server reflection and health against the real kesslerd, as a client that has none of the project's
// protos compiled in would use them (what grpcurl does): list the services, fetch the service's file
// descriptors, rebuild the API from them alone and call it; and the standard health check.
//
// The reflection protocol (grpc.reflection.v1alpha, the version Debian 12's gRPC serves) is spoken
// here on the wire through a generic stub, so nothing of it comes from the daemon's own build.
#include <google/protobuf/descriptor.h>
#include <google/protobuf/descriptor.pb.h>
#include <google/protobuf/descriptor_database.h>
#include <google/protobuf/dynamic_message.h>
#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/wire_format_lite.h>
#include <grpcpp/generic/generic_stub.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/service/service_harness.hpp"

namespace kessler {
namespace {

using google::protobuf::internal::WireFormatLite;
using google::protobuf::io::CodedInputStream;
using google::protobuf::io::CodedOutputStream;

const char* const kReflectionMethod = "/grpc.reflection.v1alpha.ServerReflection/ServerReflectionInfo";

// ---- protobuf wire format, by hand ----

// A message with one string field.
std::string string_field(int number, const std::string& value) {
  std::string out;
  {
    google::protobuf::io::StringOutputStream stream(&out);
    CodedOutputStream coded(&stream);
    coded.WriteTag(WireFormatLite::MakeTag(number, WireFormatLite::WIRETYPE_LENGTH_DELIMITED));
    coded.WriteVarint32(static_cast<std::uint32_t>(value.size()));
    coded.WriteString(value);
  }
  return out;
}

// The fields of a message: length-delimited ones as bytes, varints as numbers, by field number.
struct Fields {
  std::multimap<int, std::string> bytes;
  std::multimap<int, std::uint64_t> varints;
  std::vector<std::string> all_bytes(int number) const {
    std::vector<std::string> out;
    auto [first, last] = bytes.equal_range(number);
    for (auto it = first; it != last; ++it) out.push_back(it->second);
    return out;
  }
};

Fields parse_fields(const std::string& message) {
  Fields fields;
  CodedInputStream in(reinterpret_cast<const std::uint8_t*>(message.data()),
                      static_cast<int>(message.size()));
  while (std::uint32_t tag = in.ReadTag()) {
    const int number = static_cast<int>(WireFormatLite::GetTagFieldNumber(tag));
    switch (WireFormatLite::GetTagWireType(tag)) {
      case WireFormatLite::WIRETYPE_LENGTH_DELIMITED: {
        std::uint32_t size = 0;
        std::string value;
        if (!in.ReadVarint32(&size) || !in.ReadString(&value, static_cast<int>(size)))
          throw std::runtime_error("malformed length-delimited field");
        fields.bytes.emplace(number, std::move(value));
        break;
      }
      case WireFormatLite::WIRETYPE_VARINT: {
        std::uint64_t value = 0;
        if (!in.ReadVarint64(&value)) throw std::runtime_error("malformed varint");
        fields.varints.emplace(number, value);
        break;
      }
      default:
        if (!WireFormatLite::SkipField(&in, tag)) throw std::runtime_error("malformed field");
    }
  }
  return fields;
}

grpc::ByteBuffer to_buffer(const std::string& bytes) {
  grpc::Slice slice(bytes);
  return grpc::ByteBuffer(&slice, 1);
}

std::string from_buffer(const grpc::ByteBuffer& buffer) {
  std::vector<grpc::Slice> slices;
  if (!buffer.Dump(&slices).ok()) throw std::runtime_error("cannot read a response buffer");
  std::string out;
  for (const auto& s : slices) out.append(reinterpret_cast<const char*>(s.begin()), s.size());
  return out;
}

// ---- a reflection client: one ServerReflectionInfo stream, one response per request ----

class ReflectionClient {
 public:
  explicit ReflectionClient(const std::shared_ptr<grpc::Channel>& channel) : stub_(channel) {
    context_.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
    call_ = stub_.PrepareCall(&context_, kReflectionMethod, &cq_);
    call_->StartCall(tag(1));
    await(1, "start");
  }
  ~ReflectionClient() {
    call_->WritesDone(tag(4));
    await(4, "writes done", false);
    grpc::Status status;
    call_->Finish(&status, tag(5));
    await(5, "finish", false);
    cq_.Shutdown();
    void* ignored = nullptr;
    bool ok = false;
    while (cq_.Next(&ignored, &ok)) {
    }
  }

  // ServerReflectionResponse fields for a ServerReflectionRequest with one string field set.
  Fields ask(int request_field, const std::string& value) {
    call_->Write(to_buffer(string_field(request_field, value)), tag(2));
    await(2, "write");
    grpc::ByteBuffer response;
    call_->Read(&response, tag(3));
    await(3, "read");
    return parse_fields(from_buffer(response));
  }

  // ServerReflectionRequest fields and ServerReflectionResponse fields (reflection.proto, v1alpha).
  static constexpr int kFileByFilename = 3, kFileContainingSymbol = 4, kListServices = 7;
  static constexpr int kFileDescriptorResponse = 4, kListServicesResponse = 6, kErrorResponse = 7;

 private:
  static void* tag(std::intptr_t n) { return reinterpret_cast<void*>(n); }
  void await(std::intptr_t expected, const char* what, bool must_succeed = true) {
    void* got = nullptr;
    bool ok = false;
    auto status = cq_.AsyncNext(&got, &ok, std::chrono::system_clock::now() + std::chrono::seconds(30));
    if (status != grpc::CompletionQueue::GOT_EVENT || got != tag(expected) || (must_succeed && !ok))
      throw std::runtime_error(std::string("reflection stream: ") + what + " failed");
  }

  grpc::GenericStub stub_;
  grpc::ClientContext context_;
  grpc::CompletionQueue cq_;
  std::unique_ptr<grpc::GenericClientAsyncReaderWriter> call_;
};

// The service names a ListServices answer carries.
std::set<std::string> list_services(ReflectionClient& client) {
  Fields response = client.ask(ReflectionClient::kListServices, "");
  auto list = response.all_bytes(ReflectionClient::kListServicesResponse);
  if (list.size() != 1) throw std::runtime_error("no list_services_response");
  std::set<std::string> names;
  for (const std::string& service : parse_fields(list[0]).all_bytes(1))  // ListServiceResponse.service
    for (const std::string& name : parse_fields(service).all_bytes(1)) names.insert(name);  // .name
  return names;
}

// The FileDescriptorProtos of a file_descriptor_response (empty when the answer is an error).
std::vector<google::protobuf::FileDescriptorProto> file_descriptors(const Fields& response) {
  std::vector<google::protobuf::FileDescriptorProto> files;
  for (const std::string& r : response.all_bytes(ReflectionClient::kFileDescriptorResponse))
    for (const std::string& bytes : parse_fields(r).all_bytes(1)) {  // .file_descriptor_proto
      google::protobuf::FileDescriptorProto file;
      if (!file.ParseFromString(bytes)) throw std::runtime_error("unparsable FileDescriptorProto");
      files.push_back(std::move(file));
    }
  return files;
}

// Every file a symbol needs, fetched through reflection: the symbol's file, then any dependency the
// answers did not already bring, by name.
void fetch_symbol(ReflectionClient& client, const std::string& symbol,
                  google::protobuf::SimpleDescriptorDatabase& database) {
  std::set<std::string> have;
  std::vector<std::string> wanted;
  auto add = [&](const std::vector<google::protobuf::FileDescriptorProto>& files) {
    for (const auto& file : files) {
      if (!have.insert(file.name()).second) continue;
      database.Add(file);
      for (const auto& dependency : file.dependency()) wanted.push_back(dependency);
    }
  };
  auto files = file_descriptors(client.ask(ReflectionClient::kFileContainingSymbol, symbol));
  if (files.empty()) throw std::runtime_error("no file descriptor for " + symbol);
  add(files);
  while (!wanted.empty()) {
    std::string name = wanted.back();
    wanted.pop_back();
    if (have.count(name)) continue;
    auto more = file_descriptors(client.ask(ReflectionClient::kFileByFilename, name));
    if (more.empty()) throw std::runtime_error("no file descriptor for file " + name);
    add(more);
  }
}

// A unary call by full method name with serialized messages.
grpc::Status unary(const std::shared_ptr<grpc::Channel>& channel, const std::string& method,
                   const std::string& request, std::string& response) {
  grpc::GenericStub generic(channel);
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
  grpc::ByteBuffer in = to_buffer(request);
  grpc::ByteBuffer out;
  std::promise<grpc::Status> done;
  generic.UnaryCall(&context, method, grpc::StubOptions(), &in, &out,
                    [&](grpc::Status status) { done.set_value(status); });
  grpc::Status status = done.get_future().get();
  if (status.ok()) response = from_buffer(out);
  return status;
}

class Reflection : public ::testing::Test {
 protected:
  void SetUp() override {
    daemon_.start();
    channel_ = grpc::CreateChannel(daemon_.address(), grpc::InsecureChannelCredentials());
  }
  TempDir dir_;
  test::Daemon daemon_{dir_.path() + "/k.db"};
  std::shared_ptr<grpc::Channel> channel_;
};

TEST_F(Reflection, ListsTheApiHealthAndReflectionServices) {
  ReflectionClient client(channel_);
  std::set<std::string> services = list_services(client);
  EXPECT_TRUE(services.count("kessler.v1.KesslerService")) << testing::PrintToString(services);
  EXPECT_TRUE(services.count("grpc.health.v1.Health")) << testing::PrintToString(services);
  EXPECT_TRUE(services.count("grpc.reflection.v1alpha.ServerReflection")) << testing::PrintToString(services);
}

// The descriptors reflection serves are complete: the whole API rebuilds from them alone, and a
// call made with messages built from them (no generated code) works.
TEST_F(Reflection, TheApiRebuiltFromReflectedDescriptorsAnswersCalls) {
  google::protobuf::SimpleDescriptorDatabase database;
  {
    ReflectionClient client(channel_);
    fetch_symbol(client, "kessler.v1.KesslerService", database);
  }
  google::protobuf::DescriptorPool pool(&database);  // not the generated pool of this binary
  const google::protobuf::ServiceDescriptor* service = pool.FindServiceByName("kessler.v1.KesslerService");
  ASSERT_NE(service, nullptr);
  std::set<std::string> methods;
  for (int i = 0; i < service->method_count(); ++i) methods.insert(service->method(i)->name());
  EXPECT_EQ(methods,
            (std::set<std::string>{"SubmitRun", "GetRun", "ListRuns", "CancelRun", "ResumeRun", "DeleteRun",
                                   "WatchRun", "ListConjunctions", "GetConjunctionCdm", "GetRunStats",
                                   "ListFragments", "SubmitEnsemble", "GetEnsemble", "ListEnsembles",
                                   "CancelEnsemble", "GetFigures", "ListSnapshots", "GetSnapshot"}));
  const auto* watch = service->FindMethodByName("WatchRun");
  ASSERT_NE(watch, nullptr);
  EXPECT_TRUE(watch->server_streaming());
  EXPECT_FALSE(watch->client_streaming());
  EXPECT_EQ(watch->output_type()->full_name(), "kessler.v1.RunEvent");
  ASSERT_NE(watch->input_type()->FindFieldByName("after_seq"), nullptr);
  // The scenario message, nested deep in the submission, is there with its fields.
  const auto* scenario = pool.FindMessageTypeByName("kessler.v1.Scenario");
  ASSERT_NE(scenario, nullptr);
  EXPECT_NE(scenario->FindFieldByName("duration_days"), nullptr);

  // SubmitRun, then GetRun, with dynamic messages of the reflected types.
  google::protobuf::DynamicMessageFactory factory(&pool);
  const auto* submit = service->FindMethodByName("SubmitRun");
  std::unique_ptr<google::protobuf::Message> request(factory.GetPrototype(submit->input_type())->New());
  request->GetReflection()->SetString(
      request.get(), submit->input_type()->FindFieldByName("scenario_text"),
      test::read_text(test::source_path("tests/service/scenarios/tiny.yaml")));
  std::string bytes;
  grpc::Status status =
      unary(channel_, "/kessler.v1.KesslerService/SubmitRun", request->SerializeAsString(), bytes);
  ASSERT_TRUE(status.ok()) << status.error_message();
  std::unique_ptr<google::protobuf::Message> run(factory.GetPrototype(submit->output_type())->New());
  ASSERT_TRUE(run->ParseFromString(bytes));
  const auto* run_type = submit->output_type();
  const std::int64_t id = run->GetReflection()->GetInt64(*run, run_type->FindFieldByName("id"));
  EXPECT_GT(id, 0);

  const auto* get = service->FindMethodByName("GetRun");
  std::unique_ptr<google::protobuf::Message> get_request(factory.GetPrototype(get->input_type())->New());
  get_request->GetReflection()->SetInt64(get_request.get(), get->input_type()->FindFieldByName("run_id"), id);
  status = unary(channel_, "/kessler.v1.KesslerService/GetRun", get_request->SerializeAsString(), bytes);
  ASSERT_TRUE(status.ok()) << status.error_message();
  std::unique_ptr<google::protobuf::Message> got(factory.GetPrototype(get->output_type())->New());
  ASSERT_TRUE(got->ParseFromString(bytes));
  EXPECT_EQ(got->GetReflection()->GetString(*got, run_type->FindFieldByName("name")), "service-tiny");
  EXPECT_EQ(got->GetReflection()->GetInt64(*got, run_type->FindFieldByName("id")), id);
}

TEST_F(Reflection, AnUnknownSymbolIsNotFound) {
  ReflectionClient client(channel_);
  Fields response = client.ask(ReflectionClient::kFileContainingSymbol, "kessler.v1.NoSuchService");
  auto errors = response.all_bytes(ReflectionClient::kErrorResponse);
  ASSERT_EQ(errors.size(), 1u);
  Fields error = parse_fields(errors[0]);
  ASSERT_EQ(error.varints.count(1), 1u);  // ErrorResponse.error_code
  EXPECT_EQ(error.varints.find(1)->second, static_cast<std::uint64_t>(grpc::StatusCode::NOT_FOUND));
  // The stream still serves after an error.
  EXPECT_TRUE(list_services(client).count("kessler.v1.KesslerService"));
}

// The standard health check (what grpc_health_probe sends), for the whole server and for the API
// service by name; an unknown service is NOT_FOUND.
TEST_F(Reflection, HealthCheckAnswersServingForTheServerAndTheApiService) {
  for (const std::string service : {"", "kessler.v1.KesslerService"}) {
    std::string response;
    // HealthCheckRequest{service = 1}; an empty request asks about the whole server.
    grpc::Status status = unary(channel_, "/grpc.health.v1.Health/Check",
                                service.empty() ? std::string() : string_field(1, service), response);
    ASSERT_TRUE(status.ok()) << "'" << service << "': " << status.error_message();
    Fields fields = parse_fields(response);
    ASSERT_EQ(fields.varints.count(1), 1u) << "'" << service << "'";         // HealthCheckResponse.status
    EXPECT_EQ(fields.varints.find(1)->second, 1u) << "'" << service << "'";  // SERVING
  }
  std::string response;
  grpc::Status status =
      unary(channel_, "/grpc.health.v1.Health/Check", string_field(1, "no.such.Service"), response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
}

// `kessler health`: the same check from the CLI, for scripts and container health checks.
TEST_F(Reflection, KesslerHealthExitsZeroOnlyWhenServing) {
  auto serving = test::cli(dir_, "health --server " + daemon_.address());
  EXPECT_EQ(serving.exit_code, 0) << serving.err;
  EXPECT_EQ(serving.last_line(), "SERVING");
  auto json = test::cli(
      dir_, "health --service kessler.v1.KesslerService --output json --server " + daemon_.address());
  EXPECT_EQ(json.exit_code, 0) << json.err;
  EXPECT_NE(json.out.find("\"status\": \"SERVING\""), std::string::npos) << json.out;
  auto unknown = test::cli(dir_, "health --service no.such.Service --server " + daemon_.address());
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_NE(unknown.err.find("NOT_FOUND"), std::string::npos) << unknown.err;
  daemon_.kill9();
  auto gone = test::cli(dir_, "health --timeout-s 2 --server " + daemon_.address());
  EXPECT_EQ(gone.exit_code, 1);
  EXPECT_NE(gone.err.find("UNAVAILABLE"), std::string::npos) << gone.err;
  EXPECT_EQ(test::cli(dir_, "health --timeout-s 0").exit_code, 2);
}

}  // namespace
}  // namespace kessler
