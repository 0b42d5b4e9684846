#!/usr/bin/env python3
"""springpend tests (issue 28): the seventeenth attacker's pass
(doc/notes/2026-11-27/attack17.md), finding 6: sweep --merge's row checks,
the ones that must hold when a forger edits a shard's rows and recomputes
its SHA-256 (schema:sha256, a checksum, not a signature) and row count
(dc:extent), covered Lyapunov and basins only. A spectrum shard with rows
swapped, copied over or dropped, a precession shard missing a point, an
orbit shard with a row copied (two equal times), rows dropped or a whole
point dropped merged, exit 0. Now each measure has a row rule
(doc/sweeps.md, "Past one machine: shards"): spectrum rows at exactly the
renormalisation times T of the checkpoints, in order; precession, lyapunov
and basins one row per point; a driven orbit's rows at every sampled
t = k/f; an undriven orbit's and a Poincare mosaic's times strictly
ascending; and every point present, a point without a crossing (or a
sample) writing one row of its own (t = T0 + T, the values nan), as a point
that blew up writes one of nan. A forged shard is refused with
FILE:LINE, exit 2, nothing written; honest shards still merge into the
one-piece run's CSV. The expected times are computed here from the
description (checkpoints k = round(10^(i/10)), t = k/f), not read back.
usage: test_attack17_merge_rows.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import hashlib
import os
import re

import sptest
from sptest import done, err, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack17-merge-rows")

# name: (scene, the sweep's arguments); each in two shards
SWEEPS = {
    "spectrum": ("chaotic.ini", ["--vary", "initial.angle=10:170:6", "--measure", "spectrum",
                                 "--time", "4"]),
    "precession": ("swinging-spring.ini", ["--vary", "initial.angle=3:6:4", "--measure",
                                           "precession", "--time", "100"]),
    "orbit": ("parametric.ini", ["--vary", "pivot.amplitude=0.05:0.2:4", "--measure", "orbit",
                                 "--time", "30"]),
    "peak": ("parametric.ini", ["--vary", "pivot.amplitude=0.05:0.2:4", "--measure", "orbit",
                                "--time", "30", "--peak", "theta"]),
    "undriven": ("chaotic.ini", ["--vary", "initial.angle=0:170:6", "--measure", "orbit",
                                 "--time", "30"]),
    "poincare": ("chaotic.ini", ["--vary", "initial.angle=60:120:6", "--measure", "poincare",
                                 "--time", "30"]),
    "lyapunov": ("chaotic.ini", ["--vary", "initial.angle=10:170:6", "--measure", "lyapunov",
                                 "--time", "4"]),
    "basins": ("parametric.ini", ["--vary", "initial.angle=-90:90:4", "--vary",
                                  "initial.length_rate=-1:1:3", "--measure", "basins",
                                  "--time", "20"]),
}


def rows_of(name):
    """A CSV's rows (after its column names) as lists of fields."""
    lines = open(path(name)).read().split("\n")
    return [line.split(",") for line in lines[1:] if line]


def sweep(name):
    """The one-piece run's CSV and two shards' of sweep name; True when all ran."""
    scene, args = SWEEPS[name]
    base = [os.path.join(scenes, scene), *args, "-q"]
    r = [run("sweep", *base, "--csv", f"{name}_whole.csv", "-o", f"{name}_whole.png")]
    r += [run("sweep", *base, "--shard", f"{i}/2", "--csv", f"{name}{i}.csv") for i in (1, 2)]
    return ok(all(x.returncode == 0 for x in r),
              f"{name}: the one-piece sweep and its two shards run "
              f"({[x.returncode for x in r]} {err(r[-1])[:200]})")


def forge(name, edit):
    """Shard 1 of sweep name with its rows (lists of fields) edited by
    edit(rows) -> rows, and its SHA-256 and row count recomputed as a forger
    would, as f_NAME1.csv and its metadata."""
    lines = open(path(f"{name}1.csv")).read().split("\n")
    rows = edit([line.split(",") for line in lines[1:] if line])
    data = "\n".join([lines[0]] + [",".join(x) for x in rows]) + "\n"
    forged = f"f_{name}1.csv"
    open(path(forged), "w").write(data)
    meta = open(path(f"{name}1.csv-metadata.json")).read()
    meta = re.sub(r'"schema:sha256": "[0-9a-f]+"',
                  '"schema:sha256": "%s"' % hashlib.sha256(data.encode()).hexdigest(), meta)
    meta = re.sub(r'"dc:extent": \d+', '"dc:extent": %d' % len(rows), meta)
    meta = meta.replace(f'"{name}1.csv"', f'"{forged}"')
    open(path(forged + "-metadata.json"), "w").write(meta)
    return forged


def merge(first, second, out):
    """sweep --merge of two shards into OUT.png and OUT.csv (any OUT.* gone first)."""
    for f in os.listdir(work):
        if f.startswith(out + "."):
            os.remove(path(f))
    return run("sweep", "--merge", first, second, "-o", f"{out}.png", "--csv", f"{out}.csv", "-q")


def refused(name, what, edit):
    """The merge of a forged shard 1 and the honest shard 2: exit 2,
    FILE:LINE naming the forged file, nothing written."""
    forged = forge(name, edit)
    r = merge(forged, f"{name}2.csv", "fm")
    e = err(r)
    written = [f for f in os.listdir(work) if f.startswith("fm.") or f.endswith(".part")]
    ok(r.returncode == 2 and re.match(r"springpend: %s:\d+: " % re.escape(forged), e) and
       not written, f"{name}, {what}: refused, exit 2, FILE:LINE, nothing written "
       f"(exit {r.returncode}: {e[:260]}; written: {written})")


def point_rows(rows, p):
    return [x for x in rows if x[0] == str(p)]


