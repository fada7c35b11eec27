#!/bin/sh
# kessler run --local --output json of the shipped constellations scenario: launch lines for the inline
# plan's 322 objects of the first day (and the named plans' few), their ids counted from 2000000000 without
# gaps; the demonstration mission's 20 ends of life, each followed by its disposal's outcome; a summary
# whose final count holds every launched object (less burn-ups). Usage: cli_constellations.sh KESSLER SCENARIO
set -e
kessler="$1"
scenario="$2"
out=$("$kessler" run "$scenario" --local --threads 2 --output json)
launches=$(printf '%s\n' "$out" | grep '^{"type":"launch",' || true)
test -n "$launches"
printf '%s\n' "$launches" | head -n 3
launched=$(printf '%s\n' "$launches" | sed 's/.*"objects":\([0-9]*\).*/\1/' | awk '{ n += $1 } END { print n }')
last=$(printf '%s\n' "$launches" | tail -n 1 | sed 's/.*"last_id":\([0-9]*\).*/\1/')
echo "launched $launched objects, last id $last"
test "$launched" -ge 322
test "$last" -eq $((2000000000 + launched - 1))
ends=$(printf '%s\n' "$out" | grep -c '^{"type":"end_of_life",' || true)
outcomes=$(printf '%s\n' "$out" | grep -c '^{"type":"\(disposal\|disposal_failed\|deorbit\)",' || true)
echo "ends of life $ends, disposal outcomes $outcomes"
test "$ends" -eq 20
test "$outcomes" -eq 20
summary=$(printf '%s\n' "$out" | tail -n 1)
echo "$summary"
echo "$summary" | grep -q '"type":"summary",.*"objects_initial":1000,'
final=$(echo "$summary" | sed 's/.*"objects_final":\([0-9]*\).*/\1/')
burnt=$(echo "$summary" | sed 's/.*"burn_ups":\([0-9]*\).*/\1/')
echo "objects at the end $final, burnt up $burnt"
test $((final + burnt)) -eq $((1000 + launched))  # disposals keep their objects (no de-orbits here)
