#!/bin/sh
# kessler-mpi's cost per object-step and communication share on a synthetic population of 1-10 cm debris
# in LEO (300..2,000 km, radii 0.5..5 cm), as rank and thread counts change. Each configuration prints
# kessler-mpi's --timing line: ns per object-step of the step loop (the slowest rank's), the mean share of
# the loop spent in MPI calls (gathers, and the waits for the slowest rank inside them), peak memory per
# rank and per object.
# Usage: mpi_scaling.sh KESSLER_MPI OBJECTS STEPS "RANKSxTHREADS ..." (e.g. "1x2 2x1 4x1")
set -e
kessler_mpi="$1"
objects="${2:-100000}"
steps="${3:-20}"
configs="${4:-1x2 2x1}"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# Ranks waiting in a collective call yield their core (on a machine shared with other work a spinning rank
# takes the core the rank it waits for needs). On dedicated cluster nodes, OMPI_MCA_mpi_yield_when_idle=0.
export OMPI_MCA_mpi_yield_when_idle=${OMPI_MCA_mpi_yield_when_idle:-1}
cat >"$dir/scenario.yaml" <<YAML
name: mpi-scaling-${objects}
start_epoch: "2022-01-01T00:00:00Z"
duration_days: $(awk "BEGIN { printf \"%.9f\", ($steps + 0.5) * 30 / 86400 }")
dt_s: 30
population:
  synthetic: {objects: ${objects}, active_fraction: 0, min_altitude_km: 300, max_altitude_km: 2000}
  rules:
    small_radius_mean_m: 0.025
    small_radius_stddev_m: 0.012
    medium_radius_mean_m: 0.025
    medium_radius_stddev_m: 0.012
    large_radius_mean_m: 0.025
    large_radius_stddev_m: 0.012
checkpoints: {every_steps: 0, every_wall_s: 0}
progress_every_steps: 1000000   # progress lines cost a pass over the population: not what is measured
seed: 3
YAML
for config in $configs; do
  ranks=${config%x*}
  threads=${config#*x}
  OMP_NUM_THREADS=$threads OMP_PROC_BIND=false mpirun -np "$ranks" --bind-to none "$kessler_mpi" \
    "$dir/scenario.yaml" --threads "$threads" --output json --timing 2>&1 >"$dir/out.jsonl" | grep mpi_timing
  # Rank 0's phase timers (integrator: its share and the gathers; grid and detection: its scans).
  tail -n 1 "$dir/out.jsonl" | grep -o '"events":[0-9]*\|"events_digest":"[0-9a-f]*"\|"timers_s":{[^}]*}' | tr '\n' ' '
  echo
done
