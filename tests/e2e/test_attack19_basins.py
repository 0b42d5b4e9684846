#!/usr/bin/env python3
"""springpend tests (issue 28): the nineteenth attacker's pass, finding #3
(doc/notes/2026-11-28/attack19.md; fix35's notes): basins settled a start
whose period-2 swing was still growing (driven.ini at b = 0.3, f = 1.1 Hz:
one period-2 cycle, but the map listed two, with transients such as
theta -0.34 deg at 33.6 s as representatives). A start is now settled only
when, besides contracting between two windows, its samples differ from
those 16 periods before by under 0.02 tolerances a period (no drift), so
every decided start is on the cycle.
Expected values come from scipy (the equations of doc/physics.md, the
pivot y = A sin 2 pi f t, damping on the velocity relative to the air as
sptest.model), strobed at t = k / f, never from springpend's output.
usage: test_attack19_basins.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import csv
import json
import math
import os

import sptest
from sptest import done, err, ok

sptest.need_scipy()
import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack19-basins")
driven = os.path.join(scenes, "driven.ini")

# driven.ini with the finding's --set: L0 0.95, k 200, m 1, g 9.81, r0 0.999, A 0.08
L0, K, M, G, B, A, F, R0 = 0.95, 200.0, 1.0, 9.81, 0.3, 0.08, 1.1, 0.999
W = 2 * math.pi * F
ANGLES = [-170.0, -85.0, 0.0, 85.0, 170.0]
RATES = [-1.0, -0.5, 0.0, 0.5, 1.0]
STARTS = [(a, r) for r in RATES for a in ANGLES]  # point = rate index * 5 + angle index
HANG = STARTS.index((0.0, 0.0))  # hanging at rest: x stays 0, the fixed point itself


def rhs(t, u):
    """All 25 starts at once, (x, y, vx, vy) in the pivot's frame."""
    x, y, vx, vy = u.reshape(4, -1)
    c = K / M * (1 - L0 / np.hypot(x, y))
    vp, ap = A * W * math.cos(W * t), -A * W * W * math.sin(W * t)
    return np.concatenate([vx, vy, -c * x - B / M * vx, -c * y - G - ap - B / M * (vy + vp)])


def oracle(periods):
    """theta (degrees) of each start at t = k / f, k = 0 .. periods."""
    th = np.radians([s[0] for s in STARTS])
    thd = np.array([s[1] for s in STARTS])
    u0 = np.concatenate([R0 * np.sin(th), -R0 * np.cos(th), R0 * thd * np.cos(th),
                         R0 * thd * np.sin(th)])
    ts = np.arange(periods + 1) / F
    s = solve_ivp(rhs, (0, ts[-1]), u0, method="DOP853", rtol=1e-10, atol=1e-12, t_eval=ts)
    x, y = s.y[:25], s.y[25:50]
    return np.degrees(np.arctan2(x, -y))


def sweep(time, name):
    r = run("sweep", driven, "--set", "pendulum.damping=0.3", "--set", "pivot.frequency=1.1",
            "--vary", "initial.angle=-170:170:5", "--vary", "initial.angle_rate=-1:1:5",
            "--measure", "basins", "--time", str(time), "--format", "json", "-o", name + ".png",
            "--csv", name + ".csv", "-q", timeout=240)
    js = json.loads(r.stdout) if r.returncode == 0 else {}
    rows = []
    if r.returncode == 0:
        with open(path(name + ".csv"), newline="") as f:
            rows = [x for x in csv.DictReader(line for line in f if not line.startswith("#"))]
    return r, js, rows


def entropy(labels):
    """S_b of one 5 x 5 box: -sum p ln p over its outcomes (blown up, -1, left out)."""
    kept = [x for x in labels if x >= 0]
    return -sum(kept.count(v) / len(kept) * math.log(kept.count(v) / len(kept))
                for v in set(kept))


# the oracle: 600 s (660 periods); every start but the hanging one ends on one period-2 cycle
th = oracle(660)
last = th[:, -40:]
cycle = float(np.abs(last[:, -2:]).max())  # the cycle's |theta|, about 3.04 deg
on_cycle = [i for i in range(25) if i != HANG and
            np.abs(np.abs(last[i]) - cycle).max() < 0.05 and
            np.abs(last[i, 2:] - last[i, :-2]).max() < 0.05 and
            np.abs(last[i, 1:] + last[i, :-1]).max() < 0.1]
ok(len(on_cycle) == 24 and np.abs(th[HANG]).max() < 1e-9 and 2.5 < cycle < 3.5,
   f"scipy: the 24 starts off the hanging state end on one period-2 cycle, theta = +-{cycle:.3f} "
   f"deg ({len(on_cycle)} of 24), the hanging one stays at 0")


def check(time, name):
    r, js, rows = sweep(time, name)
    atts = js.get("attractors", [])
    ok(r.returncode == 0 and len(rows) == 25,
       f"--time {time}: ran, 25 rows ({r.returncode}: {err(r)[-300:]!r})")
    # every decided start: period 2 on the cycle (least theta = -cycle), or the hanging start at 0
    wrong = []
    for i, row in enumerate(rows):
        per, theta = int(row["period"]), float(row["theta"])
        if per == 0:
            continue
        if i == HANG:
            good = per == 1 and abs(theta) < 1e-6
        else:
            good = per == 2 and abs(theta + cycle) < 2
        if not good:
            wrong.append((i, row["initial.angle"], row["initial.angle_rate"], per, theta))
    ok(rows and not wrong,
       f"--time {time}: every decided start is on scipy's cycle (period 2, theta within 2 deg of "
       f"-{cycle:.3f}) or is the hanging start (period 1, theta 0): off it {wrong}")
    # and it was there when settled: scipy's own strobe of that start at the settle time
    early = []
    for i, row in enumerate(rows):
        if int(row["period"]) != 2:
            continue
        k = int(round(float(row["settled"]) * F))
        if k >= th.shape[1] or abs(abs(th[i, k]) - cycle) > 0.25:
            early.append((i, row["settled"], round(float(th[i, min(k, th.shape[1] - 1)]), 3)))
    ok(rows and not early,
       f"--time {time}: each start settled as period 2 was within 0.25 deg of the cycle then "
       f"(scipy's strobe at its settle time): settled early {early}")
    p2 = [a["label"] for a in atts if a.get("period") == 2]
    ok(r.returncode == 0 and len(p2) <= 1,
       f"--time {time}: at most one period-2 attractor (scipy: one): {[a['label'] for a in atts]}")
    labels = js.get("labels", [])
    want = entropy(labels) if len(labels) == 25 else None
    got = js.get("basin_entropy")
    ok(want is not None and got is not None and abs(got - want) < 1e-9,
       f"--time {time}: S_b = {got} is the entropy of the map's labels ({want})")
    return rows, js


check(60, "b60")
rows, js = check(600, "b600")
decided = [i for i, row in enumerate(rows) if int(row["period"]) != 0]
hang_once = sum(1 for a in js.get("attractors", []) if a.get("period") == 1) <= 1
s_all = -(24 / 25 * math.log(24 / 25) + 1 / 25 * math.log(1 / 25))
ok(len(decided) == 25 and hang_once and abs(js.get("basin_entropy", -1) - s_all) < 1e-9,
   f"--time 600: all 25 decided (scipy: 24 on the cycle by 545 s, one hanging), "
   f"S_b = {js.get('basin_entropy')} = {s_all:.4f} ({len(decided)} decided)")

done()
