#!/bin/sh
# kessler-mpi under mpirun with each rank count given must print what `kessler run --local` prints: the
# same event lines (encounters, burn-ups, breakups, launches, ...) in the same order and the same summary
# fingerprint (events_digest, state_digest). Progress and summary lines carry wall-clock figures: they are
# compared by their fingerprint alone.
# Usage: mpi_fingerprints.sh KESSLER KESSLER_MPI MPIEXEC SCENARIO RANKS... ($THREADS per rank, default 1)
. "$(dirname "$0")/common.sh"
shift 4
events() { grep -v '^{"type":"\(progress\|summary\)"' || true; }
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
