#!/bin/sh
# kessler run --local: a run with checkpoints, then the same run resumed from one of them, must end with
# the same fingerprint. Usage: cli_resume.sh KESSLER SCENARIO
set -e
kessler="$1"
scenario="$2"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fingerprint() { tail -n 1 | grep -o '"events_digest":"[0-9a-f]*","state_digest":"[0-9a-f]*"'; }
whole=$("$kessler" run "$scenario" --local --threads 2 --checkpoint-dir "$dir" --output json | fingerprint)
checkpoint=$(ls "$dir"/checkpoint-*.ckpt | head -n 1)
resumed=$("$kessler" run "$scenario" --local --threads 1 --resume "$checkpoint" --output json | fingerprint)
echo "whole:   $whole"
echo "resumed: $resumed (from $checkpoint)"
test -n "$whole"
test "$whole" = "$resumed"
