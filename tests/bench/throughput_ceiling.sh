#!/usr/bin/env bash
# The most a machine's cores can give a parallel run: K single-thread copies of one run at once, each
# pinned to its own CPU, against the same run alone. Perfectly parallel work on K threads reaches at
# best K x (alone / together). Usage:
#   tests/bench/throughput_ceiling.sh [BENCH_BINARY] [K]
# Defaults: build/bin/kessler-bench, K = the number of CPUs. Prints each copy's wall seconds and, last,
# the ceiling from the median and from the slowest copy (a step waits for its slowest thread).
set -euo pipefail
bench=${1:-build/bin/kessler-bench}
k=${2:-$(nproc)}
args=(run --dataset leo-19647 --days 0.25 --kappa 10 --threads 1)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
taskset -c 0 "$bench" "${args[@]}" | tail -1 >"$dir/alone.json"
for ((c = 0; c < k; c++)); do taskset -c "$c" "$bench" "${args[@]}" | tail -1 >"$dir/$c.json" & done
wait
python3 - "$dir" "$k" <<'PY'
import json, statistics, sys
d, k = sys.argv[1], int(sys.argv[2])
alone = json.load(open(f"{d}/alone.json"))["wall_s"]
together = [json.load(open(f"{d}/{c}.json"))["wall_s"] for c in range(k)]
print("alone %.3f s; together: %s" % (alone, " ".join("%.3f" % w for w in together)))
print("ceiling on %d threads: %.1fx (median copy), %.1fx (slowest copy)"
      % (k, k * alone / statistics.median(together), k * alone / max(together)))
PY
