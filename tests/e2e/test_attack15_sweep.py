#!/usr/bin/env python3
"""springpend tests (issue 28): the fifteenth attacker's pass, its sweep
findings (doc/notes/2026-11-27/attack15.md; fix24's notes):
- #3: the rows estimate of a Poincare mosaic (or an undriven orbit diagram)
  counted one row a swing at the small-oscillation frequency, so a grid
  whose pendulum whirls wrote 100x the rows estimated: the estimate is now
  an upper bound from each start's energy (else one row every two steps),
  printed with the run's summary ("rows estimated: at most N"), past 1e8
  refused, and a run whose rows pass the limit anyway stops, nothing
  written (SPRINGPEND_SWEEP_ROW_CAP lowers that backstop here);
- #8: basins listed a period-1 rotation as two more attractors ("rotating,
  period 2, +-2 turns", the same state): a start still shedding a beating
  transient settled as period 2, and the clustering compared raw winding:
  the cycle near a shorter one is held until told apart, and attractors
  cluster on turns per drive period.
Expected values come from counting the CSV's rows and from scipy.
usage: test_attack15_sweep.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import csv
import json
import os
import re
import subprocess

import sptest
from sptest import done, err, ok

sptest.need_scipy()
import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack15-sweep")
chaotic = os.path.join(scenes, "chaotic.ini")
parametric = os.path.join(scenes, "parametric.ini")


def csv_rows(name):
    """The CSV's data rows (the header line left out), as lists of strings."""
    with open(path(name), newline="") as f:
        rows = list(csv.reader(f))
    return rows[1:]


def bound(r):
    """The 'rows estimated: at most N' of a run's summary, or None."""
    m = re.search(r"rows estimated: at most (\d+)", err(r))
    return int(m.group(1)) if m else None


# ---- #3: the attacker's whirling grids: the bound printed >= the rows written ---------------
stiff = ["--vary", "pendulum.mass=1:1.01:2", "--set", "pendulum.stiffness=1e6",
         "--set", "integrator.method=dop853", "--measure", "poincare", "--time", "20"]
for rate in (0, 100, 300):
    r = run("sweep", chaotic, *stiff, "--set", f"initial.angle_rate={rate}",
            "-o", f"q{rate}.png", "--csv", f"q{rate}.csv", timeout=120)
    rows = len(csv_rows(f"q{rate}.csv")) if r.returncode == 0 else -1
    most = bound(r)
    ok(r.returncode == 0 and rows > 0 and most is not None and most >= rows,
       f"poincare, chaotic.ini at k = 1e6, angle_rate {rate}: {rows} rows written (counted), "
       f"the estimate printed ({most}) is at least that ({r.returncode}: {err(r)[-200:]!r})")


def crossings(k, rate, time):
    """scipy: upward crossings of theta = 0 (x from < 0 to >= 0 below the
    pivot) of chaotic.ini's pendulum (m 1, L0 0.75, g 9.81, undamped) with
    stiffness k from r 0.751, theta 0 at theta' = rate, over (0, time]."""
    m, L0, g = 1.0, 0.75, 9.81

    def f(t, u):
        x, y, vx, vy = u
        c = k / m * (1 - L0 / np.hypot(x, y))
        return [vx, vy, -c * x, -c * y - g]

    def through(t, u):
        return u[0]
    through.direction = 1
    s = solve_ivp(f, (0, time), [0, -0.751, 0.751 * rate, 0], method="DOP853", rtol=1e-10,
                  atol=1e-12, events=through)
    return sum(1 for t, u in zip(s.t_events[0], s.y_events[0]) if t > 1e-9 and u[1] < 0)


# a whirl at about 4 Hz where the old estimate said 0.5 Hz: springpend's rows for the point
# are scipy's crossings, and the bound printed holds them
r = run("sweep", chaotic, "--vary", "pendulum.mass=1:1.01:2", "--set", "pendulum.stiffness=1e4",
        "--set", "initial.length=0.751", "--set", "initial.angle=0", "--set", "initial.angle_rate=30",
        "--measure", "poincare", "--time", "20", "--csv", "w.csv", "-o", "w.png", timeout=120)
point0 = sum(1 for row in csv_rows("w.csv") if row[0] == "0") if r.returncode == 0 else -1
want = crossings(1e4, 30.0, 20.0)
most = bound(r)
ok(r.returncode == 0 and abs(point0 - want) <= 1 and most is not None
   and most >= len(csv_rows("w.csv")) and most >= 2 * want,
   f"a whirl (k = 1e4, 30 rad/s): point 0 wrote {point0} rows, scipy counts {want} crossings "
   f"in 20 s; the estimate printed ({most}) holds both points' ({r.returncode}: {err(r)[-200:]!r})")

# past 1e8 rows refused before it runs, nothing written: 300 such points for 5000 s would write
# about 300 / 2 x 5000 / 20 times the rows of q300 (the rate counted above), over 1e8
rate300 = len(csv_rows("q300.csv")) / 2 / 20 if os.path.exists(path("q300.csv")) else 0
try:
    r = run("sweep", chaotic, "--vary", "pendulum.mass=1:1.01:300", "--set", "pendulum.stiffness=1e6",
            "--set", "integrator.method=dop853", "--set", "initial.angle_rate=300",
            "--measure", "poincare", "--time", "5000", "-o", "big.png", "--csv", "big.csv", timeout=30)
    code, text = r.returncode, err(r)
