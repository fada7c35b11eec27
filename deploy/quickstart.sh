#!/usr/bin/env bash
# The README's first command, on a fresh Debian 12 (as root, or a user with sudo):
#   installs the dependencies, builds (Release), starts kesslerd in the background on its SQLite
#   database (var/kessler.db), submits a three-hour screening of the real 2022 catalog at 5 km (as
#   CelesTrak's SOCRATES screens it), streams the conjunctions live, then prints the run's summary, how
#   to query it, how to run the paper's scenario next and how to stop the daemon.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
server=${KESSLER_SERVER:-127.0.0.1:50051}
scenario=${1:-deploy/scenarios/catalog-screening.yaml}

echo "== 1/4 dependencies"
deploy/install-deps.sh

echo "== 2/4 build (Release)"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target kesslerd kessler
kessler="$root/build/bin/kessler"

echo "== 3/4 kesslerd"
mkdir -p var
if "$kessler" runs --server "$server" --limit 1 >/dev/null 2>&1; then
  echo "kesslerd already serving on $server"
else
  nohup build/bin/kesslerd --listen "$server" --db var/kessler.db >var/kesslerd.log 2>&1 &
  echo $! >var/kesslerd.pid
  for _ in $(seq 1 100); do
    "$kessler" runs --server "$server" --limit 1 >/dev/null 2>&1 && break
    sleep 0.1
  done
  "$kessler" runs --server "$server" --limit 1 >/dev/null || { cat var/kesslerd.log; exit 1; }
  echo "kesslerd $(cat var/kesslerd.pid) serving on $server, database var/kessler.db, log var/kesslerd.log"
fi

echo "== 4/4 run $scenario"
run=$("$kessler" submit "$scenario" --server "$server" --output json | sed -n 's/.*"run_id": *\([0-9]*\).*/\1/p')
[ -n "$run" ] || { echo "submit failed" >&2; exit 1; }
echo "run $run submitted; streaming it live (Ctrl-C stops watching, not the run)"
status=0
"$kessler" watch "$run" --events all --server "$server" || status=$?

cat <<EOT

Run $run is stored in var/kessler.db. Next:
  build/bin/kessler show $run --server $server                      # scenario, timers, counts by kappa
  build/bin/kessler conjunctions $run --kappa-max 1 --closest-per-pair --server $server
  build/bin/kessler conjunctions $run --output csv --server $server > conjunctions.csv
  build/bin/kessler runs --server $server
The paper's scenario next (the 2022 catalog with its filters, kappa_max 10; one day, then 20 years):
  build/bin/kessler submit deploy/scenarios/paper-1day.yaml --watch --server $server
  build/bin/kessler submit deploy/scenarios/paper.yaml --server $server
Stop the daemon (running runs checkpoint and resume at the next start):
  kill \$(cat var/kesslerd.pid)
EOT
exit $status
