#!/usr/bin/env bash
# Thread scaling of the propagator, the detector and the whole simulation on leo-19647 (and a larger
# synthetic population), for the README's scaling table. Usage:
#   tests/bench/thread_scaling.sh [BENCH_BINARY] [THREAD_COUNTS...]
# Defaults: build/bin/kessler-bench, threads 1 2 4 8 16. Prints one JSON line per run to stdout (the
# benchmark's own last line) and a table of speed-ups over 1 thread (median of the repeats) last.
set -euo pipefail
bench=${1:-build/bin/kessler-bench}
shift || true
threads=("$@")
[ ${#threads[@]} -gt 0 ] || threads=(1 2 4 8 16)
# OpenMP's own wait policy (spin a while, then sleep) suits a dedicated machine; on a host shared with
# other work, run with OMP_WAIT_POLICY=passive.
export OMP_PROC_BIND=${OMP_PROC_BIND:-close} OMP_PLACES=${OMP_PLACES:-cores}
results=$(mktemp)

run() {  # name threads args...
  local name=$1 t=$2
  shift 2
  local line
  line=$("$bench" "$@" --threads "$t" | tail -1)
  echo "$line"
  printf '%s\t%s\t%s\n' "$name" "$t" "$line" >>"$results"
}

# Where the machine puts its cores (a line that changes cores, read and written): multi-core figures
# follow it, and on a VM it can change between runs.
"$bench" cores | tail -1

for t in "${threads[@]}"; do
  run propagate "$t" propagate --objects 20000 --steps 200 --repeats 7
  run detect "$t" conjunctions --objects 19647 --steps 200 --repeats 5
  # The team scan, one step at a time over all threads (the default scans a step per thread side by
  # side: core/simulation/steps_in_flight.hpp); the 1-thread row is the same path for both.
  run detect-team "$t" conjunctions --objects 19647 --steps 200 --repeats 5 --steps-at-once 1
  run run-kappa10 "$t" run --dataset leo-19647 --days 0.25 --kappa 10
  run run-kappa10-team "$t" run --dataset leo-19647 --days 0.25 --kappa 10 --steps-at-once 1
  run run-synthetic-320k "$t" run --dataset synthetic --objects 320000 --days 0.005
done

python3 - "$results" <<'EOF'
import json, sys
rows = {}
for line in open(sys.argv[1]):
    name, t, js = line.rstrip("\n").split("\t", 2)
    d = json.loads(js)
    wall = d.get("detect_s") if name.startswith("detect") else d.get("wall_s")
    rows.setdefault(name, {})[int(t)] = wall
threads = sorted({t for r in rows.values() for t in r})
print("| benchmark | " + " | ".join(f"{t} thr" for t in threads) + " |")
print("|---|" + "---|" * len(threads))
for name, r in rows.items():
    base = r.get(1)
    cells = []
    for t in threads:
        w = r.get(t)
        cells.append("" if w is None else f"{w:.3f} s ({base / w:.2f}x)" if base else f"{w:.3f} s")
    print(f"| {name} | " + " | ".join(cells) + " |")
EOF
rm -f "$results"