except subprocess.TimeoutExpired:
    code, text = "still running after 30 s", ""
ok(code == 2 and "at most 1e+08 rows" in text and "allowed: fewer points" in text
   and not os.path.exists(path("big.png")) and not os.path.exists(path("big.csv"))
   and 300 * 5000 * rate300 > 1e8,
   f"300 whirling points for 5000 s (about {300 * 5000 * rate300:.3g} rows at q300's "
   f"{rate300:.1f} a second a point): refused, exit 2, nothing written ({code}: {text[-220:]!r})")

# the backstop: a run whose rows pass the limit stops, nothing written
env = dict(os.environ, SPRINGPEND_SWEEP_ROW_CAP="500")
r = run("sweep", chaotic, *stiff, "--set", "initial.angle_rate=300", "-o", "cap.png",
        "--csv", "cap.csv", timeout=120, env=env)
ok(r.returncode == 2 and "stopped, nothing written" in err(r)
   and not os.path.exists(path("cap.png")) and not os.path.exists(path("cap.csv"))
   and not os.path.exists(path("cap.csv.csv-metadata.json")),
   f"rows past the limit (500 here, for 3087): stopped, exit 2, nothing written "
   f"({r.returncode}: {err(r)[-200:]!r})")

# ---- #8: a period-1 rotation is one attractor each way -------------------------------------
r = run("sweep", parametric, "--set", "pivot.amplitude=0.1", "--vary", "initial.angle=-180:180:10",
        "--vary", "initial.angle_rate=-10:10:10", "--measure", "basins", "--transient", "20",
        "--time", "60", "--format", "json", "-o", "b.png", "--csv", "b.csv", "-q", timeout=120)
atts = json.loads(r.stdout)["attractors"] if r.returncode == 0 else []
labels = sorted(a["label"] for a in atts)
ok(r.returncode == 0 and len(atts) == 2 and all("period 1," in a["label"] for a in atts)
   and any("+1 turn," in a["label"] for a in atts) and any("-1 turn," in a["label"] for a in atts)
   and sum(a["points"] for a in atts) == 100,
   f"parametric.ini at 0.1 m: 2 attractors, the rotations at +-1 turn a period ({labels})")
rows = csv_rows("b.csv") if r.returncode == 0 else []
odd = [row[:5] for row in rows if row[3] != "1" or abs(int(row[4])) != 1]
ok(r.returncode == 0 and len(rows) == 100 and not odd,
   f"every start settles as period 1, +-1 turn (the CSV's period and winding): {odd}")


def strobes(angle, rate, until, f=1.8, amp=0.1):
    """scipy: parametric.ini's damped pendulum on a pivot at y = amp sin(2 pi f t) (in the
    pivot's frame), from angle (degrees) and rate; its state (theta unwrapped, r, theta',
    r') at t = k / f, k = 0 .. until f."""
    k_m, L0, g, gam, w = 400.0, 0.25, 9.81, 0.3, 2 * np.pi * f

    def rhs(t, u):
        x, y, vx, vy = u
        c = k_m * (1 - L0 / np.hypot(x, y))
        vp, ap = amp * w * np.cos(w * t), -amp * w * w * np.sin(w * t)
        return [vx, vy, -c * x - gam * vx, -c * y - g - ap - gam * (vy + vp)]
    th, r0 = np.radians(angle), 0.2745
    u0 = [r0 * np.sin(th), -r0 * np.cos(th), r0 * rate * np.cos(th), r0 * rate * np.sin(th)]
    n = int(round(until * f))
    fine = np.arange(8 * n + 1) / (8 * f)
    s = solve_ivp(rhs, (0, fine[-1]), u0, method="DOP853", rtol=1e-11, atol=1e-12, t_eval=fine)
    x, y, vx, vy = s.y
    theta = np.unwrap(np.arctan2(x, -y))
    r = np.hypot(x, y)
    return np.stack([theta, r, (x * vy - y * vx) / r ** 2, (x * vx + y * vy) / r])[:, ::8]


# the start the old build called period 2 (point 55: 20 degrees, 1.111 rad/s), integrated to
# 120 s: the last 20 strobes recur every period within the tolerance, one turn a period
st = strobes(20, 1.111111111, 120)
ell, w = 0.25 + 9.81 / 400, 2 * np.pi * 1.8
tol = np.array([1e-3, 1e-3 * ell, 1e-3 * w, 1e-3 * ell * w])
last = st[:, -21:]
step = np.abs(np.diff(last, axis=1))
step[0] = np.abs(step[0] - 2 * np.pi)  # one turn a period: theta grows by 2 pi
period1 = bool((step.max(axis=1) < tol).all())
turns = (last[0, -1] - last[0, 0]) / (2 * np.pi) / 20
row = next((x for x in rows if x[0] == "55"), None)
ok(period1 and abs(turns - 1) < 1e-6 and row is not None and row[3] == "1" and row[4] == "1"
   and abs(float(row[7]) - last[2, -1]) < 0.1 and abs(float(row[6]) - last[1, -1]) < 0.01 * ell,
   f"point 55 is period 1, +1 turn, as scipy's strobes (recurring every period to "
   f"{step.max(axis=1) / tol} tolerances, {turns:.6f} turns a period); springpend: {row}")

done()
