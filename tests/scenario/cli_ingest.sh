#!/bin/sh
# kessler run --local of a catalog, with the global --output before the command and --threads 0 (all
# cores): the first JSON line is the ingest report, whose records are the kept objects plus the drops, and
# whose drag sources count every kept object once; encounters carry both objects' names. Usage: cli_ingest.sh KESSLER SCENARIO
set -e
kessler="$1"
scenario="$2"
out=$("$kessler" --output json run "$scenario" --local --threads 0)
first=$(printf '%s\n' "$out" | head -n 1)
echo "$first"
case "$first" in
  '{"type":"ingest",'*) ;;
  *) echo "the first line is not the ingest report"; exit 1 ;;
esac
records=$(echo "$first" | sed 's/.*"records":\([0-9]*\).*/\1/')
kept=$(echo "$first" | sed 's/.*"kept":\([0-9]*\).*/\1/')
sum_of() { echo "$first" | sed "s/.*\"$1\":{\([^}]*\)}.*/\1/" | tr ',' '\n' | sed 's/.*://' | awk '{s += $1} END {print s + 0}'; }
dropped=$(sum_of dropped)
drag=$(sum_of drag)
echo "records $records, kept $kept, dropped $dropped, drag sources $drag"
test "$records" -eq $((kept + dropped))
test "$kept" -eq "$drag"
echo "$first" | grep -q '"excluded name":2'
echo "$first" | grep -q '"rejected: checksum":1'
printf '%s\n' "$out" | grep -q '"id1":29,"id2":99999,"name1":"TIROS 1","name2":"KESSLER TWIN"'
printf '%s\n' "$out" | tail -n 1 | grep -q '"type":"summary"'
