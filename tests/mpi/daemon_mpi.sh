#!/bin/sh
# kesslerd --mpi-launcher: a run submitted to the daemon and computed by an MPI job of 2 ranks has the
# fingerprint (events_digest, state_digest) and the stored conjunctions of `kessler run --local`, and
# the population snapshots a daemon without MPI stores; a job
# that refuses the run (more ranks than objects) fails the run with kessler-mpi's message; a cancel
# reaches the ranks; a rank killed mid-run makes the daemon compute the run again from its checkpoint
# (--mpi-retries), killed again it fails the run with the job's end named, and `kessler resume` then ends
# it with the fingerprint of the run without MPI.
# A daemon stopped mid-run leaves the run resumable: the next one ends it with the fingerprint of the run
# without MPI. A launcher whose hostfile is missing fails the run with its message, and the daemon serves
# on. Bad --mpi-* flags: exit 2 naming the flag.
# Usage: daemon_mpi.sh KESSLER KESSLERD KESSLER_MPI MPIEXEC SCENARIO LONG_SCENARIO [LAUNCHER]
# LAUNCHER (default "MPIEXEC --oversubscribe --allow-run-as-root -np 2") starts the 2 ranks, e.g.
# "srun -n 2 --mpi=pmix" under Slurm.
set -e
kessler="$1"
kesslerd="$2"
kessler_mpi="$3"
mpiexec="$4"
scenario="$5"
long_scenario="$6"
launcher_line="${7:-$mpiexec --oversubscribe --allow-run-as-root -np 2}"
dir=$(mktemp -d)
daemon=""
cleanup() {
  test -n "$daemon" && kill "$daemon" 2>/dev/null && wait "$daemon" 2>/dev/null
  rm -rf "$dir"
}
trap cleanup EXIT
export OMPI_MCA_mpi_yield_when_idle=1 OMP_NUM_THREADS=1
fingerprint() { tail -n 1 | grep -o '"events_digest":"[0-9a-f]*","state_digest":"[0-9a-f]*"'; }

start_daemon() {
  rm -f "$dir/port"
  "$kesslerd" --db "$dir/k.db" --listen 127.0.0.1:0 --port-file "$dir/port" --threads 1 \
    --mpi-launcher "$launcher_line" --mpi-program "$kessler_mpi" \
    --mpi-work-dir "$dir" --mpi-retries 1 2>>"$dir/daemon.log" &
  daemon=$!
  tries=0
  until test -s "$dir/port"; do
    tries=$((tries + 1))
    test $tries -lt 300 || { echo "kesslerd did not start"; cat "$dir/daemon.log"; exit 1; }
    sleep 0.1
  done
  export KESSLER_SERVER="127.0.0.1:$(cat "$dir/port")"
}
wait_running() {
  tries=0
  until "$kessler" show "$1" --output json | head -n 1 | grep -q '"RUN_STATE_RUNNING"'; do
    tries=$((tries + 1))
    test $tries -lt 600 || { echo "run $1 did not start"; exit 1; }
    sleep 0.1
  done
}
# 0. Bad flags: exit 2 with the flag named.
bad_flags() {  # EXPECTED_MESSAGE FLAGS...
  expected="$1"
  shift
  code=0
  out=$("$kesslerd" --db "$dir/never.db" "$@" 2>&1) || code=$?
  echo "$out"
  test "$code" -eq 2
  echo "$out" | grep -q -- "$expected"
}
bad_flags '--mpi-launcher: an unclosed "' --mpi-launcher 'mpirun "-np'
bad_flags '--mpi-launcher: no launcher command' --mpi-launcher ''
bad_flags "--mpi-program: $dir/none is not an" --mpi-launcher mpirun --mpi-program "$dir/none"
bad_flags '--mpi-program, --mpi-work-dir and --mpi-retries need --mpi-launcher' --mpi-work-dir "$dir"
bad_flags '--mpi-retries needs an integer 0..100' --mpi-launcher mpirun --mpi-retries -1
test ! -e "$dir/never.db"

start_daemon

