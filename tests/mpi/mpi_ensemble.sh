#!/bin/sh
# kessler-mpi on a scenario with ensemble.members 3: member k's line (seed base + k, fingerprint) equals
# `kessler run --local` of the member's own scenario (the ensemble dropped, the seed set to base + k),
# with the members spread over 2 and 3 groups of one rank and over one group of 2 ranks (a third rank
# idle); more ranks per member than the job has: exit 2.
# Usage: mpi_ensemble.sh KESSLER KESSLER_MPI MPIEXEC SCENARIO (SCENARIO without ensemble or seed lines)
. "$(dirname "$0")/common.sh"
export OMP_NUM_THREADS=1
base_seed=21
(grep -v '^\(seed\|ensemble\):' "$scenario"; echo "seed: $base_seed"; echo "ensemble: {members: 3}") \
  >"$dir/ensemble.yaml"
: >"$dir/expected"
for k in 0 1 2; do
  grep -v '^\(seed\|ensemble\):' "$scenario" >"$dir/member-$k.yaml"
  echo "seed: $((base_seed + k))" >>"$dir/member-$k.yaml"
  got=$("$kessler" run "$dir/member-$k.yaml" --local --threads 2 --output json | tail -n 1 | fingerprint)
  test -n "$got"
  echo "\"member\":$k,\"seed\":$((base_seed + k)) $got" >>"$dir/expected"
done
cat "$dir/expected"
members() { sed 's/.*\("member":[0-9]*,"seed":[0-9]*\).*\("events_digest".*"state_digest":"[0-9a-f]*"\).*/\1 \2/'; }
# "-": the default, ranks / members rounded down, at least 1.
for run in "2 -" "3 -" "3 2"; do
  ranks=${run% *}
  per_member=${run#* }
  if test "$per_member" = "-"; then
    "$mpiexec" -np "$ranks" "$kessler_mpi" "$dir/ensemble.yaml" --threads 1 --output json >"$dir/got.jsonl"
  else
    "$mpiexec" -np "$ranks" "$kessler_mpi" "$dir/ensemble.yaml" --ranks-per-member "$per_member" --threads 1 \
      --output json >"$dir/got.jsonl"
  fi
  members <"$dir/got.jsonl" >"$dir/got"
  echo "$ranks ranks, $per_member per member:"
  cat "$dir/got"
  cmp "$dir/expected" "$dir/got"
done
code=0
out=$("$mpiexec" -np 2 "$kessler_mpi" "$dir/ensemble.yaml" --ranks-per-member 4 2>&1) || code=$?
echo "$out" | head -n 3
test "$code" -eq 2
echo "$out" | grep -q -- '--ranks-per-member 4 is more than the job.s 2 ranks'
