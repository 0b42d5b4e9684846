#!/usr/bin/env python3
"""springpend tests: the analysis measures of `springpend sweep` against
independent computations written here (scipy's DOP853 on the equations of
motion and their tangent equations in the lab frame; numpy's Householder QR;
never springpend's own output):
- the four Lyapunov exponents of chaotic.ini and of damped.ini;
- the identities: undamped lambda1 = -lambda4, lambda2 = lambda3 = 0 (to the
  finite-T error), sum 0; damped and driven sum = -2b/m and pairs
  lambda1 + lambda4 = lambda2 + lambda3 = -b/m (conformally symplectic flow);
- lambda1 of the spectrum is the largest exponent's measure to the bit;
- a bistable basin map (parametric.ini at 10 mm: hanging and a period-2
  swing) against a scipy classification of the same starts;
- a hysteresis loop under continuation (parametric.ini, amplitude up and
  down) where a scipy sweep up and down shows one, and the per-period peak;
- numbers on stdout (-o -, --format csv|json), shards and threads giving the
  same bytes, and bad input refused.
usage: test_analysis.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import csv
import io
import json
import math
import os
import shutil
import sys

from sptest import done, need_scipy, ok, runner, sets

need_scipy()
import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "analysis"))
scenes = os.path.join(src, "..", "scenes")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
run = runner(exe, work)


def scene(name):
    return os.path.join(scenes, name)


def csv_rows(text):
    return list(csv.DictReader(text.splitlines()))


def read(name):
    with open(os.path.join(work, name), "rb") as f:
        return f.read()


# ---- the physics, in the lab frame ------------------------------------------
CHAOTIC = dict(k=39.24, m=1.0, L0=0.75, g=9.81, b=0.0, A=0.0, f=0.0, r0=1.2, th0=85.94,
               rd0=0.0, thd0=0.0)
DAMPED = dict(k=40.0, m=1.0, L0=0.5, g=9.81, b=0.4, A=0.0, f=0.0, r0=0.95, th0=25.0,
              rd0=0.0, thd0=0.0)
PARAMETRIC = dict(k=400.0, m=1.0, L0=0.25, g=9.81, b=0.3, A=0.03, f=1.8, r0=0.2745, th0=5.0,
                  rd0=0.0, thd0=0.0)


def start(p):
    """The lab-frame state at t = 0: the scene's start is relative to the pivot,
    which is at y = A sin(2 pi f t), moving up at A 2 pi f."""
    th, r = math.radians(p["th0"]), p["r0"]
    w = 2 * math.pi * p["f"]
    x, y = r * math.sin(th), -r * math.cos(th)
    thd, rd = p["thd0"], p["rd0"]
    vx = rd * math.sin(th) + r * thd * math.cos(th)
    vy = -rd * math.cos(th) + r * thd * math.sin(th)
    return [x, y, vx, vy + p["A"] * w]


def rhs_factory(p, tangents):
    km, L0, g, bm, A, w = p["k"] / p["m"], p["L0"], p["g"], p["b"] / p["m"], p["A"], \
        2 * math.pi * p["f"]

    def rhs(t, s):
        x, y, vx, vy = s[:4]
        dy = y - A * math.sin(w * t)
        rho = math.hypot(x, dy)
        c = km * (1 - L0 / rho)
        out = [vx, vy, -c * x - bm * vx, -c * dy - g - bm * vy]
        if tangents:
            a = km * L0 / rho ** 3
            J = np.array([[-c - a * x * x, -a * x * dy], [-a * x * dy, -c - a * dy * dy]])
            D = np.asarray(s[4:]).reshape(4, tangents)  # rows: dx, dy, dvx, dvy
            dq, dv = D[:2], D[2:]
            out += list(np.vstack([dv, J @ dq - bm * dv]).ravel())
        return out
    return rhs


def spectrum_scipy(p, T):
    """Benettin with four tangent vectors, numpy's QR every second."""
    rhs = rhs_factory(p, 4)
    Q = np.eye(4)
    s = np.array(start(p) + list(Q.ravel()))
    total = np.zeros(4)
    for k in range(1, int(T) + 1):
        sol = solve_ivp(rhs, (k - 1, k), s, method="DOP853", rtol=1e-11, atol=1e-12)
        s = sol.y[:, -1]
        Q, R = np.linalg.qr(s[4:].reshape(4, 4))
        sign = np.sign(np.diag(R))
        Q, diag = Q * sign, np.abs(np.diag(R))
        total += np.log(diag)
        s[4:] = Q.ravel()
    return total / T


