#!/bin/sh
# kessler run --local of the shipped Iridium 33 / Cosmos 2251 replay: both objects ingested, both broken
# up at 16:56 into floor(0.1 * 1510^0.75 * 0.1^-1.71) = 1242 fragments (M = 560 + 950 kg, catastrophic),
# each either still in the run at its end or burnt up before. Usage: cli_iridium_cosmos.sh KESSLER SCENARIO
set -e
kessler="$1"
scenario="$2"
out=$("$kessler" --output json run "$scenario" --local --threads 1)
printf '%s\n' "$out" | head -n 1 | grep -q '"records":2,"kept":2'
summary=$(printf '%s\n' "$out" | tail -n 1)
echo "$summary"
echo "$summary" | grep -q '"type":"summary",.*"collisions":0,.*"objects_initial":2,'
final=$(echo "$summary" | sed 's/.*"objects_final":\([0-9]*\).*/\1/')
burnt=$(echo "$summary" | sed 's/.*"burn_ups":\([0-9]*\).*/\1/')
echo "objects at the end $final, burnt up $burnt"
test $((final + burnt)) -eq 1242