# 1. The fingerprint and the stored conjunctions of the run without MPI.
"$kessler" run "$scenario" --local --threads 1 --output json >"$dir/local.jsonl"
reference=$(fingerprint <"$dir/local.jsonl")
local_conjunctions=$(grep -c '^{"type":"\(conjunction\|collision\)"' "$dir/local.jsonl")
"$kessler" submit "$scenario" --watch --output json >"$dir/submitted.jsonl"
got=$(fingerprint <"$dir/submitted.jsonl")
echo "kessler run --local:         $reference, $local_conjunctions conjunctions"
echo "kesslerd on 2 MPI ranks:     $got"
test -n "$reference"
test "$got" = "$reference"
run=$(tail -n 1 "$dir/submitted.jsonl" | sed 's/.*"run_id":\([0-9]*\).*/\1/')
"$kessler" show "$run" --output json | tail -n 1 | fingerprint >"$dir/shown"
test "$(cat "$dir/shown")" = "$reference"
stored=$("$kessler" conjunctions "$run" --output json | grep -o '"seq":' | wc -l)
echo "stored conjunctions:         $stored"
test "$stored" -eq "$local_conjunctions"
test "$(ls "$dir" | grep -c kesslerd-mpi-)" -eq 0  # the run's directory is gone
# The population snapshots the ranks took are those a daemon without MPI stores.
"$kessler" snapshot "$run" --list --output json >"$dir/mpi-snapshots"
"$kessler" snapshot "$run" --output csv >"$dir/mpi-newest.csv"
plain_server=$KESSLER_SERVER
"$kesslerd" --db "$dir/plain.db" --listen 127.0.0.1:0 --port-file "$dir/plain-port" --threads 1 \
  2>>"$dir/daemon.log" &
plain=$!
tries=0
until test -s "$dir/plain-port"; do
  tries=$((tries + 1))
  test $tries -lt 300 || { echo "the second kesslerd did not start"; exit 1; }
  sleep 0.1
done
export KESSLER_SERVER="127.0.0.1:$(cat "$dir/plain-port")"
plain_run=$("$kessler" submit "$scenario" --watch --output json | tail -n 1 | sed 's/.*"run_id":\([0-9]*\).*/\1/')
"$kessler" snapshot "$plain_run" --list --output json >"$dir/plain-snapshots"
"$kessler" snapshot "$plain_run" --output csv >"$dir/plain-newest.csv"
kill "$plain"
wait "$plain" || true
export KESSLER_SERVER="$plain_server"
echo "snapshots: $(grep -o '"step"' "$dir/mpi-snapshots" | wc -l), newest $(wc -l <"$dir/mpi-newest.csv") rows"
test "$(wc -l <"$dir/mpi-newest.csv")" -gt 1
cmp "$dir/mpi-snapshots" "$dir/plain-snapshots"
cmp "$dir/mpi-newest.csv" "$dir/plain-newest.csv"

# 2. More ranks than objects: the run fails with kessler-mpi's message.
sed 's/objects: [0-9]*/objects: 1/' "$scenario" >"$dir/one.yaml"
code=0
"$kessler" submit "$dir/one.yaml" --watch --output json >"$dir/one.jsonl" 2>&1 || code=$?
cat "$dir/one.jsonl" | tail -n 2
test "$code" -eq 1
grep -q '2 MPI ranks for 1 objects' "$dir/one.jsonl"
refused=$(grep -o '"run_id":[0-9]*' "$dir/one.jsonl" | head -n 1 | grep -o '[0-9]*$')
test -n "$refused"
if grep -q "run $refused: MPI job lost" "$dir/daemon.log"; then  # a refusal is not computed again
  echo "the refused run $refused was computed again"
  exit 1
fi

# 3. A cancel stops the ranks: the run ends cancelled and the job's processes are gone.
run=$("$kessler" submit "$long_scenario" --output json | grep -o '"run_id": *[0-9]*' | grep -o '[0-9]*$')
wait_running "$run"
sleep 1
"$kessler" cancel "$run" >/dev/null
tries=0
until "$kessler" show "$run" --output json | head -n 1 | grep -q '"RUN_STATE_CANCELLED"'; do
  tries=$((tries + 1))
  test $tries -lt 600 || { echo "the run was not cancelled"; "$kessler" show "$run"; exit 1; }
  sleep 0.1
done
echo "cancelled run $run"
test -z "$(pgrep -P "$daemon")"

