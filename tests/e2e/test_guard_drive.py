#!/usr/bin/env python3
"""springpend tests: the blow-up guard on strongly driven pivots. The guard
subtracts the work of damping and drive from the energy; scipy (DOP853 at
rtol 1e-11, lab frame, the drive's and damping's work integrated beside the
state) checks that accounting, and shows that a strong parametric drive which
flings the bob past the pivot stays bounded. A fixed step loses energy on
each pass it cannot resolve, so the guard stops it; the message must say
that this is not a blow-up and name a method that then completes, while
real instabilities keep their own words.
usage: test_guard_drive.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import math
import os
import re
import shutil
import sys

from sptest import done, need_scipy, ok, runner, sets

need_scipy()
import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "guard_drive"))
scenes = os.path.join(src, "..", "scenes")
PARAMETRIC = os.path.join(scenes, "parametric.ini")
DEFAULT = os.path.join(scenes, "default.ini")
# parametric.ini's pendulum and start
L0, K, M, G, R0 = 0.25, 400.0, 1.0, 9.81, 0.2745
EMIN = -M * G * L0 - (M * G) ** 2 / (2 * K)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


run = runner(exe, work)


def rows(text):
    lines = text.strip().split("\n")
    head = lines[0].split(",")
    data = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    return {h: data[:, i] for i, h in enumerate(head)}


def reference(A, f, b, th0_deg, ts):
    """The lab frame: bob at (X, Y), pivot at (0, A sin W t). Energy in the
    pivot's frame (doc/integrators.md); its rate is the drive's -m a_p v_rel,y plus the
    damping's -b V . v_rel (the air at rest in the lab), integrated beside."""
    W = 2 * math.pi * f

    def rhs(t, u):
        X, Y, VX, VY, _ = u
        yp, vp, ap = A * math.sin(W * t), A * W * math.cos(W * t), -A * W * W * math.sin(W * t)
        c = K / M * (1 - L0 / math.hypot(X, Y - yp))
        return [VX, VY, -c * X - b / M * VX, -c * (Y - yp) - G - b / M * VY,
                -M * ap * (VY - vp) - b * (VX * VX + VY * (VY - vp))]
    th = math.radians(th0_deg)
    # initial rates relative to the pivot: the bob starts with its velocity
    u0 = [R0 * math.sin(th), -R0 * math.cos(th), 0, A * W, 0]
    s = solve_ivp(rhs, (0, ts[-1]), u0, method="DOP853", rtol=1e-11, atol=1e-13, t_eval=ts)
    X, Y, VX, VY, w = s.y
    yp, vp = A * np.sin(W * s.t), A * W * np.cos(W * s.t)
    rho = np.hypot(X, Y - yp)
    E = 0.5 * M * (VX ** 2 + (VY - vp) ** 2) + 0.5 * K * (rho - L0) ** 2 + M * G * (Y - yp)
    return {"x": X, "y": Y - yp, "energy": E, "work": w, "rho": rho,
            "speed": np.hypot(VX, VY - vp)}


# ---- the drive's work is accounted right ------------------------------------
# parametric.ini at A = 0.171 m (the drive's acceleration 2.2 g): the motion
# tumbles, the drive does 50 J of work; energy and work each agree with scipy.
A1 = {"pivot.amplitude": 0.171}
r = run("data", PARAMETRIC, "-o", "-", "--every", "0.01", *sets(A1))
if ok(r.returncode == 0, f"parametric.ini at A = 0.171 m runs its 60 s (exit {r.returncode}) "
      f"{r.stderr.strip()[:200]}"):
    d = rows(r.stdout)
    ref = reference(0.171, 1.8, 0.3, 5, d["t"])
    de = np.max(np.abs(d["energy"] - ref["energy"]))
    dw = np.max(np.abs(d["work"] - ref["work"]))
    ok(de < 2e-5 and dw < 2e-5 and np.max(np.abs(ref["work"])) > 10,
       f"A = 0.171 m, rk4 dt 1e-3: energy within {de:.1e} J, work within {dw:.1e} J of scipy "
       f"(<= 2e-5; the work reaches {np.max(np.abs(ref['work'])):.1f} J)")

# ---- a pass by the pivot: bounded, yet beyond a fixed step -------------------
# Driven at 7.64 Hz (10 g), the bob is flung past the pivot twice a period.
PASS = {"pivot.amplitude": 0.17643882061606092, "pivot.frequency": 7.637978711754736,
        "pendulum.damping": 1, "initial.angle": 156.60182793179516, "video.duration": 20}
