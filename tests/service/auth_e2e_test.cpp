// Transport and authentication end to end: the real kesslerd over TLS (tests/data/tls, a test CA) with a
// tokens file made by `kesslerd token create`, called through gRPC stubs and the kessler CLI. Calls
// without a token, with an unknown one, with a read token submitting and with another submitter's token
// are refused (UNAUTHENTICATED, PERMISSION_DENIED); plaintext and an untrusted CA never get through;
// the right token works. Also: per-token limits, SIGHUP, idempotent submission, exposure rules.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <memory>
#include <string>

#include "kessler/v1/service.grpc.pb.h"
#include "tests/service/service_harness.hpp"

namespace kessler {
namespace {

using test::cli;
using test::Daemon;

std::string tls_file(const std::string& name) {
  return test::source_path("tests/data/tls/" + name);
}

// `kesslerd token create`: the token it prints on stdout.
std::string create_token(const std::string& tokens, const std::string& name, const std::string& role) {
  const std::string cmd = test::bin("kesslerd") + " token create --role " + role + " --name " + name +
                          " --tokens " + tokens + " 2>/dev/null";
  FILE* pipe = popen(cmd.c_str(), "r");
  std::string out;
  char buffer[256];
  while (pipe && fgets(buffer, sizeof buffer, pipe)) out += buffer;
  if (!pipe || pclose(pipe) != 0) throw std::runtime_error("kesslerd token create failed");
  while (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

std::shared_ptr<grpc::Channel> tls_channel(const std::string& address, const std::string& ca,
                                           const std::string& cert = "", const std::string& key = "") {
  grpc::SslCredentialsOptions ssl;
  ssl.pem_root_certs = test::read_text(ca);
  if (!cert.empty()) {
    ssl.pem_cert_chain = test::read_text(cert);
    ssl.pem_private_key = test::read_text(key);
  }
  return grpc::CreateChannel(address, grpc::SslCredentials(ssl));
}

// A context with the token (none when empty) and a deadline, so a refused handshake ends the call.
std::unique_ptr<grpc::ClientContext> context_with(const std::string& token) {
  auto context = std::make_unique<grpc::ClientContext>();
  if (!token.empty()) context->AddMetadata("authorization", "Bearer " + token);
  context->set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
  return context;
}

v1::SubmitRunRequest tiny_request(const std::string& request_id = "") {
  v1::SubmitRunRequest request;
  request.set_scenario_text(test::read_text(test::kTinyScenario));
  request.set_request_id(request_id);
  return request;
}

class TlsTokens : public ::testing::Test {
 protected:
  void SetUp() override { start({}); }

  void start(std::vector<std::string> extra) {
    tokens_file = dir.path() + "/tokens";
    for (const auto& [name, role] : std::map<std::string, std::string>{
             {"root", "admin"}, {"alice", "submit"}, {"bob", "submit"}, {"viewer", "read"}})
      if (!token.count(name)) token[name] = create_token(tokens_file, name, role);
    std::vector<std::string> args = {
        "--tls-cert", tls_file("server.pem"), "--tls-key", tls_file("server.key"), "--tokens", tokens_file};
    args.insert(args.end(), extra.begin(), extra.end());
    daemon = std::make_unique<Daemon>(dir.path() + "/k.db", args);
    daemon->start();
    address = "localhost:" + daemon->address().substr(daemon->address().rfind(':') + 1);
    stub = v1::KesslerService::NewStub(tls_channel(address, tls_file("ca.pem")));
  }

  grpc::Status submit(const std::string& who, v1::Run& run, const std::string& request_id = "") {
    return stub->SubmitRun(context_with(token[who]).get(), tiny_request(request_id), &run);
  }
  grpc::Status list(const std::string& bearer, v1::ListRunsResponse& out) {
    return stub->ListRuns(context_with(bearer).get(), v1::ListRunsRequest(), &out);
  }

  TempDir dir;
  std::string tokens_file;
  std::map<std::string, std::string> token;
  std::unique_ptr<Daemon> daemon;
  std::string address;
  std::unique_ptr<v1::KesslerService::Stub> stub;
};

TEST_F(TlsTokens, TokensFileKeepsOnlyHashes) {
  const std::string text = test::read_text(tokens_file);
  for (const auto& [name, secret] : token) {
    EXPECT_EQ(secret.rfind("kst_", 0), 0u) << secret;
    EXPECT_EQ(text.find(secret), std::string::npos) << "token of " << name << " stored in clear";
    EXPECT_NE(text.find(name + " "), std::string::npos);
  }
  EXPECT_NE(text.find("sha256:"), std::string::npos);
}

TEST_F(TlsTokens, CallsWithoutTheRightTokenAreRefused) {
  v1::ListRunsResponse runs;
  EXPECT_EQ(list("", runs).error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(list("kst_" + std::string(64, '0'), runs).error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(list(token["alice"] + "x", runs).error_code(), grpc::StatusCode::UNAUTHENTICATED);
  // A token of the right kind in the wrong scheme.
  grpc::ClientContext basic;
  basic.AddMetadata("authorization", "Basic " + token["root"]);
  EXPECT_EQ(stub->ListRuns(&basic, v1::ListRunsRequest(), &runs).error_code(),
            grpc::StatusCode::UNAUTHENTICATED);

  v1::Run run;
  auto read_submits = submit("viewer", run);
  EXPECT_EQ(read_submits.error_code(), grpc::StatusCode::PERMISSION_DENIED) << read_submits.error_message();
  EXPECT_NE(read_submits.error_message().find("role read"), std::string::npos)
      << read_submits.error_message();
  ASSERT_TRUE(list(token["root"], runs).ok());
  EXPECT_EQ(runs.runs_size(), 0);  // nothing refused was queued
}

TEST_F(TlsTokens, SubmitTokensReachOnlyTheirOwnRuns) {
  v1::Run alices;
  ASSERT_TRUE(submit("alice", alices).ok());
  EXPECT_EQ(alices.submitter(), "alice");
  v1::Run bobs;
  ASSERT_TRUE(submit("bob", bobs).ok());

  v1::CancelRunRequest cancel;
  cancel.set_run_id(alices.id());
  v1::Run out;
  EXPECT_EQ(stub->CancelRun(context_with(token["bob"]).get(), cancel, &out).error_code(),
            grpc::StatusCode::PERMISSION_DENIED);
  EXPECT_EQ(stub->CancelRun(context_with(token["viewer"]).get(), cancel, &out).error_code(),
            grpc::StatusCode::PERMISSION_DENIED);
  ASSERT_TRUE(stub->CancelRun(context_with(token["alice"]).get(), cancel, &out).ok());
  v1::DeleteRunRequest remove;
  remove.set_run_id(alices.id());
  v1::DeleteRunResponse removed;
  auto bob_deletes = stub->DeleteRun(context_with(token["bob"]).get(), remove, &removed);
  EXPECT_EQ(bob_deletes.error_code(), grpc::StatusCode::PERMISSION_DENIED) << bob_deletes.error_message();

  v1::GetRunRequest get;
  get.set_run_id(alices.id());
  EXPECT_EQ(stub->GetRun(context_with(token["bob"]).get(), get, &out).error_code(),
            grpc::StatusCode::PERMISSION_DENIED);
  EXPECT_TRUE(stub->GetRun(context_with(token["viewer"]).get(), get, &out).ok());  // read sees all
  EXPECT_EQ(out.submitter(), "alice");
  v1::WatchRunRequest watch;
  watch.set_run_id(alices.id());
  auto bob_context = context_with(token["bob"]);
  auto reader = stub->WatchRun(bob_context.get(), watch);
  v1::RunEvent event;
  EXPECT_FALSE(reader->Read(&event));
  EXPECT_EQ(reader->Finish().error_code(), grpc::StatusCode::PERMISSION_DENIED);

  v1::ListRunsResponse runs;
  ASSERT_TRUE(list(token["bob"], runs).ok());
  ASSERT_EQ(runs.runs_size(), 1);
  EXPECT_EQ(runs.runs(0).id(), bobs.id());
  ASSERT_TRUE(list(token["viewer"], runs).ok());
  EXPECT_EQ(runs.runs_size(), 2);
  // The admin reaches every run (once the cancelled run has stopped).
  grpc::Status deleted;
  for (int i = 0; i < 200; ++i) {
    deleted = stub->DeleteRun(context_with(token["root"]).get(), remove, &removed);
    if (deleted.error_code() != grpc::StatusCode::FAILED_PRECONDITION) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_TRUE(deleted.ok()) << deleted.error_message();
}

TEST_F(TlsTokens, PlaintextAndUntrustedCertificatesNeverGetThrough) {
  auto plain = v1::KesslerService::NewStub(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
  v1::ListRunsResponse runs;
  auto status = plain->ListRuns(context_with(token["root"]).get(), v1::ListRunsRequest(), &runs);
  EXPECT_FALSE(status.ok());
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAVAILABLE) << status.error_message();
  auto untrusted = v1::KesslerService::NewStub(tls_channel(address, tls_file("other_ca.pem")));
  status = untrusted->ListRuns(context_with(token["root"]).get(), v1::ListRunsRequest(), &runs);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::UNAVAILABLE) << status.error_message();
  // The CLI over plaintext says what is missing rather than that the daemon cannot be reached.
  auto cli_plain = cli(dir, "runs --server " + address + " --token " + token["root"]);
  EXPECT_EQ(cli_plain.exit_code, 1);
  EXPECT_NE(cli_plain.err.find("pass --tls-ca FILE"), std::string::npos) << cli_plain.err;
}

TEST_F(TlsTokens, TheRightTokenWorksThroughTheCli) {
  const std::string server = " --server " + address + " --tls-ca " + tls_file("ca.pem");
  auto refused = cli(dir, "runs" + server);
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("UNAUTHENTICATED"), std::string::npos) << refused.err;
  auto submitted =
      cli(dir, "submit " + test::kTinyScenario + server + " --token " + token["alice"] + " --watch --output json");
  ASSERT_EQ(submitted.exit_code, 0) << submitted.err;
  EXPECT_NE(submitted.last_line().find("\"state\":\"succeeded\""), std::string::npos) << submitted.out;
  auto listed = cli(dir, "runs" + server, "KESSLER_TOKEN=" + token["viewer"]);
  EXPECT_EQ(listed.exit_code, 0) << listed.err;
  EXPECT_NE(listed.out.find("service-tiny"), std::string::npos) << listed.out;
}

TEST_F(TlsTokens, TokensAddedAreTakenOnSighup) {
  const std::string carol = create_token(tokens_file, "carol", "read");
  v1::ListRunsResponse runs;
  EXPECT_EQ(list(carol, runs).error_code(), grpc::StatusCode::UNAUTHENTICATED);
  ::kill(daemon->pid(), SIGHUP);
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!list(carol, runs).ok() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_TRUE(list(carol, runs).ok());
  EXPECT_TRUE(daemon->alive());
}

TEST_F(TlsTokens, ARetriedSubmissionReturnsTheFirstRun) {
  v1::Run first, again, other, bobs;
  ASSERT_TRUE(submit("alice", first, "req-1").ok());
  ASSERT_TRUE(submit("alice", again, "req-1").ok());
  EXPECT_EQ(again.id(), first.id());
  ASSERT_TRUE(submit("alice", other, "req-2").ok());
  EXPECT_NE(other.id(), first.id());
  ASSERT_TRUE(submit("bob", bobs, "req-1").ok());  // request ids are per submitter
  EXPECT_NE(bobs.id(), first.id());
  v1::ListRunsResponse runs;
  ASSERT_TRUE(list(token["root"], runs).ok());
  EXPECT_EQ(runs.runs_size(), 3);
}

TEST_F(TlsTokens, PerTokenLimitsNameTheLimitAndItsValue) {
  daemon.reset();
  start({"--max-runs-per-token", "2", "--max-watches-per-token", "1", "--max-requests-per-s", "1",
         "--runs-at-once", "1"});
  // A long run of the admin's (held by the daemon-wide limits only) keeps the one slot busy, so
  // alice's runs stay queued.
  v1::SubmitRunRequest long_run = tiny_request();
  const std::string text = long_run.scenario_text();
  long_run.set_scenario_text(text.substr(0, text.find("duration_days")) + "duration_days: 4" +
                             text.substr(text.find('\n', text.find("duration_days"))));
  v1::Run run;
  ASSERT_TRUE(stub->SubmitRun(context_with(token["root"]).get(), long_run, &run).ok());
  ASSERT_TRUE(submit("alice", run).ok());
  const std::int64_t first = run.id();
  ASSERT_TRUE(submit("alice", run).ok());
  // The bucket holds 2 s of 1 request/s: the third expensive call at once is refused.
  auto third = submit("alice", run);
  ASSERT_EQ(third.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  std::this_thread::sleep_for(std::chrono::milliseconds(2100));
  third = submit("alice", run);
  ASSERT_EQ(third.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(third.error_message().find("--max-runs-per-token"), std::string::npos) << third.error_message();
  EXPECT_NE(third.error_message().find("limit is 2"), std::string::npos) << third.error_message();

  // One watch stream per token: a second while the first is open is refused.
  v1::WatchRunRequest watch;
  watch.set_run_id(first);
  auto first_context = context_with(token["alice"]);
  first_context->set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
  auto open = stub->WatchRun(first_context.get(), watch);
  v1::RunEvent event;
  ASSERT_TRUE(open->Read(&event));  // the stream is open
  auto second_context = context_with(token["alice"]);
  auto second = stub->WatchRun(second_context.get(), watch);
  while (second->Read(&event)) {
  }
  auto refused = second->Finish();
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(refused.error_message().find("--max-watches-per-token 1"), std::string::npos)
      << refused.error_message();
  first_context->TryCancel();
  open->Finish();
}

TEST_F(TlsTokens, MutualTlsRefusesClientsWithoutACertificate) {
  daemon.reset();
  start({"--tls-client-ca", tls_file("ca.pem")});
  v1::ListRunsResponse runs;
  EXPECT_FALSE(list(token["root"], runs).ok());
  auto with_cert = v1::KesslerService::NewStub(
      tls_channel(address, tls_file("ca.pem"), tls_file("client.pem"), tls_file("client.key")));
  EXPECT_TRUE(with_cert->ListRuns(context_with(token["root"]).get(), v1::ListRunsRequest(), &runs).ok());
}

// Exposure: loopback needs nothing; any other address needs TLS and tokens or --insecure; bad ports
// are refused.
int kesslerd_exit(const TempDir& dir, const std::string& args) {
  const std::string cmd =
      test::bin("kesslerd") + " --db " + dir.path() + "/x.db " + args + " > " + dir.path() + "/x.out 2>&1";
  int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(DaemonExposure, PublicAddressesNeedTlsAndTokensOrInsecure) {
  TempDir dir;
  EXPECT_EQ(kesslerd_exit(dir, "--listen 0.0.0.0:0"), 2);
  EXPECT_NE(test::read_text(dir.path() + "/x.out").find("not loopback"), std::string::npos);
  EXPECT_EQ(kesslerd_exit(dir, "--listen 0.0.0.0:0 --tls-cert " + tls_file("server.pem") + " --tls-key " +
                                   tls_file("server.key")),
            2);  // TLS without tokens
  EXPECT_EQ(kesslerd_exit(dir, "--listen 127.0.0.1:99999"), 2);
  // The dashboard takes no tokens: loopback only, unless --insecure.
  EXPECT_EQ(kesslerd_exit(dir, "--http 0.0.0.0:0"), 2);
  EXPECT_NE(test::read_text(dir.path() + "/x.out").find("--http 0.0.0.0:0 is not loopback"),
            std::string::npos);
  EXPECT_EQ(kesslerd_exit(dir, "--http 127.0.0.1:99999"), 2);
  EXPECT_EQ(kesslerd_exit(dir, "--listen 127.0.0.1:-1"), 2);
  EXPECT_EQ(kesslerd_exit(dir, "--listen 127.0.0.1:5x"), 2);
  EXPECT_EQ(
      kesslerd_exit(dir, "--tls-cert " + tls_file("server.pem") + " --tls-key " + tls_file("client.key")),
      1);  // a key that does not match
}

TEST(DaemonExposure, InsecureWarnsAtStartAndInHealth) {
  TempDir dir;
  Daemon daemon(dir.path() + "/k.db", {"--listen", "0.0.0.0:0", "--insecure"});
  daemon.start();
  EXPECT_NE(daemon.log().find("WARNING: insecure"), std::string::npos) << daemon.log();
  auto health = cli(dir, "health --server " + daemon.address());
  EXPECT_EQ(health.exit_code, 0) << health.err;
  EXPECT_NE(health.out.find("warning: insecure"), std::string::npos) << health.out;
  // Loopback: no warning.
  Daemon local(dir.path() + "/l.db");
  local.start();
  auto quiet = cli(dir, "health --server " + local.address());
  EXPECT_EQ(quiet.out, "SERVING\n");
}

}  // namespace
}  // namespace kessler
