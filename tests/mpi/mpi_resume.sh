#!/bin/sh
# A run checkpointed under 2 ranks, resumed under 3 ranks and under 1 (kessler-mpi) and by kessler run
# --local, must end with the fingerprint of the uninterrupted run without MPI.
# Usage: mpi_resume.sh KESSLER KESSLER_MPI MPIEXEC SCENARIO
. "$(dirname "$0")/common.sh"
export OMP_NUM_THREADS=1
whole=$("$kessler" run "$scenario" --local --threads 2 --output json | fingerprint)
under2=$("$mpiexec" -np 2 "$kessler_mpi" "$scenario" --threads 1 --checkpoint-dir "$dir" --output json | fingerprint)
checkpoint=$(ls "$dir"/checkpoint-*.ckpt | head -n 1)
test -n "$checkpoint"
under3=$("$mpiexec" -np 3 "$kessler_mpi" "$scenario" --threads 1 --resume "$checkpoint" --output json | fingerprint)
under1=$("$mpiexec" -np 1 "$kessler_mpi" "$scenario" --threads 1 --resume "$checkpoint" --output json | fingerprint)
local=$("$kessler" run "$scenario" --local --threads 2 --resume "$checkpoint" --output json | fingerprint)
echo "whole, no MPI:              $whole"
echo "2 ranks with checkpoints:   $under2"
echo "resumed under 3 ranks:      $under3 (from $checkpoint)"
echo "resumed under 1 rank:       $under1"
echo "resumed by kessler run:     $local"
test -n "$whole"
test "$under2" = "$whole"
test "$under3" = "$whole"
test "$under1" = "$whole"
test "$local" = "$whole"