ts = np.arange(0, 20.0005, 0.001)
ref = reference(PASS["pivot.amplitude"], PASS["pivot.frequency"], 1, PASS["initial.angle"], ts)
balance = np.max(np.abs(ref["energy"] - ref["energy"][0] - ref["work"]))
near = ref["rho"] < 1e-3
ok(np.max(ref["energy"]) < 400 and balance < 1e-5 and near.any()
   and np.min(ref["speed"][near]) > 10,
   f"scipy: the strongly driven bob stays bounded (energy at most {np.max(ref['energy']):.1f} J, "
   f"balance {balance:.1e} J) and passes within {np.min(ref['rho']):.1e} m of the pivot "
   f"at {np.min(ref['speed'][near]) if near.any() else 0:.0f} m/s or more")

for method in ("rk4", "verlet"):
    r = run("data", PARAMETRIC, "-o", "pass.csv", *sets({**PASS, "integrator.method": method}))
    m = re.search(r"passed ([0-9.e+-]+) m from the pivot at ([0-9.e+-]+) m/s", r.stderr)
    ok(r.returncode == 3 and not os.path.exists(os.path.join(work, "pass.csv"))
       and "not a blow-up" in r.stderr and "became unstable" not in r.stderr
       and m is not None and float(m.group(1)) < L0 / 2 and float(m.group(2)) > 10
       and "integrator.method = dop853" in r.stderr and "completes with it over [0, 20]" in r.stderr,
       f"{method} at dt 1e-3 past the pivot: exit {r.returncode} (3), no CSV, called a pass by "
       f"the pivot, not a blow-up, dop853 offered as completing: {r.stderr.strip()[:600]!r}")

# the same words on the frame path (still's pre-pass)
r = run("still", PARAMETRIC, "--at", "10", "-o", "pass.png", *sets(PASS))
ok(r.returncode == 3 and "not a blow-up" in r.stderr
   and not os.path.exists(os.path.join(work, "pass.png")),
   f"still --at 10 past the pivot: exit {r.returncode}, no image, the same words")

# what the message says to do: dop853 completes, and agrees with scipy
r = run("data", PARAMETRIC, "-o", "-", "--every", "0.001",
        *sets({**PASS, "integrator.method": "dop853"}))
if ok(r.returncode == 0, f"dop853 completes the pass scene (exit {r.returncode})"):
    d = rows(r.stdout)
    pos = np.max(np.hypot(d["x"] - ref["x"], d["y"] - ref["y"]))
    de = np.max(np.abs(d["energy"] - ref["energy"]))
    dw = np.max(np.abs(d["work"] - ref["work"]))
    ok(pos < 1e-6 and de < 1e-3 and dw < 1e-3,
       f"dop853 past the pivot: position within {pos:.1e} m, energy {de:.1e} J, work "
       f"{dw:.1e} J of scipy over 20 s (<= 1e-6 m, 1e-3 J)")

# ---- real instabilities keep their words -------------------------------------
unstable = [
    ("parametric.ini at dt 0.15 (h omega_s = 3 > 2.83)", PARAMETRIC, {"integrator.dt": 0.15}),
    ("k/m = 1e8 at dt 2.9e-4", DEFAULT,
     {"pendulum.mass": 1, "pendulum.stiffness": 1e8, "pendulum.natural_length": 1,
      "initial.length": 1.01, "initial.angle": 20, "integrator.dt": 2.9e-4, "video.duration": 1}),
    # starts 5 cm from the pivot and bounces off it: no pass, dt too coarse
    ("a bounce off the pivot at dt 0.01", DEFAULT,
     {"pendulum.mass": 1, "pendulum.stiffness": 1e4, "pendulum.natural_length": 1,
      "initial.length": 0.05, "initial.angle": 2, "initial.length_rate": -3,
      "initial.angle_rate": 0.5, "integrator.dt": 0.01}),
    # a step 2.5 times the spring's period: its suggested dt is too small to
    # check over the whole run, so dop853, which completes it, comes first
    ("parametric.ini driven at 10 g, dt 0.05", PARAMETRIC, {**PASS, "integrator.dt": 0.05}),
]
for name, scene, d in unstable:
    r = run("data", scene, "-o", "x.csv", *sets(d))
    fix = r.stderr[r.stderr.rfind("; use ") + 2:]
    first = ("use integrator.method = dop853 (the run completes with it over [0, 20] s) or "
             "integrator.dt = ") if "10 g" in name else "use integrator.dt = "
    ok(r.returncode == 3 and "became unstable" in r.stderr and "not a blow-up" not in r.stderr
       and fix.startswith(first),
       f"{name}: exit {r.returncode} (3), still called unstable, the fix starts "
       f"{first!r}: {r.stderr.strip()[:200]!r} ... {fix!r}")

done()
