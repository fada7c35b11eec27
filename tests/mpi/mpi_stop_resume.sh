#!/bin/sh
# SIGTERM to the ranks after the run's first checkpoint (as srun and scancel deliver it; OpenMPI's mpirun
# does not pass it on at once, it ends the job): every rank stops at the same step after writing a
# checkpoint (exit 1, no rank left waiting); the run resumed from its last checkpoint under another rank
# count ends with the fingerprint of the uninterrupted run without MPI (nothing lost, nothing twice: the
# events digest chains every event). Usage: mpi_stop_resume.sh KESSLER KESSLER_MPI MPIEXEC SCENARIO
. "$(dirname "$0")/common.sh"
export OMP_NUM_THREADS=1
"$mpiexec" -np 2 "$kessler_mpi" "$scenario" --threads 1 --checkpoint-dir "$dir" --output json \
  >"$dir/stopped.jsonl" &
pid=$!
tries=0
until grep -q '^{"type":"checkpoint"' "$dir/stopped.jsonl" 2>/dev/null; do
  tries=$((tries + 1))
  test $tries -lt 600 || { echo "no checkpoint after 60 s"; kill $pid; exit 1; }
  sleep 0.1
done
# The ranks are mpirun's children. Rank 0 alone is signalled: the ranks agree on the signals once a step.
rank0=$(pgrep -P $pid | head -n 1)
test -n "$rank0"
kill -TERM "$rank0"
code=0
wait $pid || code=$?
stopped_at=$(tail -n 1 "$dir/stopped.jsonl" | sed 's/.*"steps":\([0-9]*\).*/\1/')
echo "stopped: exit $code at step $stopped_at"
test "$code" -eq 1
checkpoint=$(ls "$dir"/checkpoint-*.ckpt | sort -t- -k2 -n | tail -n 1)
echo "resuming from $checkpoint under 3 ranks"
test "$checkpoint" = "$dir/checkpoint-$stopped_at.ckpt"
resumed=$("$mpiexec" -np 3 "$kessler_mpi" "$scenario" --threads 1 --resume "$checkpoint" --output json | fingerprint)
whole=$("$kessler" run "$scenario" --local --threads 2 --output json | fingerprint)
echo "resumed: $resumed"
echo "whole:   $whole"
test -n "$whole"
test "$resumed" = "$whole"