def spectrum(scene_file, T, extra=()):
    r = run("sweep", scene_file, "--vary", "pendulum.mass=1:1:1", "--measure", "spectrum",
            "--time", str(T), "--format", "json", "-o", "-", "-q", *extra)
    if r.returncode:
        print("#", r.stderr)
        return None, r
    j = json.loads(r.stdout)
    return j, r


# ---- the spectrum against scipy ---------------------------------------------
for what, name, p in (("chaotic.ini", "chaotic.ini", CHAOTIC), ("damped.ini", "damped.ini", DAMPED)):
    j, r = spectrum(scene(name), 40)
    ref = spectrum_scipy(p, 40)
    got = j["rows"][0][3:7] if j else [math.nan] * 4
    good = all(abs(a - b) <= 0.02 * abs(b) + 3e-3 for a, b in zip(got, ref))
    ok(good, f"{what}: the four exponents over 40 s {[round(x, 4) for x in got]} 1/s; scipy "
       f"DOP853 + numpy QR {[round(x, 4) for x in ref]}")

# chaotic.ini over 200 s: the Hamiltonian identities
j, r = spectrum(scene("chaotic.ini"), 200)
l1, l2, l3, l4, total, ky = j["rows"][0][3:9]
ok(abs(l1 + l4) < 0.02 * l1 and abs(l2) < 0.02 and abs(l3) < 0.02 and abs(total) < 1e-6 and
   l1 > 0.3 and abs(ky - 4) < 0.01,
   f"undamped (chaotic.ini, 200 s): lambda1 + lambda4 = {l1 + l4:.2g}, lambda2 = {l2:.3g}, "
   f"lambda3 = {l3:.3g} (zero up to the finite-T error), sum {total:.2g}, Kaplan-Yorke {ky}")
running = j["running"]
ok(len(running) > 15 and running[-1] == j["rows"][0] and all(x[2] <= y[2] for x, y in zip(running, running[1:])),
   f"the running values: {len(running)} checkpoints of T, the last the result")

# lambda1 to the bit: the first Gram-Schmidt column is only normalised
r2 = run("sweep", scene("chaotic.ini"), "--vary", "pendulum.mass=1:1:1", "--measure", "lyapunov",
         "--time", "200", "-o", "-", "-q")
lyap = csv_rows(r2.stdout)[0]["lyapunov"] if r2.returncode == 0 else "?"
r3 = run("sweep", scene("chaotic.ini"), "--vary", "pendulum.mass=1:1:1", "--measure", "spectrum",
         "--time", "200", "-o", "-", "-q")
spec_rows = csv_rows(r3.stdout)
ok(spec_rows and spec_rows[-1]["lambda1"] == lyap,
   f"lambda1 of the spectrum ({spec_rows[-1]['lambda1'] if spec_rows else '?'}) is the largest "
   f"exponent's measure ({lyap}) to the printed digit")

# damped: the sum is -2b/m at every step; pairs sum to -b/m (Dressler 1988)
j, r = spectrum(scene("damped.ini"), 100)
l1, l2, l3, l4, total, ky = j["rows"][0][3:9]
ok(abs(total + 0.8) < 1e-6 and abs(l1 + l4 + 0.4) < 0.01 and abs(l2 + l3 + 0.4) < 0.01 and
   all(abs(x + 0.2) < 0.02 for x in (l1, l2, l3, l4)) and ky == 0,
   f"damped (b/m = 0.4 1/s): sum {total:.9f} = -2b/m, pairs {l1 + l4:.4f} and {l2 + l3:.4f} = "
   f"-b/m, each near -b/2m = -0.2 (the hanging state's rate): {[round(x, 4) for x in (l1, l2, l3, l4)]}; "
   f"Kaplan-Yorke {ky}")

