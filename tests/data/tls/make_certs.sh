#!/bin/sh
# Test-only TLS material for tests/service/auth_e2e_test.cpp: a CA, a server certificate for
# localhost / 127.0.0.1 and a client certificate (mutual TLS), all signed by the CA and valid for 100
# years. Never use these keys outside the tests. Regenerate with: sh tests/data/tls/make_certs.sh
set -eu
cd "$(dirname "$0")"
days=36500
openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -keyout ca.key -out ca.pem \
  -days $days -subj "/CN=Kessler test CA"
openssl req -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -keyout server.key -out server.csr \
  -subj "/CN=localhost"
printf 'subjectAltName=DNS:localhost,IP:127.0.0.1\nextendedKeyUsage=serverAuth\n' > server.ext
openssl x509 -req -in server.csr -CA ca.pem -CAkey ca.key -CAcreateserial -out server.pem -days $days \
  -extfile server.ext
openssl req -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -keyout client.key -out client.csr \
  -subj "/CN=kessler-test-client"
printf 'extendedKeyUsage=clientAuth\n' > client.ext
openssl x509 -req -in client.csr -CA ca.pem -CAkey ca.key -CAcreateserial -out client.pem -days $days \
  -extfile client.ext
# A second, unrelated CA: a client trusting it must fail the handshake.
openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -keyout other_ca.key \
  -out other_ca.pem -days $days -subj "/CN=Unrelated test CA"
rm -f server.csr client.csr server.ext client.ext ca.srl other_ca.key ca.key
