// The daemon's security parts on their own: SHA-256 against FIPS 180-2's test vectors, the tokens file,
// roles, listen addresses and the per-token limits.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "server/auth.hpp"
#include "server/limits.hpp"
#include "server/transport.hpp"
#include "tests/service/temp_dir.hpp"

namespace kessler::server {
namespace {

TEST(Auth, Sha256MatchesTheStandardsVectors) {
  // FIPS 180-2, appendix B.1 and B.2.
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

TEST(Auth, CreatedTokensAuthenticateWithTheirRole) {
  kessler::TempDir dir;
  const std::string path = dir.path() + "/tokens";
  const std::string alice = create_token(path, "alice", Role::kSubmit);
  const std::string root = create_token(path, "root", Role::kAdmin);
  EXPECT_EQ(alice.size(), 4u + 64u);
  EXPECT_NE(alice, root);
  struct stat info {};
  ASSERT_EQ(::stat(path.c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 0777, 0600u);
  EXPECT_THROW(create_token(path, "alice", Role::kRead), std::runtime_error);  // taken
  EXPECT_THROW(create_token(path, "a b", Role::kRead), std::runtime_error);

  Authenticator auth(path);
  EXPECT_EQ(auth.size(), 2u);
  auto caller = auth.authenticate("Bearer " + alice);
  ASSERT_TRUE(caller);
  EXPECT_EQ(caller->name, "alice");
  EXPECT_EQ(caller->role, Role::kSubmit);
  EXPECT_TRUE(caller->owns_only());
  EXPECT_TRUE(auth.authenticate("bearer " + root));
  EXPECT_FALSE(auth.authenticate(std::nullopt));
  EXPECT_FALSE(auth.authenticate(alice));  // no scheme
  EXPECT_FALSE(auth.authenticate("Bearer " + alice.substr(1)));
  EXPECT_THROW(admit_caller(auth, "Bearer " + alice, Role::kAdmin), AccessError);
  EXPECT_EQ(admit_caller(auth, "Bearer " + alice, Role::kSubmit).name, "alice");

  // Without a tokens file every caller is the anonymous admin.
  Authenticator open;
  auto anonymous = open.authenticate(std::nullopt);
  ASSERT_TRUE(anonymous);
  EXPECT_EQ(anonymous->role, Role::kAdmin);
  EXPECT_TRUE(anonymous->anonymous);
}

TEST(Auth, BadTokenFilesAreRefusedNamingTheLine) {
  kessler::TempDir dir;
  const std::string path = dir.path() + "/tokens";
  const std::string hash = "sha256:" + std::string(64, 'a');
  const std::vector<std::string> bad_lines = {"alice superuser " + hash, "alice read sha256:abc",
                                              "alice read", "alice read " + hash + "\nalice admin " + hash};
  for (const std::string& bad : bad_lines) {
    std::ofstream(path) << "# comment\n\n" << bad << "\n";
    try {
      read_tokens_file(path);
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("line "), std::string::npos) << e.what();
    }
  }
  // A reload that fails keeps the tokens loaded before.
  const std::string good = create_token(dir.path() + "/ok", "ok", Role::kRead);
  Authenticator auth(dir.path() + "/ok");
  std::ofstream(dir.path() + "/ok") << "garbage\n";
  EXPECT_THROW(auth.reload(), std::runtime_error);
  EXPECT_TRUE(auth.authenticate("Bearer " + good));
}

TEST(Transport, ListenAddressesAndLoopback) {
  std::string error;
  auto ok = parse_listen_address("127.0.0.1:50051", error);
  ASSERT_TRUE(ok);
  EXPECT_EQ(ok->port, 50051);
  EXPECT_TRUE(parse_listen_address("[::1]:0", error));
  for (const char* bad :
       {"127.0.0.1:99999", "127.0.0.1:-1", "127.0.0.1:", "127.0.0.1", ":80", "h:1.5", "h:8o"})
    EXPECT_FALSE(parse_listen_address(bad, error)) << bad;
  for (const char* host : {"127.0.0.1", "127.1.2.3", "localhost", "[::1]"})
    EXPECT_TRUE(is_loopback_host(host)) << host;
  for (const char* host : {"0.0.0.0", "[::]", "10.0.0.1", "127.0.0.1.example.com", "example.com", ""})
    EXPECT_FALSE(is_loopback_host(host)) << host;
}

TEST(Limits, RunsWatchesAndRequestRatesPerToken) {
  LimitOptions options;
  options.runs_per_token = 3;
  options.watches_per_token = 2;
  options.watches = 3;
  options.requests_per_s_per_token = 5;  // bursts of 10
  Limits limits(options);
  const Caller alice{"alice", Role::kSubmit, false};
  const Caller bob{"bob", Role::kRead, false};
  const Caller admin{"root", Role::kAdmin, false};
  EXPECT_NO_THROW(limits.check_runs(alice, 2, 1));
  EXPECT_THROW(limits.check_runs(alice, 3, 1), LimitError);
  EXPECT_THROW(limits.check_runs(alice, 0, 4), LimitError);  // an ensemble too large at once
  EXPECT_NO_THROW(limits.check_runs(admin, 1000, 1000));

  int taken = 0;
  try {
    for (; taken < 100; ++taken) limits.take_request(alice);
  } catch (const LimitError& e) {
    EXPECT_NE(std::string(e.what()).find("--max-requests-per-s"), std::string::npos);
  }
  EXPECT_EQ(taken, 10);
  EXPECT_NO_THROW(limits.take_request(bob));  // buckets are per token
  std::this_thread::sleep_for(std::chrono::milliseconds(250));
  EXPECT_NO_THROW(limits.take_request(alice));  // refilled at 5 per second

  {
    Limits::Watch a(limits, alice), b(limits, alice);
    EXPECT_THROW(Limits::Watch(limits, alice), LimitError);
    Limits::Watch c(limits, bob);
    EXPECT_EQ(limits.watches_open(), 3u);
    EXPECT_THROW(Limits::Watch(limits, admin), LimitError);  // the daemon-wide cap holds everyone
  }
  EXPECT_EQ(limits.watches_open(), 0u);
  Limits::Watch again(limits, alice);
}

}  // namespace
}  // namespace kessler::server
