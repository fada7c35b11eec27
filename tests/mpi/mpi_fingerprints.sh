#!/bin/sh
# kessler-mpi under mpirun with each rank count given must print what `kessler run --local` prints: the
# same event lines (encounters, burn-ups, breakups, launches, ...) in the same order and the same summary
# fingerprint (events_digest, state_digest). Progress and summary lines carry wall-clock figures: they are
# compared by their fingerprint alone.
# Usage: mpi_fingerprints.sh KESSLER KESSLER_MPI MPIEXEC SCENARIO RANKS... ($THREADS per rank, default 1)
set -e
kessler="$1"
kessler_mpi="$2"
mpiexec="$3"
scenario="$4"
shift 4
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
# Root may launch ranks in a test container; more ranks than cores; idle ranks yield their core.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_mpi_yield_when_idle=1
export OMPI_MCA_rmaps_base_oversubscribe=1
events() { grep -v '^{"type":"\(progress\|summary\)"' || true; }
fingerprint() { tail -n 1 | grep -o '"events_digest":"[0-9a-f]*","state_digest":"[0-9a-f]*"'; }
"$kessler" run "$scenario" --local --threads 2 --output json >"$dir/reference.jsonl"
reference=$(fingerprint <"$dir/reference.jsonl")
echo "kessler run --local:  $reference ($(grep -c '' "$dir/reference.jsonl") lines)"
test -n "$reference"
threads=${THREADS:-1}
for ranks in "$@"; do
  OMP_NUM_THREADS=$threads "$mpiexec" -np "$ranks" "$kessler_mpi" "$scenario" --threads "$threads" --output json \
    >"$dir/ranks-$ranks.jsonl"
  got=$(fingerprint <"$dir/ranks-$ranks.jsonl")
  echo "kessler-mpi, $ranks ranks of $threads threads: $got"
  test "$got" = "$reference"
  events <"$dir/reference.jsonl" >"$dir/reference.events"
  events <"$dir/ranks-$ranks.jsonl" >"$dir/ranks-$ranks.events"
  if ! cmp -s "$dir/reference.events" "$dir/ranks-$ranks.events"; then
    echo "the event lines differ under $ranks ranks:"
    diff "$dir/reference.events" "$dir/ranks-$ranks.events" | head -n 20
    exit 1
  fi
done
