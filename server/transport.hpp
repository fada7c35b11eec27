// How the daemon faces the network: its listening address (host and port checked), whether that is
// loopback, and the TLS material read and checked at start (OpenSSL) rather than at the first handshake.
#pragma once

#include <optional>
#include <string>

namespace kessler::server {

struct ListenAddress {
  std::string host;  // as given, brackets kept for IPv6 ("[::1]")
  int port = 0;      // 0..65535; 0 picks a free one
};

// "HOST:PORT" with a port of 0..65535 in decimal; nullopt with `error` set otherwise.
std::optional<ListenAddress> parse_listen_address(const std::string& text, std::string& error);
// 127.0.0.0/8, ::1 and "localhost": reachable from this machine only.
bool is_loopback_host(const std::string& host);

struct TlsFiles {
  std::string cert;       // PEM certificate chain of the server
  std::string key;        // PEM private key
  std::string client_ca;  // PEM CA bundle: clients must present a certificate it signed (mutual TLS)
};

struct TlsMaterial {
  std::string cert_pem;
  std::string key_pem;
  std::string client_ca_pem;  // empty: no client certificates asked for
};

// Reads the files and checks that the key matches the certificate and that the CA bundle parses;
// throws std::runtime_error naming the file at fault.
TlsMaterial load_tls(const TlsFiles& files);

}  // namespace kessler::server