# driven and damped: parametric.ini in its chaotic window
j, r = spectrum(scene("parametric.ini"), 200, ("--transient", "50"))
l1, l2, l3, l4, total, ky = j["rows"][0][3:9]
ok(abs(total + 0.6) < 1e-6 and abs(l1 + l4 + 0.3) < 0.02 and abs(l2 + l3 + 0.3) < 0.02 and
   l1 > 0.05 and 2 < ky < 4,
   f"driven, damped (parametric.ini, 30 mm): sum {total:.9f} = -2b/m, pairs {l1 + l4:.4f}, "
   f"{l2 + l3:.4f} = -b/m, lambda1 = {l1:.4f} > 0 (chaos), Kaplan-Yorke {ky:.3f}")

# driven, undamped: Hamiltonian with time-periodic forcing: +- pairs, no zero
j, r = spectrum(scene("driven.ini"), 100, ("--set", "integrator.method=rk4",
                                             "--set", "integrator.dt=0.001"))
l1, l2, l3, l4, total, ky = j["rows"][0][3:9]
ok(abs(total) < 1e-6 and abs(l1 + l4) < 0.03 and abs(l2 + l3) < 0.03,
   f"driven, undamped (driven.ini): sum {total:.2g}, lambda1 + lambda4 = {l1 + l4:.3g}, "
   f"lambda2 + lambda3 = {l2 + l3:.3g}")

# ---- numbers on stdout --------------------------------------------------------
r = run("sweep", scene("chaotic.ini"), "--vary", "pendulum.stiffness=39.24:39.24:1", "--measure",
        "spectrum", "--time", "20", "--format", "json")
try:
    j = json.loads(r.stdout)
    four = j["rows"][0][3:7]
except (ValueError, KeyError, IndexError):
    four = []
ok(r.returncode == 0 and len(four) == 4 and j["columns"][3:7] == ["lambda1", "lambda2", "lambda3", "lambda4"]
   and "wrote stdout" in r.stderr and not os.listdir(work),
   f"--format json without -o prints the four exponents, writes no file: {four}")
r = run("sweep", scene("chaotic.ini"), "--vary", "initial.angle=60:80:3", "--measure", "lyapunov",
        "--time", "5", "-o", "-", "-q")
ok(r.returncode == 0 and r.stdout.startswith("point,initial.angle,lyapunov,") and
   len(csv_rows(r.stdout)) == 3 and "#" not in r.stdout,
   "-o - prints the CSV on stdout: the column names, then the rows (no comment line)")
r = run("sweep", scene("chaotic.ini"), "--vary", "initial.angle=60:80:3", "--measure", "lyapunov",
        "--time", "5", "-o", "fig.png", "--format", "json", "-q")
ok(r.returncode == 0 and len(json.loads(r.stdout)["rows"]) == 3 and os.path.getsize(os.path.join(work, "fig.png")) > 1000,
   "a figure and --format json together")

# ---- shards and threads: the same bytes ----------------------------------------
grids = {
    "spectrum": (scene("chaotic.ini"), ["--vary", "initial.angle=40:90:5", "--vary",
                 "initial.length=1:1.3:2", "--measure", "spectrum", "--time", "6",
                 "--set", "integrator.dt=0.002"]),
    "basins": (scene("parametric.ini"), ["--vary", "initial.angle=-90:90:7", "--vary",
               "initial.angle_rate=-4:4:5", "--set", "pivot.amplitude=0.01", "--measure",
               "basins", "--transient", "10", "--time", "60", "--set", "integrator.dt=0.002"]),
}
for what, (sc, grid) in grids.items():
    r = run("sweep", sc, *grid, "-o", f"{what}.png", "--csv", f"{what}.csv", "-q")
    r1 = run("sweep", sc, *grid, "--threads", "1", "-o", f"{what}1.png", "--csv", f"{what}1.csv", "-q")
    for i in (1, 2, 3):
        run("sweep", sc, *grid, "--shard", f"{i}/3", "--csv", f"{what}_p{i}.csv")
    rm = run("sweep", "--merge", *[f"{what}_p{i}.csv" for i in (3, 1, 2)], "-o", f"{what}m.png",
             "--csv", f"{what}m.csv", "-q")
    ok(r.returncode == 0 and r1.returncode == 0 and rm.returncode == 0 and
       read(f"{what}.csv") == read(f"{what}1.csv") == read(f"{what}m.csv") and
       read(f"{what}.png") == read(f"{what}1.png") == read(f"{what}m.png"),
       f"{what}: one thread, all threads and 3 shards merged give the same CSV and PNG bytes "
       f"{r.stderr.strip()} {rm.stderr.strip()}")
    for ext in ("svg", "pdf"):
        rr = run("sweep", sc, *grid, "-o", f"{what}.{ext}", "-q")
        ok(rr.returncode == 0 and os.path.getsize(os.path.join(work, f"{what}.{ext}")) > 1000,
           f"{what}: the {ext} figure is written")


