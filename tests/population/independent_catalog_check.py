#!/usr/bin/python3
"""Independent route to the catalog-2022 ingest figures that tests/population checks.

Uses only the Python standard library and python3-sgp4 (Debian package; Vallado's SGP4 in its
official Python port), not the project's code. Run from the repository root:

    /usr/bin/python3 tests/population/independent_catalog_check.py

It reads the 3LE catalog, the Space-Track SATCAT (gzip) and the CelesTrak active list, applies the
paper's rules as the project documents them (element sets repeated from an earlier record dropped as docked;
name exclusions ISS (*), STARLINK*, ONEWEB*; perigee
>= 175 km and apogee <= 2000 km of the SGP4 mean elements over 6378.135 km; SGP4 to
2022-01-01T00:00:00Z; active = on the active list), and the radius/mass rules with the documented
counter-based generator (SplitMix64 finaliser, Box-Muller), re-implemented here from the spec.
"""
import csv, fnmatch, gzip, io, math, statistics, sys
from sgp4.api import Satrec, jday

ROOT = 'deploy/datasets/catalog/'
M64 = (1 << 64) - 1

def mix64(z):
    z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & M64
    z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & M64
    return z ^ (z >> 31)

def bits(seed, oid, purpose, counter):
    h = mix64((seed + 0x9E3779B97F4A7C15) & M64)
    h = mix64(h ^ ((oid + 0x632BE59BD9B4E019) & M64))
    h = mix64(h ^ ((purpose * 0x8CB92BA72F3D8DD7) & M64))
    return mix64(h ^ ((counter + 0xD6E8FEB86659FD93) & M64))

def uniform(seed, oid, purpose, counter):
    return ((bits(seed, oid, purpose, counter) >> 11) + 0.5) * 2.0 ** -53

def normal(seed, oid, purpose, k):
    u1, u2 = uniform(seed, oid, purpose, 2 * k), uniform(seed, oid, purpose, 2 * k + 1)
    return math.sqrt(-2.0 * math.log(u1)) * math.cos(2.0 * math.pi * u2)

CLASSES = {'SMALL': (0.09, 0.04), 'MEDIUM': (0.37, 0.10), 'LARGE': (1.30, 0.60)}

def radius(size_class, seed, oid):
    mean, sd = CLASSES.get(size_class, CLASSES['MEDIUM'])
    for k in range(64):
        r = mean + sd * normal(seed, oid, 1, k)
        if r >= 0.005:
            return r
    return 0.005

def mass(r):
    v = 4.0 / 3.0 * math.pi * r ** 3
    return v * 2698.9 if r <= 0.01 else v * 92.937 * (2 * r) ** -0.74

def checksum_ok(line):
    s = sum(int(c) if c.isdigit() else (1 if c == '-' else 0) for c in line[:68])
    return line[68].isdigit() and s % 10 == int(line[68])

lines = open(ROOT + 'spacetrack_3le_2022-01-22_ODAP.txt', newline='').read().splitlines()
satcat = {}
with gzip.open(ROOT + 'spacetrack_satcat_2021-01-19.csv.gz', 'rt', newline='') as f:
    for row in csv.DictReader(f):
        satcat[int(row['NORAD_CAT_ID'])] = row
active_ids = set()
with open(ROOT + '2026-03-10_celestrak_active_gp.csv', newline='') as f:
    for row in csv.DictReader(f):
        active_ids.add(int(row['NORAD_CAT_ID']))

records = bad = 0
seen_sets = set()
counts = dict.fromkeys(['docked', 'excluded name', 'perigee below band', 'apogee above band', 'SGP4 failed',
                        'decayed before the start'], 0)
jd, fr = jday(2022, 1, 1, 0, 0, 0)
kept = {'active': [], 'passive': []}
samples = {}
for i in range(0, len(lines), 3):
    name, l1, l2 = lines[i][2:].strip(), lines[i + 1], lines[i + 2]
    records += 1
    if not (checksum_ok(l1) and checksum_ok(l2)):
        bad += 1
        continue
    sat = Satrec.twoline2rv(l1, l2)
    key = (l1[18:32], l2[8:63])  # epoch and the mean elements, as written
    if key in seen_sets:
        counts['docked'] += 1
        continue
    seen_sets.add(key)
    if any(fnmatch.fnmatchcase(name.upper(), p) for p in ['ISS (*)', 'STARLINK*', 'ONEWEB*']):
        counts['excluded name'] += 1
        continue
    a_km = sat.a * 6378.135
    if a_km * (1 - sat.ecco) - 6378.135 < 175.0:
        counts['perigee below band'] += 1
        continue
    if a_km * (1 + sat.ecco) - 6378.135 > 2000.0:
        counts['apogee above band'] += 1
        continue
    e, r, v = sat.sgp4(jd, fr)
    if e != 0:
        counts['SGP4 failed'] += 1
        continue
    if math.sqrt(sum(x * x for x in r)) * 1000.0 < 6378137.0 + 150e3:  # the simulation's burn-up test
        counts['decayed before the start'] += 1
        continue
    oid = sat.satnum
    size = satcat.get(oid, {}).get('RCS_SIZE', '')
    rad = radius(size, 1, oid)
    status = 'active' if oid in active_ids else 'passive'
    kept[status].append((rad, mass(rad), a_km))
    if oid in (5, 11, 22675, 43013):
        samples[oid] = (r, v)

print('records', records, 'rejected', bad, 'accepted', records - bad)
for k, n in counts.items():
    print('filtered', k, n)
print('kept', len(kept['active']) + len(kept['passive']), 'active', len(kept['active']), 'passive', len(kept['passive']))
for s in ('active', 'passive'):
    rs, ms, as_ = zip(*kept[s])
    print(s, 'median radius %.9f mass %.9f sma %.6f' % (statistics.median(rs), statistics.median(ms), statistics.median(as_)))
for oid, (r, v) in sorted(samples.items()):
    print('state', oid, ' '.join('%.6f' % x for x in r), ' '.join('%.9f' % x for x in v))