# 4. A rank killed mid-run: the daemon computes the run again from its last checkpoint (--mpi-retries 1);
# a rank of that job killed too, the run fails naming the job's end; `kessler resume` then ends it with
# the fingerprint of the run without MPI.
run=$("$kessler" submit "$long_scenario" --output json | grep -o '"run_id": *[0-9]*' | grep -o '[0-9]*$')
# The ranks are kessler-mpi processes (mpirun's children; under Slurm, slurmstepd's). The ranks seen when
# one was killed are left out the next time, so the second kill hits the job that computes the run again.
ranks_of_jobs() { pgrep -f "^$kessler_mpi .*$dir/kesslerd-mpi-" || true; }
kill_a_rank() {  # OLD_LAUNCHER OLD_RANKS: a rank of the next launcher's job, killed; prints the launcher and its ranks
  tries=0
  rank=""
  until test -n "$rank"; do
    tries=$((tries + 1))
    test $tries -lt 600 || { echo "no ranks" >&2; exit 1; }
    sleep 0.1
    launcher=$(pgrep -P "$daemon" | head -n 1)
    test -n "$launcher" && test "$launcher" != "$1" || continue
    rank=$(ranks_of_jobs | grep -vxF -e "$2" -e "none" | tail -n 1)  # the newest (highest pid)
  done
  sleep 1
  seen=$(ranks_of_jobs | tr '\n' ' ')
  kill -KILL "$rank"
  echo "$launcher $seen"
}
first=$(kill_a_rank "" "")
first_launcher=${first%% *}
first_ranks=$(echo "${first#* }" | tr ' ' '\n' | grep . || true)
kill_a_rank "$first_launcher" "$first_ranks" >/dev/null
code=0
"$kessler" watch "$run" --output json >"$dir/killed.jsonl" 2>&1 || code=$?
tail -n 1 "$dir/killed.jsonl"
test "$code" -eq 1
grep -q 'the MPI job ended without the run' "$dir/killed.jsonl"
grep "run $run: MPI job lost" "$dir/daemon.log"
grep -q "run $run: MPI job lost; computing the run again from its last checkpoint (retry 1 of 1): the MPI job ended" \
  "$dir/daemon.log"
test -z "$(pgrep -P "$daemon")"
# kessler resume: the failed run continues (from its last checkpoint) to the fingerprint of the run
# without MPI.
whole=$("$kessler" run "$long_scenario" --local --threads 1 --output json | fingerprint)
test -n "$whole"
"$kessler" resume "$run"
"$kessler" watch "$run" --output json >"$dir/killed-resumed.jsonl"
echo "killed twice, then resumed: $(fingerprint <"$dir/killed-resumed.jsonl")"
test "$(fingerprint <"$dir/killed-resumed.jsonl")" = "$whole"

# 5. The daemon stopped mid-run (SIGTERM): the ranks stop after a checkpoint, the run stays resumable,
# and the next daemon resumes it from the stored checkpoint to the fingerprint of the run without MPI.
run=$("$kessler" submit "$long_scenario" --output json | grep -o '"run_id": *[0-9]*' | grep -o '[0-9]*$')
wait_running "$run"
sleep 2
kill -TERM "$daemon"
wait "$daemon"
daemon=""
start_daemon
"$kessler" watch "$run" --output json >"$dir/resumed.jsonl"
grep "run $run" "$dir/daemon.log"
grep -q "run $run from the checkpoint at step [1-9][0-9]*: MPI job: .*--resume" "$dir/daemon.log"
resumed=$(fingerprint <"$dir/resumed.jsonl")
echo "resumed by the next daemon: $resumed"
echo "kessler run --local:        $whole"
test "$resumed" = "$whole"

# 6. A hostfile the launcher cannot open (mpirun only): the run fails with the launcher's message (after
# the one retry), the daemon keeps serving, and the runs stored before are intact.
if test -z "$7"; then
  kill -TERM "$daemon"
  wait "$daemon"
  daemon=""
  launcher_line="$mpiexec --oversubscribe --allow-run-as-root -np 2 --hostfile $dir/no-such-hosts"
  start_daemon
  code=0
  "$kessler" submit "$scenario" --watch --output json >"$dir/hostfile.jsonl" 2>&1 || code=$?
  tail -n 1 "$dir/hostfile.jsonl"
  test "$code" -eq 1
  grep -q "unable to open the hostfile" "$dir/hostfile.jsonl"
  "$kessler" show "$run" --output json | tail -n 1 | fingerprint >"$dir/shown-after"
  test "$(cat "$dir/shown-after")" = "$whole"
fi
echo "ok"