# ---- basins of a bistable case against scipy ------------------------------------
def settle_scipy(p, starts, T=120.0):
    """Integrates each (theta0 deg, theta rate rad/s) start (lab frame) and says
    where it ends: 'hanging' when the swing's largest |theta| over the last 4
    drive periods is below 1 degree, 'swing' when it is a regular swing below
    90 degrees, else 'other'. All starts are one system of 4N equations, so
    numpy evaluates them together; the tolerances are divided by sqrt(4N),
    as scipy's error norm is the RMS over all components, so that each start
    is held to at least the tolerance it would have alone."""
    n = len(starts)
    km, L0, g, bm, A = p["k"] / p["m"], p["L0"], p["g"], p["b"] / p["m"], p["A"]
    w = 2 * math.pi * p["f"]

    def rhs(t, s):
        x, y, vx, vy = s.reshape(4, n)
        dy = y - A * math.sin(w * t)
        c = km * (1 - L0 / np.hypot(x, dy))
        return np.concatenate([vx, vy, -c * x - bm * vx, -c * dy - g - bm * vy])

    s0 = np.array([start(dict(p, th0=a, thd0=b)) for a, b in starts]).T.ravel()
    t_end = math.floor(T * p["f"]) / p["f"]
    k = math.sqrt(4 * n)
    sol = solve_ivp(rhs, (0, t_end), s0, method="DOP853", rtol=1e-9 / k, atol=1e-11 / k,
                    dense_output=True)
    ts = np.linspace(t_end - 4 / p["f"], t_end, 400)
    q = sol.sol(ts).reshape(4, n, len(ts))
    x, y = q[0], q[1] - A * np.sin(w * ts)
    peak = np.max(np.abs(np.degrees(np.arctan2(x, -y))), axis=1)
    return ["hanging" if v < 1 else "swing" if v < 90 else "other" for v in peak]


BIST = dict(PARAMETRIC, A=0.01)
n_side = 9
angles = np.linspace(-150, 150, n_side)
rates = np.linspace(-6, 6, n_side)
r = run("sweep", scene("parametric.ini"), "--set", "pivot.amplitude=0.01", "--vary",
        f"initial.angle=-150:150:{n_side}", "--vary", f"initial.angle_rate=-6:6:{n_side}",
        "--measure", "basins", "--transient", "20", "--time", "200", "--format", "json",
        "-o", "basins_bist.png", "-q")
j = json.loads(r.stdout) if r.returncode == 0 else {"rows": [], "attractors": []}
atts = j["attractors"]
# which of springpend's attractors is hanging: period 1 at theta 0
names = {}
for a in atts:
    names[a["index"]] = ("hanging" if a["period"] == 1 and abs(a["theta"]) < 1 else
                         "swing" if a["period"] == 2 and a["winding"] == 0 else "other")
ok(sorted(names.values()) == ["hanging", "swing"],
   f"parametric.ini at 10 mm: two attractors, {[a['label'] for a in atts]}")
ours = [names.get(label, "other") for label in j.get("labels", [])]
ref = settle_scipy(BIST, [(row[1], row[2]) for row in j["rows"]][:len(ours)]) if ours else []
agree = sum(a == b for a, b in zip(ours, ref)) / max(1, len(ref))
f_ours = ours.count("hanging") / max(1, len(ours))
f_ref = ref.count("hanging") / max(1, len(ref))
frac = {a["index"]: a["fraction"] for a in atts}
f_json = sum(frac[i] for i, n in names.items() if n == "hanging")
ok(len(ref) == n_side * n_side == len(j["rows"]) and abs(f_ours - f_ref) <= 0.04 and agree >= 0.93 and
   abs(f_json - f_ours) < 1e-9,
   f"basin map {n_side}x{n_side} (angle x rate): the hanging basin {f_ours:.3f} of the map, "
   f"scipy {f_ref:.3f}; {agree:.1%} of the starts end alike")
