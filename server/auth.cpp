#include "server/auth.hpp"

#include <fcntl.h>
#include <openssl/evp.h>
#include <openssl/rand.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <mutex>
#include <sstream>
#include <stdexcept>

namespace kessler::server {
namespace {

constexpr std::string_view kHashPrefix = "sha256:";

std::string to_hex(const unsigned char* bytes, std::size_t n) {
  static const char* const kDigits = "0123456789abcdef";
  std::string out;
  out.reserve(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    out += kDigits[bytes[i] >> 4];
    out += kDigits[bytes[i] & 15];
  }
  return out;
}

bool is_hex64(std::string_view s) {
  return s.size() == 64 && s.find_first_not_of("0123456789abcdef") == std::string_view::npos;
}

}  // namespace

const char* role_name(Role role) {
  switch (role) {
    case Role::kRead:
      return "read";
    case Role::kSubmit:
      return "submit";
    case Role::kAdmin:
      return "admin";
  }
  return "?";
}

std::optional<Role> parse_role(std::string_view text) {
  if (text == "read") return Role::kRead;
  if (text == "submit") return Role::kSubmit;
  if (text == "admin") return Role::kAdmin;
  return std::nullopt;
}

std::string sha256_hex(std::string_view data) {
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int length = 0;
  if (EVP_Digest(data.data(), data.size(), digest.data(), &length, EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("SHA-256 failed (OpenSSL)");
  return to_hex(digest.data(), length);
}

bool valid_token_name(std::string_view name) {
  return !name.empty() && name.size() <= 64 &&
         name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-") ==
             std::string_view::npos;
}

std::vector<TokenEntry> read_tokens_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("tokens file " + path + ": cannot read (" + std::strerror(errno) + ")");
  std::vector<TokenEntry> entries;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto where = [&] { return "tokens file " + path + " line " + std::to_string(number) + ": "; };
    std::istringstream words(line);
    std::string name, role, hash, extra;
    if (!(words >> name) || name[0] == '#') continue;
    if (!(words >> role >> hash) || (words >> extra))
      throw std::runtime_error(where() + "expected NAME ROLE sha256:HEX");
    TokenEntry entry;
    if (!valid_token_name(name)) throw std::runtime_error(where() + "bad name (1..64 of A-Z a-z 0-9 . _ -)");
    auto parsed = parse_role(role);
    if (!parsed) throw std::runtime_error(where() + "role must be read, submit or admin");
    if (hash.rfind(kHashPrefix, 0) != 0 || !is_hex64(std::string_view(hash).substr(kHashPrefix.size())))
      throw std::runtime_error(where() + "hash must be sha256: and 64 lowercase hex digits");
    for (const TokenEntry& e : entries)
      if (e.name == name) throw std::runtime_error(where() + "name " + name + " appears twice");
    entry.name = name;
    entry.role = *parsed;
    entry.sha256 = hash.substr(kHashPrefix.size());
    entries.push_back(std::move(entry));
  }
  return entries;
}

std::string create_token(const std::string& path, const std::string& name, Role role) {
  if (!valid_token_name(name)) throw std::runtime_error("token name: 1..64 of A-Z a-z 0-9 . _ -");
  struct stat info {};
  if (::stat(path.c_str(), &info) == 0) {
    for (const TokenEntry& e : read_tokens_file(path))
      if (e.name == name) throw std::runtime_error("token name " + name + " is taken in " + path);
  }
  std::array<unsigned char, 32> secret{};
  if (RAND_bytes(secret.data(), static_cast<int>(secret.size())) != 1)
    throw std::runtime_error("cannot draw random bytes (OpenSSL RAND_bytes)");
  std::string token = "kst_" + to_hex(secret.data(), secret.size());
  const std::string line =
      name + " " + role_name(role) + " " + std::string(kHashPrefix) + sha256_hex(token) + "\n";
  const int fd = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0600);
  if (fd < 0)
    throw std::runtime_error("tokens file " + path + ": cannot write (" + std::strerror(errno) + ")");
  const ssize_t written = ::write(fd, line.data(), line.size());
  const bool closed = ::close(fd) == 0;
  if (written != static_cast<ssize_t>(line.size()) || !closed)
    throw std::runtime_error("tokens file " + path + ": write failed");
  return token;
}

Authenticator::Authenticator(std::string tokens_path) : path_(std::move(tokens_path)) {
  if (enabled()) reload();
}

void Authenticator::reload() {
  if (!enabled()) return;
  std::unordered_map<std::string, TokenEntry> fresh;
  for (TokenEntry& e : read_tokens_file(path_)) fresh.emplace(e.sha256, std::move(e));
  std::unique_lock lock(mutex_);
  by_hash_ = std::move(fresh);
}

std::size_t Authenticator::size() const {
  std::shared_lock lock(mutex_);
  return by_hash_.size();
}

std::optional<Caller> Authenticator::authenticate(std::optional<std::string_view> authorization) const {
  if (!enabled()) return Caller{};
  if (!authorization) return std::nullopt;
  std::string_view value = *authorization;
  constexpr std::string_view kScheme = "bearer ";
  if (value.size() <= kScheme.size() || value.size() > 512) return std::nullopt;
  for (std::size_t i = 0; i < kScheme.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(value[i])) != kScheme[i]) return std::nullopt;
  const std::string hash = sha256_hex(value.substr(kScheme.size()));
  std::shared_lock lock(mutex_);
  auto it = by_hash_.find(hash);
  if (it == by_hash_.end()) return std::nullopt;
  return Caller{it->second.name, it->second.role, false};
}

Caller admit_caller(const Authenticator& auth, std::optional<std::string_view> authorization, Role needed) {
  std::optional<Caller> caller = auth.authenticate(authorization);
  if (!caller)
    throw AccessError(true, authorization
                                ? "unknown token (authorization: Bearer TOKEN)"
                                : "a token is required (authorization: Bearer TOKEN; kessler --token)");
  if (static_cast<int>(caller->role) < static_cast<int>(needed))
    throw AccessError(false, std::string("token '") + caller->name + "' has role " + role_name(caller->role) +
                                 "; this call needs " + role_name(needed));
  return *caller;
}

}  // namespace kessler::server
