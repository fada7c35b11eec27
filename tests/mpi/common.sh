# Sourced by the MPI test scripts, whose first arguments are KESSLER KESSLER_MPI MPIEXEC SCENARIO: those
# four as variables, a scratch directory removed at exit, OpenMPI set for one machine (root may launch
# ranks in a test container, more ranks than cores, idle ranks yield their core), and `fingerprint`,
# which reads the events_digest and state_digest of the last line of a `--output json` run.
set -e
kessler="$1"
kessler_mpi="$2"
mpiexec="$3"
scenario="$4"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_mpi_yield_when_idle=1
export OMPI_MCA_rmaps_base_oversubscribe=1
fingerprint() { tail -n 1 | grep -o '"events_digest":"[0-9a-f]*","state_digest":"[0-9a-f]*"'; }
