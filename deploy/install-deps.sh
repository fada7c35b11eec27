#!/usr/bin/env bash
# Installs every Debian 12 package Kessler needs to build, test and run. Idempotent; run as root.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git ca-certificates
  libeigen3-dev libomp-dev
  libprotobuf-dev protobuf-compiler libgrpc++-dev protobuf-compiler-grpc
  libsqlite3-dev sqlite3
  libyaml-cpp-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  clang-format clang-tidy zlib1g-dev libssl-dev
  libsimdjson-dev libpugixml-dev
  nlohmann-json3-dev libcpp-httplib-dev
  libopenmpi-dev openmpi-bin
  chromium chromium-driver
  clang-14 libfuzzer-14-dev ccache
  nlohmann-json3-dev
)
# The web assets' installer; a node from elsewhere (e.g. NodeSource's, which brings its own npm) will do.
command -v npm >/dev/null 2>&1 || packages+=(nodejs npm)

# vega, vega-lite and vega-embed from the npm registry, as pinned by web/package-lock.json; the build
# compiles them into the binaries. Skipped when node_modules already matches the lock file.
install_web_assets() {
  local web lock stamp
  web="$(cd "$(dirname "$0")/.." && pwd)/web"
  if [ ! -f "$web/package-lock.json" ]; then
    echo "install-deps: no web/ beside this script; run it from the source tree for the web assets"
    return 0
  fi
  lock=$(sha256sum "$web/package-lock.json" | cut -d' ' -f1)
  stamp="$web/node_modules/.kessler-lock-sha256"
  if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$lock" ]; then
    echo "install-deps: web assets present (web/node_modules)"
    return 0
  fi
  if ! (cd "$web" && npm ci --no-audit --no-fund); then
    echo "install-deps: 'npm ci' in web/ failed: the charting libraries come from the npm registry" \
         "(registry.npmjs.org or npm's configured registry); without them the build stops" >&2
    exit 1
  fi
  echo "$lock" >"$stamp"
}

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  install_web_assets
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then exec sudo -E bash "$0" "$@"; fi
  echo "install-deps: missing ${missing[*]}; run this script as root" >&2
  exit 1
fi

export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: installed ${missing[*]}"
install_web_assets
