// Who is calling: bearer tokens from a tokens file (kept as SHA-256 hashes, never in clear), their roles,
// and what each role may call. No gRPC here: the API layer hands over the "authorization" metadata.
#pragma once

#include <cstddef>
#include <optional>
#include <shared_mutex>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace kessler::server {

// read: list and read every run and ensemble (dashboards, monitoring). submit: submit, and list, read,
// cancel, resume and delete its own runs and ensembles only. admin: everything, on every run.
enum class Role { kRead = 1, kSubmit = 2, kAdmin = 3 };

const char* role_name(Role role);
std::optional<Role> parse_role(std::string_view text);

// The caller of one request. Without a tokens file every caller is the anonymous admin (name "").
struct Caller {
  std::string name;
  Role role = Role::kAdmin;
  bool anonymous = true;
  // Whether the caller sees and changes only its own runs.
  bool owns_only() const { return role == Role::kSubmit; }
};

// A call refused for who makes it: unauthenticated (no token, or an unknown one) or not allowed.
struct AccessError : std::runtime_error {
  AccessError(bool unauthenticated_, const std::string& message)
      : std::runtime_error(message), unauthenticated(unauthenticated_) {}
  bool unauthenticated;
};

// The caller of a request with this "authorization" metadata, allowed calls needing `needed`; throws
// AccessError otherwise.
Caller admit_caller(const class Authenticator& auth, std::optional<std::string_view> authorization,
                    Role needed);

// Lowercase hex of the SHA-256 of `data` (OpenSSL).
std::string sha256_hex(std::string_view data);

struct TokenEntry {
  std::string name;  // 1..64 of [A-Za-z0-9._-], unique in the file
  Role role = Role::kRead;
  std::string sha256;  // lowercase hex of the token's SHA-256
};

// The tokens file: one token a line, "NAME ROLE sha256:HEX"; blank lines and lines starting with '#'
// are skipped. Throws std::runtime_error naming the line at fault.
std::vector<TokenEntry> read_tokens_file(const std::string& path);
// Adds a token named `name` with `role` to the file (created 0600 when missing) and returns it in clear
// ("kst_" and 64 hex digits from OpenSSL's RAND_bytes); only its hash is written. Throws
// std::runtime_error for a bad or taken name or a file it cannot write.
std::string create_token(const std::string& path, const std::string& name, Role role);
bool valid_token_name(std::string_view name);

class Authenticator {
 public:
  // `tokens_path` empty: no tokens, every call is the anonymous admin. Otherwise reads the file (throws
  // std::runtime_error when it cannot).
  explicit Authenticator(std::string tokens_path = {});

  bool enabled() const { return !path_.empty(); }
  // Reads the tokens file again (SIGHUP). On an error the tokens already loaded stay and it throws.
  void reload();
  std::size_t size() const;
  // The caller whose "authorization" metadata value is `authorization` ("Bearer TOKEN"); nullopt when
  // tokens are enabled and it is missing, malformed or unknown.
  std::optional<Caller> authenticate(std::optional<std::string_view> authorization) const;

 private:
  std::string path_;
  mutable std::shared_mutex mutex_;
  std::unordered_map<std::string, TokenEntry> by_hash_;
};

}  // namespace kessler::server