ok(j.get("basin_entropy", -1) >= 0 and j.get("boundary_basin_entropy", -1) >= j.get("basin_entropy", 0),
   f"S_b = {j.get('basin_entropy')}, S_bb = {j.get('boundary_basin_entropy')} (S_bb >= S_b)")


# entropy: a map of one attractor has S_b = 0; of a checkerboard near ln 2
def entropy_of(labels, nx, ny, box=5):
    tot, nb, bnd = 0.0, 0, 0
    for j0 in range(0, ny - ny % box, box):
        for i0 in range(0, nx - nx % box, box):
            cell = [labels[y * nx + x] for y in range(j0, j0 + box) for x in range(i0, i0 + box)]
            s = 0.0
            for v in set(cell):
                q = cell.count(v) / len(cell)
                s -= q * math.log(q)
            tot, nb, bnd = tot + s, nb + 1, bnd + (s > 0)
    return tot / nb, (tot / bnd if bnd else 0)


grid_args = ["--set", "pivot.amplitude=0.01", "--vary", "initial.angle=-150:150:10", "--vary",
             "initial.angle_rate=-6:6:10", "--measure", "basins", "--transient", "20", "--time",
             "200", "--format", "json", "-o", "-", "-q"]
r = run("sweep", scene("parametric.ini"), *grid_args)
j = json.loads(r.stdout)
labels = j["labels"]
sb, sbb = entropy_of(labels, 10, 10)
ok(abs(sb - j["basin_entropy"]) < 1e-9 and abs(sbb - j["boundary_basin_entropy"]) < 1e-9,
   f"S_b {j['basin_entropy']:.4f} and S_bb {j['boundary_basin_entropy']:.4f} as Daza et al. "
   f"define them, recomputed here from the labels: {sb:.4f}, {sbb:.4f}")

# ---- hysteresis under continuation ----------------------------------------------
AMPS = [0.004, 0.008, 0.012, 0.016]


def continued_scipy(amps, T0=60.0, T=10.0):
    """A scipy sweep: each amplitude starts from the previous one's relative
    state at its last whole drive period (the drive's phase 0), a start within
    0.05 degrees of hanging seeded at 0.05 degrees; returns the largest |theta|
    over the last T seconds for each amplitude."""
    p = dict(PARAMETRIC)
    rel = None
    out = []
    for A in amps:
        q = dict(p, A=A)
        w = 2 * math.pi * q["f"]
        if rel is not None:
            x, y, vx, vy = rel
            r0 = math.hypot(x, y)
            th = math.atan2(x, -y)
            thd = (x * vy - y * vx) / r0 ** 2
            if abs(th) < math.radians(0.05) and abs(thd) < 1e-3:
                th = math.radians(0.05)
            q.update(r0=r0, th0=math.degrees(th), rd0=(x * vx + y * vy) / r0, thd0=thd)
        t_end = math.ceil((T0 + T) * q["f"] - 1e-9) / q["f"]
        sol = solve_ivp(rhs_factory(q, 0), (0, t_end), start(q), method="DOP853", rtol=1e-9,
                        atol=1e-11, dense_output=True)
        ts = np.linspace(T0, T0 + T, 4000)
        s = sol.sol(ts)
        peak = np.max(np.abs(np.degrees(np.arctan2(s[0], -(s[1] - A * np.sin(w * ts))))))
        xe, ye, vxe, vye = sol.y[:, -1]
        rel = (xe, ye - A * math.sin(w * t_end), vxe, vye - A * w * math.cos(w * t_end))
        out.append(peak)
    return out


up_ref = continued_scipy(AMPS)
down_ref = continued_scipy(AMPS[::-1])[::-1]
r = run("sweep", scene("parametric.ini"), "--vary", "pivot.amplitude=0.004:0.016:4", "--measure",
        "orbit", "--continue", "both", "--peak", "theta", "--transient", "60", "--time", "10",
        "-o", "hyst.png", "--csv", "hyst.csv", "-q")
