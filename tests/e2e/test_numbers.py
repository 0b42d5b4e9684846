#!/usr/bin/env python3
"""springpend tests: the numbers a teacher reads. The blow-up guard against the
energy of the motion, info's safe dt (a promise: the run completes with it),
the exchange time near 2:1, the damping's decay times and the driven pivot's
growth, info --json, data's row limits and data --poincare. Every expected
value comes from scipy (DOP853 at rtol 1e-11 on the Cartesian equations) or a
closed form, never from springpend's own output.
usage: test_numbers.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import math
import os
import shutil
import sys

from sptest import done, model, need_scipy, ok, runner, sets, solve, start

need_scipy()
import numpy as np  # noqa: E402

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "numbers"))
scenes = os.path.join(src, "..", "scenes")
DEFAULT = os.path.join(scenes, "default.ini")
G = 9.81
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


run = runner(exe, work)


def info(scene, d):
    r = run("info", scene, "--json", *sets(d))
    return json.loads(r.stdout) if r.returncode == 0 else {"error": r.stderr}


def csv_rows(text):
    lines = text.strip().split("\n")
    head = lines[0].split(",")
    return head, [dict(zip(head, map(float, line.split(",")))) for line in lines[1:]]


# ---- the blow-up guard ------------------------------------------------------
# Judged against the energy of the motion: E - E_min, E_min = -m g L0 - (m g)^2 / 2k
# (hanging still at l). No row may drift beyond 1% of it; both of the issue's
# stiff scenes must stop with exit 3.
stiff = {"pendulum.mass": 1, "pendulum.stiffness": 1e8, "pendulum.natural_length": 1,
         "initial.length": 1.01, "initial.angle": 20}
emin = -1 * G * 1 - (1 * G) ** 2 / (2 * 1e8)
for dt, dur, every in [("2.9e-4", 1, "1e-4"), ("2.7718e-4", 1.8, "0.01")]:
    r = run("data", DEFAULT, "-o", "-", "--every", every,
            *sets({**stiff, "video.duration": dur, "integrator.dt": dt}))
    head, rows = csv_rows(r.stdout)
    e0 = rows[0]["energy"]
    worst = max(abs(row["energy"] - e0 - row["work"]) / (e0 - emin) for row in rows)
    ok(r.returncode == 3 and worst <= 0.01,
       f"stiff scene at dt {dt}: exit {r.returncode} (3 wanted), {len(rows)} rows written, "
       f"worst drift {worst:.2e} of the motion's energy {e0 - emin:.4g} J (<= 1%)")
# A bob at rest has no motion to judge drift against: it must not be "unstable".
rest = [("hanging still at l", {"initial.length": 0.5 + 0.5 * G / 2, "initial.angle": 0}),
        ("at L0 without gravity", {"pendulum.gravity": 0, "initial.length": 0.5})]
for name, d in rest:
    codes = {m: run("data", DEFAULT, "-o", "-", "--every", "1", *sets({**d, "integrator.method": m})).returncode
             for m in ("rk4", "verlet", "yoshida4", "dopri5", "dop853", "rkn1210")}
    ok(set(codes.values()) == {0}, f"a bob at rest, {name}: every method exits 0 ({codes})")
r = run("still", DEFAULT, "--at", "1", "-o", "late.png", "--state", "late.json", "-q",
        *sets({**stiff, "integrator.dt": "2.7718e-4", "video.duration": 2}))
ok(r.returncode == 3 and not os.path.exists(os.path.join(work, "late.png"))
   and not os.path.exists(os.path.join(work, "late.json")),
   f"still --at 1 --state on the unstable scene: exit {r.returncode}, no image, no state")

# ---- info's safe dt: every suggested step completes ----------------------
# The issue's scenes, with the scene's own verdict checked both ways against
# what data then does.
issue_scenes = [
    ("default at dt 1", {"integrator.dt": 1}),
    ("near-pivot pass", {"pendulum.mass": 1, "pendulum.stiffness": 1e4, "pendulum.natural_length": 1,
                         "initial.length": 0.05, "initial.angle": 2, "initial.length_rate": -3,
                         "initial.angle_rate": 0.5, "integrator.dt": 0.01}),
    ("fast driven pivot", {"pendulum.mass": 1, "pendulum.stiffness": 1e4, "pendulum.natural_length": 0.2,
                           "initial.length": 0.19902, "initial.angle": 170, "pivot.amplitude": 0.005,
                           "pivot.frequency": 200}),
]
damped_heavy = {"pendulum.mass": 1, "pendulum.stiffness": 10, "pendulum.natural_length": 1,
                "pendulum.damping": 1000, "initial.length": 2.5, "initial.angle": 40,
                "integrator.dt": 2.8e-3}
for method in ("rk4", "verlet", "yoshida4"):
    issue_scenes.append((f"b/m = 1000, {method}", {**damped_heavy, "integrator.method": method}))
for name, d in issue_scenes:
    j = info(DEFAULT, d)
    if not ok("safe_dt" in j and j["safe_dt"], f"{name}: info --json gives a safe_dt ({j.get('safe_dt')})"):
        continue
    own = run("data", DEFAULT, "-o", "-", "--every", "0.1", *sets(d))
    safe = run("data", DEFAULT, "-o", "-", "--every", "0.1", *sets({**d, "integrator.dt": j["safe_dt"]}))
    ok(safe.returncode == 0 and (own.returncode == 0) == j["dt_completes"],
       f"{name}: data at the suggested dt {j['safe_dt']} s exits {safe.returncode}; the scene's "
       f"own dt {d.get('integrator.dt', 1e-3)} exits {own.returncode}, info said completes = "
       f"{j['dt_completes']} (margin {j['stability_margin']:.3g})")
# The blow-up message's step is the same promise.
for name, d in [("k/m = 1e7", {"pendulum.stiffness": 5e6}), ("default at dt 1", {"integrator.dt": 1})]:
    r = run("data", DEFAULT, "-o", "-", "--every", "0.1", *sets(d))
    said = r.stderr.split("use integrator.dt = ")[-1].split(" ")[0] if "use integrator.dt = " in r.stderr else None
    again = run("data", DEFAULT, "-o", "-", "--every", "0.1", *sets({**d, "integrator.dt": said})) if said else None
    ok(r.returncode == 3 and again is not None and again.returncode == 0,
       f"{name}: data exits {r.returncode}, its message suggests dt {said}, with which data exits "
       f"{again.returncode if again else None}")
# RK4 on the negative real axis: |R(-x)| = 1 at the real root of
# x^3/24 - x^2/6 + x/2 - 1 = 0 (2.785), not 2 sqrt 2.
root = max(z.real for z in np.roots([1 / 24, -1 / 6, 1 / 2, -1]) if abs(z.imag) < 1e-9)
j = info(DEFAULT, damped_heavy)
ok(abs(j["stability_limit"] * 1000 - root) < 1e-3 and j["stability_margin"] < 1,
   f"RK4 with b/m = 1000: stability limit x b/m = {j['stability_limit'] * 1000:.5f} "
   f"(closed form {root:.5f}), margin {j['stability_margin']:.3f} < 1")

# Verlet and Yoshida-4 take the damping as its exact flow in each substep:
# Verlet's limit stays 2 / omega; Yoshida-4's backward substep (weight
# -2^(1/3) / (2 - 2^(1/3))) amplifies by exp(+b/m h |w| / 2) and limits it.
# Reference: the spectral radius of one step's 2x2 map for x'' = -w^2 x - g x',
# composed here in numpy, scanned for where it first exceeds 1.
def split_limit(weights, w, g):
    def radius(h):
        M = np.eye(2)
        for wi in weights:
            hi = wi * h
            d = np.diag([1, math.exp(-g * hi / 2)])
            kick = np.array([[1, 0], [-0.5 * hi * w * w, 1]])
            drift = np.array([[1, hi], [0, 1]])
            M = d @ kick @ drift @ kick @ d @ M
        return max(abs(np.linalg.eigvals(M)))
    lo = hi = 1e-5
    while radius(hi) <= 1 + 1e-9:
        lo, hi = hi, hi * 1.01
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if radius(mid) > 1 + 1e-9 else (mid, hi)
    return lo


c2 = 2 ** (1 / 3)
w_damped = math.sqrt(10)
for method, weights in (("verlet", [1]), ("yoshida4", [1 / (2 - c2), -c2 / (2 - c2), 1 / (2 - c2)])):
    j = info(DEFAULT, {**damped_heavy, "integrator.method": method})
    ref = split_limit(weights, w_damped, 1000)
    over = run("data", DEFAULT, "-o", "-", *sets({**damped_heavy, "integrator.method": method,
                                                "integrator.dt": 1.15 * j["stability_limit"]}))
    ok(abs(j["stability_limit"] / ref - 1) < 1e-3 and over.returncode == 3,
       f"{method} with b/m = 1000: stability limit {j['stability_limit']:.5g} s (numpy's step map: "
       f"{ref:.5g} s; undamped {(2 if method == 'verlet' else 1.5734) / w_damped:.4g} s); at 1.15x "
       f"it data exits {over.returncode}")

# ---- info --json: the scene's frequencies, closed forms --------------------
L0, k, m = 0.5, 2.0, 0.5
ell = L0 + m * G / k
j = info(DEFAULT, {})
want = {"omega_spring": math.sqrt(k / m), "omega_pendulum": math.sqrt(G / ell),
        "ratio": math.sqrt(k / m) / math.sqrt(G / ell), "equilibrium_length": ell}
ok(all(abs(j[key] - v) <= 1e-9 * v for key, v in want.items()) and j["exchange_time"] is None
   and j["safe_dt"] > 0 and j["stability_margin"] > 1,
   "info --json on the default scene: " + ", ".join(f"{key} {j[key]:.6g}" for key in want) +
   f"; exchange_time {j['exchange_time']} (not near 2:1), safe_dt {j['safe_dt']}")

# ---- the exchange time near 2:1 --------------------------------------------
# The first maximum of the swing energy's envelope (averaged over one swing
# period) in the scipy run, on several exact 2:1 scenes (k L0 = 3 m g).
def first_swing_peak(L0, m, B0, th0):
    k = 3 * m * G / L0
    ell = L0 + m * G / k
    wp = math.sqrt(G / ell)
    j = info(DEFAULT, {"pendulum.natural_length": L0, "pendulum.mass": m, "pendulum.stiffness": k,
                       "initial.length": ell + B0, "initial.angle": th0,
                       "integrator.method": "dop853"})
    tend = 2.5 * j["exchange_time"]
    ts = np.linspace(0, tend, int(tend * 200))
    x, y, vx, vy = solve(model(L0, k, m), start(ell + B0, th0), tend, ts).y
    r = np.hypot(x, y)
    swing = 0.5 * m * (x * vy - y * vx) ** 2 / r ** 2 + m * G * (r + y)
    n = int(2 * math.pi / wp * 200)
    env = np.convolve(swing, np.ones(n) / n, mode="same")
    top, i = env[n:-n].max(), n
    while env[i] < 0.5 * top:
        i += 1
    while env[i + 1] >= env[i]:
        i += 1
    return j["exchange_time"], ts[i]


for case in [(1, 1, 0.1, 1), (1, 1, 0.2, 1), (1, 1, 0.1, 3), (0.5, 0.3, 0.05, 2), (2, 1, -0.1, 0.5)]:
    pred, sim = first_swing_peak(*case)
    ok(abs(pred / sim - 1) < 0.05,
       f"2:1 with L0 {case[0]} m, m {case[1]} kg, B0 {case[2]} m, theta0 {case[3]} deg: "
       f"info's exchange time {pred:.3f} s, scipy's first swing-energy peak {sim:.3f} s (within 5%)")
r = run("info", os.path.join(scenes, "resonance.ini"))
ok("first peaks at t = 20.8 s" in r.stdout, "resonance.ini: the swing's energy first peaks at "
   "20.8 s, as its charts show (not 9.56)")


# ---- damping: each regime's energy decay time ------------------------------
# The e-folding time of E - E_min late in the scipy run (between 1e-3 and 1e-10
# of its start), against info's bounce/swing decay time.
def decay_time(L0, k, m, b, th0, r0):
    emin = -m * G * L0 - (m * G) ** 2 / (2 * k)
    j = info(DEFAULT, {"pendulum.natural_length": L0, "pendulum.mass": m, "pendulum.stiffness": k,
                       "pendulum.damping": b, "initial.length": r0, "initial.angle": th0,
                       "integrator.method": "dop853"})
    key = "swing" if th0 else "bounce"
    tend = 30 * j[key + "_decay_time"]
    ts = np.linspace(0, tend, 3000)
    x, y, vx, vy = solve(model(L0, k, m, b), start(r0, th0), tend, ts).y
    e = 0.5 * m * (vx ** 2 + vy ** 2) + 0.5 * k * (np.hypot(x, y) - L0) ** 2 + m * G * y - emin
    sel = (e < 1e-3 * e[0]) & (e > 1e-10 * e[0])
    return j[key + "_regime"], j[key + "_decay_time"], -1 / np.polyfit(ts[sel], np.log(e[sel]), 1)[0]


for case, regime in [((1, 10, 1, 0.5, 0, 2), "underdamped"), ((1, 10, 1, 10, 0, 2), "overdamped"),
                     ((1, 1000, 1, 20, 10, 1.01), "overdamped")]:
    got_regime, pred, sim = decay_time(*case)
    ok(got_regime == regime and abs(pred / sim - 1) < 0.02,
       f"{'swing' if case[4] else 'bounce'} with k {case[1]}, b {case[3]}: {got_regime} "
       f"({regime} wanted), energy decay time {pred:.4g} s, scipy {sim:.4g} s (within 2%)")
j = info(DEFAULT, {"pendulum.natural_length": 1, "pendulum.mass": 1, "pendulum.stiffness": 10,
                   "pendulum.damping": 2 * math.sqrt(10)})
ok(j["bounce_regime"] == "critically damped" and abs(j["bounce_decay_time"] - 1 / (2 * math.sqrt(10))) < 1e-9,
   f"b = 2 sqrt(k m): critically damped, decay time {j['bounce_decay_time']} = m/b")


# ---- the driven pivot -------------------------------------------------------
def swing_envelope(d, tend=40):
    L0, k, b = d["pendulum.natural_length"], d["pendulum.stiffness"], d.get("pendulum.damping", 0)
    A, f = d["pivot.amplitude"], d["pivot.frequency"]
    ell = L0 + G / k
    ts = np.linspace(0, tend, 8001)
    x = solve(model(L0, k, 1, b, A, f), start(ell, d["initial.angle"]), tend, ts).y[0]
    n = int(2 * math.pi / math.sqrt(G / ell) / (ts[1] - ts[0]))
    return ts, np.array([np.abs(x[i:i + n]).max() for i in range(len(x) - n)]) / abs(x[0])


drv = {"pendulum.natural_length": 0.95, "pendulum.stiffness": 200, "initial.angle": 2,
       "pivot.amplitude": 0.08, "pivot.frequency": 2 * math.sqrt(G / (0.95 + G / 200)) / (2 * math.pi)}
j = info(os.path.join(scenes, "driven.ini"), drv)
ts, env = swing_envelope(drv)
t10 = ts[np.argmax(env >= 10)]
ok(j["drive_swing_growth"] > 0 and abs(j["drive_time_10x"] / t10 - 1) < 0.1,
   f"driven at 2 omega_p: growth expected ({j['drive_swing_growth']:.3f} 1/s); the swing is 10x "
   f"its start at {j['drive_time_10x']:.2f} s, scipy {t10:.2f} s (within 10%)")
d = {**drv, "pendulum.damping": 0.4}
j = info(os.path.join(scenes, "driven.ini"), d)
ts, env = swing_envelope(d)
sel = (ts[:len(env)] > 15) & (ts[:len(env)] < 38)
fit = np.polyfit(ts[:len(env)][sel], np.log(env[sel]), 1)[0]
ok(abs(j["drive_swing_growth"] / fit - 1) < 0.05,
   f"driven with b = 0.4: amplitude growth rate {j['drive_swing_growth']:.4f} 1/s, scipy's "
   f"envelope {fit:.4f} 1/s (within 5%)")
for name, extra in [("b = 1", {"pendulum.damping": 1.0}),
                    ("Omega = 2.4 omega_p", {"pivot.frequency": drv["pivot.frequency"] * 1.2})]:
    d = {**drv, **extra}
    j = info(os.path.join(scenes, "driven.ini"), d)
    ts, env = swing_envelope(d)
    ok(j["drive_swing_growth"] <= 0 and env.max() < 3,
       f"driven, {name}: info expects no growth ({j['drive_swing_growth']:.3f} 1/s); scipy's swing "
       f"peaks at {env.max():.2f}x its start in 40 s")
d = {**drv, "pivot.amplitude": 0.02}
j = info(os.path.join(scenes, "driven.ini"), d)
ts, env = swing_envelope(d, 30)
ok(j["drive_time_10x"] > 30 and env.max() < 2,
   f"driven with A = 2 cm: 10x only by {j['drive_time_10x']:.0f} s (slow growth "
   f"{j['drive_swing_growth']:.3f} 1/s, {100 * j['drive_seed_share']:.0f}% of the seed growing); "
   f"scipy's swing stays under {env.max():.2f}x its start in 30 s")

# The bounce under a vertical drive is forced, not parametric: at Omega = 2 omega_s
# it stays at its forced amplitude A Omega^2 / |omega_s^2 - Omega^2| plus the free
# start, and does not grow.
ws = math.sqrt(200)
d = {"pendulum.natural_length": 0.95, "pendulum.stiffness": 200, "initial.angle": 0,
     "initial.length": 0.95 + G / 200 + 0.01, "pivot.amplitude": 0.005,
     "pivot.frequency": 2 * ws / (2 * math.pi)}
j = info(os.path.join(scenes, "driven.ini"), d)
txt = run("info", os.path.join(scenes, "driven.ini"), *sets(d)).stdout
ts = np.linspace(0, 60, 60001)
u = solve(model(0.95, 200, 1, 0, 0.005, d["pivot.frequency"]), start(d["initial.length"], 0), 60, ts).y
z = np.hypot(u[0], u[1]) - (0.95 + G / 200)
early, late = abs(z[ts < 10]).max(), abs(z[ts > 55]).max()
ok(abs(j["drive_bounce_amplitude"] - 0.005 * 4 * ws ** 2 / (3 * ws ** 2)) < 1e-12
   and "no parametric resonance of the bounce" in txt and late < 1.05 * early,
   f"drive at 2 omega_s: forced bounce {j['drive_bounce_amplitude']:.4g} m (closed form 4A/3), "
   f"info says no parametric bounce resonance; scipy's bounce {early:.4f} m in the first 10 s, "
   f"{late:.4f} m at 55-60 s")

# ---- data: limits on rows, not video frames --------------------------------
r = run("data", os.path.join(scenes, "chaotic.ini"), "--set", "video.duration=20000",
        "--every", "100", "-o", "-")
ok(r.returncode == 0 and len(r.stdout.strip().split("\n")) == 202,
   f"data chaotic.ini over 20000 s every 100 s: exit {r.returncode}, "
   f"{len(r.stdout.strip().split(chr(10))) - 1} rows (201 wanted)")
r = run("data", DEFAULT, "--every", "0.0001", "--set", "video.duration=1000", "-o", "big.csv")
ok(r.returncode == 2 and "10000001 rows" in r.stderr and "GB" in r.stderr
   and not os.path.exists(os.path.join(work, "big.csv")),
   f"data --every 1e-4 over 1000 s is refused with its size: {r.stderr.strip()}")

s_ = run("still", DEFAULT, "--set", "video.duration=40000", "--set", "video.fps=60", "-o", "x.png")
ok(s_.returncode == 2 and "frames; at most 1000000 are allowed in a video" in s_.stderr
   and not os.path.exists(os.path.join(work, "x.png")),
   f"a still of a 2.4e6-frame video is refused as a video ({s_.stderr.strip()})")

# ---- data --poincare against scipy's events --------------------------------
res = os.path.join(scenes, "resonance.ini")
r = run("data", res, "--poincare", "-o", "-")
head, rows = csv_rows(r.stdout)
L0, k, m = 1.0, 29.43, 1.0


def crossing(t, u):
    return u[0]


crossing.direction = 1
sol = solve(model(L0, k, m), start(1.4333, 1), 40, events=crossing, dense_output=False)
ref = [(t, u) for t, u in zip(sol.t_events[0], sol.y_events[0]) if u[1] < 0]
worst_t = worst_v = 0.0
for row, (t, (x, y, vx, vy)) in zip(rows, ref):
    r_ = math.hypot(x, y)
    worst_t = max(worst_t, abs(row["t"] - t))
    worst_v = max(worst_v, abs(row["r"] - r_), abs(row["r_dot"] + vy), abs(row["theta_dot"] - vx / r_))
ok(r.returncode == 0 and head[:4] == ["t", "r", "r_dot", "theta_dot"] and len(rows) == len(ref) > 10
   and worst_t < 1e-6 and worst_v < 1e-6,
   f"data --poincare on resonance.ini: {len(rows)} crossings (scipy: {len(ref)}), header "
   f"{','.join(head)}; worst time {worst_t:.1e} s, worst r/r_dot/theta_dot {worst_v:.1e}")

# ---- the conventions are where a reader looks ------------------------------
r = run("data", "--help")
ok(all(s in r.stdout for s in ("pivot's frame", "relative to the air", "relative to the\npivot")),
   "data --help states the driven scene's conventions (frame, damping, initial rates)")

done()
