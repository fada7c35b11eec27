#!/usr/bin/env python3
"""Step-independence of two runs' events (CSV from `kessler-bench run --events-out FILE`).

Every encounter closer than --below-m (4900) in one file must have a partner in the other: same pair,
TCA within --tca-s (1 s), miss distance within --miss-m (5 m). Checked in both directions. Prints the
counts and the worst differences; exits 1 when the check fails.

    python3 tests/speed/compare_events.py a.csv b.csv
"""
import argparse
import bisect
import collections
import csv
import sys


def read(path):
    by_pair = collections.defaultdict(list)
    events = []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            e = (int(row["id1"]), int(row["id2"]), float(row["tca_s"]), float(row["miss_m"]))
            events.append(e)
            by_pair[(e[0], e[1])].append(e)
    for v in by_pair.values():
        v.sort(key=lambda e: e[2])
    return events, by_pair


def check(src, dst_by_pair, below, tca_tol, miss_tol):
    required = missing = off = 0
    worst = worst_tca = 0.0
    examples = []
    for e in src:
        if e[3] >= below:
            continue
        required += 1
        cands = dst_by_pair.get((e[0], e[1]), [])
        times = [c[2] for c in cands]
        k = bisect.bisect_left(times, e[2])
        best = None
        for c in cands[max(0, k - 1):k + 1]:
            if abs(c[2] - e[2]) <= tca_tol and (best is None or abs(c[2] - e[2]) < abs(best[2] - e[2])):
                best = c
        if best is None:
            missing += 1
            if len(examples) < 5:
                examples.append(f"missing: {e}")
            continue
        d = abs(best[3] - e[3])
        worst = max(worst, d)
        worst_tca = max(worst_tca, abs(best[2] - e[2]))
        if d > miss_tol:
            off += 1
            if len(examples) < 5:
                examples.append(f"miss differs by {d:.3f} m: {e} vs {best}")
    return required, missing, off, worst, worst_tca, examples


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("a")
    p.add_argument("b")
    p.add_argument("--below-m", type=float, default=4900.0)
    p.add_argument("--tca-s", type=float, default=1.0)
    p.add_argument("--miss-m", type=float, default=5.0)
    args = p.parse_args()
    a, a_pairs = read(args.a)
    b, b_pairs = read(args.b)
    ok = True
    for name, src, dst in ((f"{args.a} -> {args.b}", a, b_pairs), (f"{args.b} -> {args.a}", b, a_pairs)):
        req, missing, off, worst, worst_tca, examples = check(src, dst, args.below_m, args.tca_s, args.miss_m)
        print(f"{name}: {len(src)} events, {req} below {args.below_m:g} m, {missing} missing, "
              f"{off} with miss off by > {args.miss_m:g} m, worst miss difference {worst:.3f} m, "
              f"worst TCA difference {worst_tca:.3g} s")
        for x in examples:
            print("   ", x)
        ok = ok and missing == 0 and off == 0
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
