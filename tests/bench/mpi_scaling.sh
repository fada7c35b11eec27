#!/usr/bin/env bash
# Rank scaling of kessler-mpi (built with -DKESSLER_MPI=ON), for the README's table of 1 to 16 ranks:
# `kessler-bench mpi` at each rank count R (ranks of one thread each, and one rank of R threads in turn,
# on the benchmark's synthetic 1-10 cm debris). Usage:
#   tests/bench/mpi_scaling.sh [BENCH_BINARY] [RANK_COUNTS...]
# Defaults: build/bin/kessler-bench, ranks 1 2 4 8 16. OBJECTS, STEPS and REPEATS (environment) default
# to 1000000, 10 and 3. Prints each benchmark's JSON line, then a table of speed-ups over one rank of one
# thread (medians of the repeats), and the shares of a rank's loop in its part of the propagation, of
# the scan and in MPI calls. Run it on a machine with as many cores as the largest rank count:
# with fewer, the ranks share cores and the figures say nothing of scaling.
set -euo pipefail
bench=${1:-build/bin/kessler-bench}
shift || true
ranks=("$@")
[ ${#ranks[@]} -gt 0 ] || ranks=(1 2 4 8 16)
objects=${OBJECTS:-1000000} steps=${STEPS:-10} repeats=${REPEATS:-3}
results=$(mktemp)
trap 'rm -f "$results"' EXIT

for r in "${ranks[@]}"; do
  line=$("$bench" mpi --ranks "$r" --threads 1 --objects "$objects" --steps "$steps" --repeats "$repeats" |
    tail -1)
  echo "$line"
  echo "$line" >>"$results"
done

python3 - "$results" <<'EOF'
import json, sys
rows = sorted((json.loads(line) for line in open(sys.argv[1])), key=lambda d: d["ranks"])
base = next((d["ns_per_object_step"] for d in rows if d["ranks"] == 1), None)
print("| ranks | ns / object-step | speed-up over 1 rank | 1 rank of as many threads "
      "| propagation / scan / MPI share | RSS / object |")
print("|---|---|---|---|---|---|")
for d in rows:
    ns = d["ns_per_object_step"]
    speed_up = f"{base / ns:.2f}x" if base else ""
    print(f"| {d['ranks']} | {ns:.1f} ({d['ns_per_object_step_min']:.1f}-{d['ns_per_object_step_max']:.1f}) "
          f"| {speed_up} | {d['one_rank_ns_per_object_step']:.1f} ns "
          f"| {100 * d['propagate_share']:.0f} / {100 * d['scan_share']:.0f} / {100 * d['mpi_share']:.1f} % "
          f"| {d['peak_rss_bytes_per_object']:.0f} B |")
EOF