rows = csv_rows(open(os.path.join(work, "hyst.csv")).read()) if r.returncode == 0 else []
up = [max([float(x["peak"]) for x in rows if x["branch"] == "1" and abs(float(x["pivot.amplitude"]) - A) < 1e-9] or [math.nan]) for A in AMPS]
down = [max([float(x["peak"]) for x in rows if x["branch"] == "-1" and abs(float(x["pivot.amplitude"]) - A) < 1e-9] or [math.nan]) for A in AMPS]
loop_ref = [i for i in range(len(AMPS)) if down_ref[i] > 20 and up_ref[i] < 1]
loop = [i for i in range(len(AMPS)) if down[i] > 20 and up[i] < 1]
ok(r.returncode == 0 and loop_ref and loop == loop_ref and
   all(abs(a - b) < 1.0 for a, b in zip(up + down, up_ref + down_ref) if a > 1 or b > 1),
   f"a hysteresis loop at amplitudes {[AMPS[i] for i in loop]} m (scipy: {[AMPS[i] for i in loop_ref]}): "
   f"largest |theta| up {[round(x, 2) for x in up]}, down {[round(x, 2) for x in down]}; scipy up "
   f"{[round(x, 2) for x in up_ref]}, down {[round(x, 2) for x in down_ref]} degrees")
plain = run("sweep", scene("parametric.ini"), "--vary", "pivot.amplitude=0.004:0.016:4", "--measure",
            "orbit", "--transient", "60", "--time", "10", "-o", "-", "-q")
peak_only = run("sweep", scene("parametric.ini"), "--vary", "pivot.amplitude=0.004:0.016:4",
                "--measure", "orbit", "--peak", "theta", "--transient", "60", "--time", "10", "-o", "-", "-q")
a_rows, b_rows = csv_rows(plain.stdout), csv_rows(peak_only.stdout)
ok(len(a_rows) == len(b_rows) > 0 and all(x["theta"] == y["theta"] and x["t"] == y["t"] for x, y in zip(a_rows, b_rows))
   and all(float(y["peak"]) >= abs(float(y["theta"])) for y in b_rows) and all(y["branch"] == "0" for y in b_rows),
   "--peak keeps the stroboscopic samples of the plain diagram and adds the period's largest |theta|")
r = run("sweep", "--help")
ok("largest |theta|" in r.stdout and "t = k/f" in r.stdout and "--continue" in r.stdout,
   "--help says what an orbit diagram samples")

# ---- bad input ----------------------------------------------------------------------
bad = [
    ([scene("parametric.ini"), "--vary", "initial.angle=0:10:3", "--measure", "basins", "--time", "5", "-o", "b.png"],
     "give two --vary"),
    ([scene("chaotic.ini"), "--vary", "initial.angle=0:10:3", "--vary", "initial.length=1:1.2:2",
      "--measure", "basins", "--time", "5", "-o", "b.png"], "damped, driven scene"),
    ([scene("parametric.ini"), "--vary", "pivot.amplitude=0:0.01:3", "--measure", "orbit",
      "--continue", "both", "--time", "5", "--shard", "1/2", "--csv", "b.csv"], "cannot be cut into shards"),
    ([scene("parametric.ini"), "--vary", "pivot.amplitude=0:0.01:3", "--measure", "lyapunov",
      "--continue", "up", "--time", "5", "-o", "b.png"], "belong to orbit diagrams"),
    ([scene("chaotic.ini"), "--vary", "initial.angle=0:10:3", "--measure", "orbit",
      "--peak", "theta", "--time", "5", "-o", "b.png"], "belong to orbit diagrams"),
    ([scene("parametric.ini"), "--vary", "pivot.amplitude=0:0.01:3", "--measure", "orbit",
      "--continue", "sideways", "--time", "5", "-o", "b.png"], "up, down or both"),
    ([scene("parametric.ini"), "--vary", "pivot.amplitude=0:0.01:3", "--measure", "orbit",
      "--peak", "x", "--time", "5", "-o", "b.png"], "theta"),
    ([scene("parametric.ini"), "--vary", "pivot.amplitude=0:0.01:3", "--measure", "orbit",
      "--format", "xml", "--time", "5"], "csv or json"),
    ([scene("parametric.ini"), "--vary", "pivot.amplitude=0:0.01:3", "--measure", "orbit",
      "--format", "json", "--time", "5", "--shard", "1/2", "--csv", "b.csv"], "no --format"),
]
for args, want in bad:
    rr = run("sweep", *args)
    ok(rr.returncode == 2 and want in rr.stderr and not any(f.startswith("b.") for f in os.listdir(work))
       and rr.stdout == "", f"refused, exit 2, nothing written: {rr.stderr.strip()}")

done()