def drop_point(p):
    return lambda rows: [x for x in rows if x[0] != str(p)]


def copy_over(i, j):
    def edit(rows):
        rows[j] = list(rows[i])
        return rows
    return edit


def swap(i, j):
    def edit(rows):
        rows[i], rows[j] = rows[j], rows[i]
        return rows
    return edit


def delete(a, b=None):
    def edit(rows):
        del rows[a:(a + 1 if b is None else b)]
        return rows
    return edit


def insert_copy(i):
    def edit(rows):
        rows.insert(i + 1, list(rows[i]))
        return rows
    return edit


def first_index(rows, p):
    return next(i for i, x in enumerate(rows) if x[0] == str(p))


for name in SWEEPS:
    if not sweep(name):
        continue
    # honest shards merge into the one-piece run's CSV, byte for byte
    r = merge(f"{name}1.csv", f"{name}2.csv", "hm")
    same = r.returncode == 0 and open(path("hm.csv")).read() == \
        open(path(f"{name}_whole.csv")).read()
    ok(same, f"{name}: the honest shards merge (exit {r.returncode}) into the one-piece CSV "
       f"{err(r)[:200]}")

# ---- the rows the sweeps write, against expectations computed here --------

# spectrum, rk4 at dt = 0.001: tau = 1 s, K = 4 renormalisations; the
# checkpoints are k = round(10^(i/10)) for i = 0, 1, ... up to K, and K:
# 1, 2, 3, 4
K = 4
checks = sorted({round(10 ** (i / 10)) for i in range(100) if round(10 ** (i / 10)) < K} | {K})
whole = rows_of("spectrum_whole.csv")
ok(all([float(x[2]) for x in point_rows(whole, p)] == [float(k) for k in checks]
       for p in range(6)), f"spectrum: every point's rows at T = {checks}")
# a driven orbit at f = 1.8 Hz over 30 s: t = k/1.8 for k = 1 .. 54
whole = rows_of("orbit_whole.csv")
ok(all([round(float(x[2]) * 1.8, 6) for x in point_rows(whole, p)] == list(range(1, 55))
       for p in range(4)), "orbit (driven, 1.8 Hz, 30 s): every point's rows at t = k/f, "
       "k = 1 .. 54")
# an undriven orbit: point 0 starts hanging at rest (angle 0) and never
# crosses theta = 0 upward; it writes one row of its own, t = 30 and nan
whole = rows_of("undriven_whole.csv")
p0 = point_rows(whole, 0)
ok(len(p0) == 1 and float(p0[0][2]) == 30 and all(v == "nan" for v in p0[0][3:]),
   f"orbit (undriven): a point without a crossing has one row, t = T0 + T, nan: {p0}")
ok(all(point_rows(whole, p) for p in range(6)), "orbit (undriven): every point has rows")
ok(all(all(float(a[2]) < float(b[2]) for a, b in zip(pr, pr[1:]))
       for pr in (point_rows(whole, p) for p in range(6))),
   "orbit (undriven): each point's times strictly ascend")
whole = rows_of("poincare_whole.csv")
ok(all(point_rows(whole, p) for p in range(6)), "poincare: every point has rows")

# ---- forged shards (SHA-256 and dc:extent recomputed) ----------------------

# spectrum shard 1: points 0, 1, 2, four rows each
refused("spectrum", "a point's first two rows swapped", swap(0, 1))
refused("spectrum", "T = 3 copied over T = 4", copy_over(2, 3))
refused("spectrum", "the T = 4 row dropped (the point ends at T = 3)", delete(3))
refused("spectrum", "a row copied in (T = 4 twice)", insert_copy(3))
refused("spectrum", "point 1 dropped", drop_point(1))
refused("spectrum", "the last point dropped", drop_point(2))
refused("spectrum", "the first point dropped", drop_point(0))

refused("precession", "the last point dropped", drop_point(1))
refused("precession", "the first point dropped", drop_point(0))
refused("precession", "a point copied over the next", copy_over(0, 1))

refused("orbit", "a row copied over the next (two equal times)", copy_over(4, 5))
refused("orbit", "three drive periods dropped", delete(3, 6))
refused("orbit", "point 1 dropped", drop_point(1))
refused("orbit", "point 0 dropped", drop_point(0))
refused("orbit", "the last row dropped (a point ends early)", lambda rows: rows[:-1])
refused("orbit", "two rows swapped", swap(0, 1))
refused("orbit", "a time moved off t = k/f", lambda rows: [
    x if i != 2 else x[:2] + ["%.10g" % (float(x[2]) + 0.01)] + x[3:]
    for i, x in enumerate(rows)])

refused("peak", "a row copied over the next", copy_over(4, 5))
refused("peak", "point 1 dropped", drop_point(1))
refused("peak", "the last row dropped", lambda rows: rows[:-1])

u1 = rows_of("undriven1.csv")  # points 0 (no crossing), 1, 2
refused("undriven", "a crossing copied in (two equal times)", insert_copy(first_index(u1, 1)))
refused("undriven", "point 1 dropped", drop_point(1))
refused("undriven", "point 0 (no crossing) dropped", drop_point(0))
refused("undriven", "the last point dropped", drop_point(2))

c1 = rows_of("poincare1.csv")
refused("poincare", "a crossing copied in (two equal times)", insert_copy(0))
refused("poincare", "the first point dropped", drop_point(c1[0][0]))
refused("poincare", "the last point dropped", drop_point(c1[-1][0]))

refused("lyapunov", "a point copied over the next", copy_over(0, 1))
refused("lyapunov", "the last point dropped", drop_point(2))
refused("basins", "a point copied over the next", copy_over(0, 1))
refused("basins", "the last point dropped", lambda rows: rows[:-1])

done()
