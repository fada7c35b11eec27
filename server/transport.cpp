#include "server/transport.hpp"

#include <openssl/bio.h>
#include <openssl/pem.h>
#include <openssl/x509.h>

#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace kessler::server {
namespace {

std::string read_file(const std::string& path, const char* what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(std::string(what) + " " + path + ": cannot read");
  std::ostringstream text;
  text << in.rdbuf();
  if (text.str().size() > (1 << 20)) throw std::runtime_error(std::string(what) + " " + path + ": over 1 MB");
  return text.str();
}

using Bio = std::unique_ptr<BIO, decltype(&BIO_free)>;

Bio bio_of(const std::string& pem) {
  return Bio(BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size())), &BIO_free);
}

}  // namespace

std::optional<ListenAddress> parse_listen_address(const std::string& text, std::string& error) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0) {
    error = "--listen must be HOST:PORT";
    return std::nullopt;
  }
  ListenAddress out;
  out.host = text.substr(0, colon);
  const std::string port = text.substr(colon + 1);
  if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos ||
      std::stol(port) > 65535) {
    error = "--listen port must be 0..65535, got '" + port.substr(0, 16) + "'";
    return std::nullopt;
  }
  out.port = static_cast<int>(std::stol(port));
  return out;
}

bool is_loopback_host(const std::string& host) {
  if (host == "localhost" || host == "[::1]" || host == "::1") return true;
  // 127.0.0.0/8 in dotted decimal.
  if (host.rfind("127.", 0) != 0) return false;
  int parts = 2;  // "127." holds the first dot
  for (char c : host.substr(4)) {
    if (c == '.')
      ++parts;
    else if (c < '0' || c > '9')
      return false;
  }
  return parts == 4;
}

TlsMaterial load_tls(const TlsFiles& files) {
  TlsMaterial out;
  out.cert_pem = read_file(files.cert, "--tls-cert");
  out.key_pem = read_file(files.key, "--tls-key");
  auto cert_bio = bio_of(out.cert_pem);
  std::unique_ptr<X509, decltype(&X509_free)> cert(
      PEM_read_bio_X509(cert_bio.get(), nullptr, nullptr, nullptr), &X509_free);
  if (!cert) throw std::runtime_error("--tls-cert " + files.cert + ": not a PEM certificate");
  auto key_bio = bio_of(out.key_pem);
  std::unique_ptr<EVP_PKEY, decltype(&EVP_PKEY_free)> key(
      PEM_read_bio_PrivateKey(key_bio.get(), nullptr, nullptr, nullptr), &EVP_PKEY_free);
  if (!key) throw std::runtime_error("--tls-key " + files.key + ": not a PEM private key (or encrypted)");
  if (X509_check_private_key(cert.get(), key.get()) != 1)
    throw std::runtime_error("--tls-key " + files.key + ": does not match the certificate " + files.cert);
  if (!files.client_ca.empty()) {
    out.client_ca_pem = read_file(files.client_ca, "--tls-client-ca");
    auto ca_bio = bio_of(out.client_ca_pem);
    std::unique_ptr<X509, decltype(&X509_free)> ca(PEM_read_bio_X509(ca_bio.get(), nullptr, nullptr, nullptr),
                                                   &X509_free);
    if (!ca) throw std::runtime_error("--tls-client-ca " + files.client_ca + ": not a PEM certificate");
  }
  return out;
}

}  // namespace kessler::server
