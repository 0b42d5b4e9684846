"""The swinging spring in three dimensions (initial.azimuth_rate): every
integrator against scipy's DOP853 on the 3-D Cartesian equations written
here, energy and the vertical angular momentum L_y conserved (and L_y's
exact decay exp(-b t / m) under damping), a planar scene's data byte for
byte as recorded before the third dimension existed
(golden/planar_data.sha256), the precession of the swing's plane per
exchange against a scipy run measured from the horizontal motion alone, and
bad input refused.

usage: test_spatial.py SPRINGPEND SRCDIR/tests BUILDDIR/tests"""
import hashlib
import math
import os
import shutil
import subprocess
import sys

from sptest import done, model3, need_scipy, ok, precessions, runner, sets, start3

need_scipy()
import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "spatial"))
scenes = os.path.join(src, "..", "scenes")
SWING = os.path.join(scenes, "swinging-spring.ini")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
run = runner(exe, work)
G = 9.81


def table(text):
    """CSV text to a dict of numpy columns."""
    lines = text.strip().split("\n")
    head = lines[0].split(",")
    rows = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    return {h: rows[:, i] for i, h in enumerate(head)}


def reference(d, ts):
    """scipy's DOP853 at rtol 1e-12 for the scene settings d (dict of keys)."""
    g = lambda key, dflt: float(d.get(key, dflt))  # noqa: E731
    rhs = model3(g("pendulum.natural_length", 0.5), g("pendulum.stiffness", 2),
                 g("pendulum.mass", 0.5), g("pendulum.damping", 0),
                 g("pivot.amplitude", 0), g("pivot.frequency", 0))
    u0 = start3(g("initial.length", 0.55), g("initial.angle", 10),
                g("initial.length_rate", 0), g("initial.angle_rate", 0),
                g("initial.azimuth_rate", 0))
    return solve_ivp(rhs, (0, ts[-1]), u0, method="DOP853", rtol=1e-12, atol=1e-14,
                     t_eval=ts).y


# ---- a planar scene: today's numbers, bit for bit ------------------------
golden = os.path.join(src, "golden", "planar_data.sha256")
bad = []
with open(golden) as fh:
    lines = fh.read().split("\n")
for line in filter(None, lines):
    digest, scene, method = line.split()
    r = run("data", os.path.join(scenes, scene + ".ini"), "-o", "-", "-q",
            "--set", f"integrator.method={method}", "--set", "video.duration=3")
    if r.returncode != 0 or hashlib.sha256(r.stdout.encode()).hexdigest() != digest:
        bad.append(f"{scene}/{method}")
ok(not bad and len(lines) > 40,
   f"{len(lines) - 1} planar scene/method pairs write data byte for byte as recorded "
   f"before 3-D (golden/planar_data.sha256); differ: {bad}")
r0 = run("data", os.path.join(scenes, "default.ini"), "-o", "-", "-q")
r1 = run("data", os.path.join(scenes, "default.ini"), "-o", "-", "-q",
         "--set", "initial.azimuth_rate=0")
ok(r0.stdout == r1.stdout and r0.stdout.split("\n")[0].endswith("work,pivot_y"),
   "azimuth_rate = 0 is the planar run, and its columns stay the planar ones")

# ---- every integrator against scipy on the 3-D equations -----------------
# a large, non-resonant swing turning about the vertical (a spherical
# pendulum's rosette with bounce), and a damped, driven one for the methods
# that take forces depending on velocity and time
FREE = {"pendulum.natural_length": 1.0, "pendulum.stiffness": 40, "pendulum.mass": 1,
        "initial.length": 1.3, "initial.angle": 40, "initial.length_rate": 0.2,
        "initial.angle_rate": 0.3, "initial.azimuth_rate": 1.5, "video.duration": 10}
FORCED = dict(FREE, **{"pendulum.damping": 0.2, "pivot.amplitude": 0.05,
                       "pivot.frequency": 1.3})
CASES = [("rk4", {"integrator.dt": 1e-3}, 1e-7), ("verlet", {"integrator.dt": 2e-4}, 2e-4),
         ("yoshida4", {"integrator.dt": 1e-3}, 1e-6),
         ("dopri5", {"integrator.tolerance": 1e-10}, 1e-6),
         ("dop853", {"integrator.tolerance": 1e-11}, 1e-7),
         ("rkn1210", {"integrator.tolerance": 1e-11}, 1e-7)]
ts = np.arange(0, 10 + 1e-9, 0.5)
for label, base in (("free", FREE), ("damped+driven", FORCED)):
    ref = reference(base, ts)
    for method, extra, tol in CASES:
        if method == "rkn1210" and label != "free":
            continue
        d = dict(base, **extra, **{"integrator.method": method})
        r = run("data", SWING, "-o", "-", "-q", "--every", "0.5", *sets(d))
        if not ok(r.returncode == 0, f"{label} {method}: data runs ({r.stderr.strip()})"):
            continue
        c = table(r.stdout)
        err = max(np.max(np.abs(c["x"] - ref[0])), np.max(np.abs(c["y"] - ref[1])),
                  np.max(np.abs(c["z"] - ref[2])))
        zspan = np.ptp(c["z"])
        ok(err < tol and zspan > 0.5,
           f"{label} {method}: positions within {tol:g} m of scipy's DOP853 on the 3-D "
           f"equations over 10 s (largest error {err:.2g} m; z spans {zspan:.2f} m)")

# ---- energy and L_y conserved; L_y decays exactly with damping ------------
CONS = [("rk4", {"integrator.dt": 1e-3}, 1e-9, 1e-9), ("verlet", {"integrator.dt": 1e-3},
        2e-4, 1e-12), ("yoshida4", {"integrator.dt": 1e-3}, 1e-8, 1e-12),
        ("dopri5", {"integrator.tolerance": 1e-10}, 1e-7, 1e-7),
        ("dop853", {"integrator.tolerance": 1e-11}, 1e-9, 1e-9),
        ("rkn1210", {"integrator.tolerance": 1e-11}, 1e-9, 1e-9)]
for method, extra, etol, ltol in CONS:
    d = dict(FREE, **extra, **{"integrator.method": method, "video.duration": 30})
    r = run("data", SWING, "-o", "-", "-q", "--every", "0.1", *sets(d))
    c = table(r.stdout)
    m, g = 1.0, G
    rho = np.sqrt(c["x"] ** 2 + c["y"] ** 2 + c["z"] ** 2)
    # the energy from the columns, as this test defines it
    E = 0.5 * m * (c["vx"] ** 2 + c["vy"] ** 2 + c["vz"] ** 2) + \
        0.5 * 40 * (rho - 1.0) ** 2 + m * g * c["y"]
    scale = E[0] - (-m * g * 1.0 - 0.5 * (m * g) ** 2 / 40)  # above hanging still
    Ly = c["z"] * c["vx"] - c["x"] * c["vz"]
    de, dl = np.max(np.abs(E - E[0])) / scale, np.max(np.abs(Ly - Ly[0])) / abs(Ly[0])
    ok(de < etol and dl < ltol,
       f"{method}: over 30 s energy holds to {de:.2g} of the motion's energy (< {etol:g}) and "
       f"L_y = z vx - x vz to {dl:.2g} (< {ltol:g}) relative")
d = dict(FREE, **{"pendulum.damping": 0.3, "pivot.amplitude": 0.05, "pivot.frequency": 1.3,
                  "integrator.method": "dop853", "integrator.tolerance": 1e-11})
c = table(run("data", SWING, "-o", "-", "-q", "--every", "0.5", *sets(d)).stdout)
Ly = c["z"] * c["vx"] - c["x"] * c["vz"]
want = Ly[0] * np.exp(-0.3 * c["t"])
dev = np.max(np.abs(Ly - want)) / abs(Ly[0])
ok(dev < 1e-8, f"damped and driven: L_y follows L_y(0) exp(-b t / m) (closed form) to {dev:.2g}")


# ---- the precession of the swing's plane per exchange ---------------------
ell = 0.75 + 1 * G / 39.24
period = 2 * math.pi / math.sqrt(G / ell)
ts = np.arange(0, 200 + 1e-9, 0.02)
ref = reference({"pendulum.natural_length": 0.75, "pendulum.stiffness": 39.24,
                 "pendulum.mass": 1, "initial.length": 1.05, "initial.angle": 1,
                 "initial.azimuth_rate": 1}, ts)
want, t_max = precessions(ts, ref[0], ref[2], period)
r = run("data", SWING, "-o", "-", "-q", "--every", "0.02")
c = table(r.stdout)
got, _ = precessions(c["t"], c["x"], c["z"], period)
idx = [int(round(tm / 0.02)) for tm in t_max]
col = np.diff(c["azimuth"][idx])
ok(len(want) >= 3 and len(got) == len(want) and
   np.max(np.abs(got - want)) < 0.03 * np.max(np.abs(want)),
   f"scenes/swinging-spring.ini: the swing plane turns by {np.round(got, 2)} degrees per "
   f"exchange, measured from springpend's x and z; scipy's run gives {np.round(want, 2)} "
   f"(within 3%)")
ok(len(col) == len(want) and np.max(np.abs(col - want)) < 0.03 * np.max(np.abs(want)),
   f"data's azimuth column steps by {np.round(col, 2)} degrees between the swing's maxima "
   f"(scipy's horizontal motion: {np.round(want, 2)}; within 3%)")
steps = np.diff(c["azimuth"][::int(round(period / 0.02))])
ok(np.max(np.abs(steps)) > 5 * np.median(np.abs(steps)),
   "the azimuth moves in steps: its largest change per pendulum period is over 5 times the "
   f"median one ({np.max(np.abs(steps)):.2f} against {np.median(np.abs(steps)):.3f} degrees)")

# ---- info's prediction: the averaged three-wave equations ----------------
def info(d):
    import json
    r = run("info", SWING, "--json", *sets(d))
    return json.loads(r.stdout) if r.returncode == 0 else {"error": r.stderr}


ts = np.arange(0, 240 + 1e-9, 0.02)
for d, note in (({}, "the scene, amplitude 0.05 l"),
                ({"initial.length": 1.02}, "a 2 cm bounce"),
                ({"initial.azimuth_rate": 3}, "a fast turn, near 90 degrees a step"),
                ({"pendulum.stiffness": 38.5}, "0.7% below 2:1")):
    full = {"pendulum.natural_length": 0.75, "pendulum.stiffness": 39.24, "pendulum.mass": 1,
            "initial.length": 1.05, "initial.angle": 1, "initial.azimuth_rate": 1, **d}
    ref = reference(full, ts)
    k = float(full["pendulum.stiffness"])
    period = 2 * math.pi / math.sqrt(G / (0.75 + G / k))
    want, _ = precessions(ts, ref[0], ref[2], period)
    j = info(d)
    pred = math.degrees(j["precession_per_exchange"]) if j.get("precession_per_exchange") \
        is not None else math.nan
    rel = abs(pred - np.mean(want)) / abs(np.mean(want)) if len(want) else math.inf
    ok(j.get("precession_applies") is True and rel < 0.04,
       f"info predicts {pred:.2f} degrees per exchange for {note}; scipy's full motion turns "
       f"by {np.mean(want):.2f} (within the 4% info states: {100 * rel:.1f}%)")
r = run("info", SWING, "--set", "initial.length=1.1")
j = info({"initial.length": 1.1})
ok(j.get("precession_applies") is False and "too large for the averaged" in r.stdout,
   "a 10 cm bounce (0.1 l): info still gives the averaged number but says the theory does "
   "not apply there")
j = info({"pendulum.damping": 0.01})
ok(j.get("precession_applies") is False, "damped: the prediction is marked as not applying")
r = run("info", SWING, "--set", "pendulum.stiffness=60")
j = info({"pendulum.stiffness": 60})
ok(j.get("precession_per_exchange") is None and "not predicted: omega_s / omega_p is further "
   "than 10% from 2" in r.stdout, "far from 2:1: no prediction, and info says why")
j = info({"initial.azimuth_rate": 0})
ok("precession_per_exchange" in j and j["precession_per_exchange"] is None,
   "a planar scene: precession_per_exchange is null")

# ---- the HUD writes a tiny precession as the axes write numbers -----------
SUP = str.maketrans("0123456789-", "\u2070\u00b9\u00b2\u00b3\u2074\u2075\u2076\u2077\u2078\u2079\u207b")


def shown_degrees(deg):
    """Two significant digits; past 6 decimals as m.m×10⁻ⁿ; minus U+2212."""
    sign = "\u2212" if deg < 0 else ""
    e = math.floor(math.log10(abs(deg)))
    if e - 1 < -6:
        mant = round(abs(deg) / 10 ** e, 1)
        if mant >= 10:
            mant, e = mant / 10, e + 1
        return f"{sign}{mant:.1f}\u00d710{str(e).translate(SUP)}\u00b0"
    return f"{sign}{abs(deg):.{1 - e}f}\u00b0"


for rate in (1e-3, 1e-5, 1e-7, -1e-9):
    j = info({"initial.azimuth_rate": rate})
    want = shown_degrees(math.degrees(j["precession_per_exchange"]))
    pdf = os.path.join(work, "tiny.pdf")
    r = run("still", SWING, "--at", "20", "--set", f"initial.azimuth_rate={rate}", "-o", pdf)
    text = ""
    if r.returncode == 0:
        text = subprocess.run(["pdftotext", pdf, "-"], capture_output=True, text=True).stdout
    line = next((t for t in text.split("\n") if "theory" in t), "(no theory line)")
    ok(f"theory \u2248 {want} " in line and "e-" not in line,
       f"azimuth_rate {rate}: the HUD prints info's precession as {want!r}: {line!r}")

# ---- the 3-D panels ------------------------------------------------------
png = os.path.join(work, "panels.png")
r = run("still", SWING, "--at", "200", "--set", "view.panels=azimuth,top", "--size", "640x360",
        "-o", png)
ok(r.returncode == 0 and os.path.getsize(png) > 5000,
   f"view.panels = azimuth, top: a still of the 3-D scene with both panels ({r.stderr.strip()})")
r = run("still", SWING, "--set", "view.panels=azimuth,side", "-o", os.path.join(work, "x.png"))
ok(r.returncode == 2 and "spread, azimuth, top" in r.stderr,
   f"an unknown panel name: exit 2, the list names azimuth and top ({r.stderr.strip()})")

# ---- bad input -----------------------------------------------------------
bad_scene = os.path.join(work, "vertical.ini")
with open(bad_scene, "w") as fh:
    fh.write("[initial]\nangle = 0\nazimuth_rate = 0.5\n")
r = run("data", bad_scene, "-o", os.path.join(work, "no.csv"))
ok(r.returncode == 2 and f"{bad_scene}:3: initial.azimuth_rate" in r.stderr and
   not os.path.exists(os.path.join(work, "no.csv")),
   f"azimuth_rate on a bob that starts on the vertical: FILE:LINE, exit 2, no file "
   f"({r.stderr.strip()})")
# straight down or straight up, however spelt: sin(180 degrees) is 1.2e-16, not 0
for angle in ("180", "360", "-180", "1e-300"):
    with open(bad_scene, "w") as fh:
        fh.write(f"[initial]\nangle = {angle}\nazimuth_rate = 0.5\n")
    r = run("data", bad_scene, "-o", os.path.join(work, "no.csv"))
    ok(r.returncode == 2 and f"{bad_scene}:3: initial.azimuth_rate" in r.stderr and
       not os.path.exists(os.path.join(work, "no.csv")),
       f"azimuth_rate with angle = {angle} (on the vertical): FILE:LINE, exit 2, no file "
       f"({r.stderr.strip()[:120]})")
r = run("data", SWING, "-o", "-", "--set", "initial.azimuth_rate=x")
ok(r.returncode == 2 and "azimuth_rate" in r.stderr, "a non-number azimuth_rate: exit 2")
r = run("data", SWING, "-o", "-", "--set", "ensemble.count=3",
        "--set", "ensemble.key=initial.angle", "--set", "video.duration=1")
ok(r.returncode == 0 and r.stdout.startswith("t,member,initial.angle,x,y,vx,vy,z,vz,azimuth\n"),
   f"[ensemble] of a 3-D scene runs in 3-D: its members' rows have z, vz, azimuth (each "
   f"member against its single run: test ensemble) {r.stderr.strip()}")
r = run("sweep", SWING, "--vary", "pendulum.mass=1:2:2", "--measure", "orbit",
        "--time", "5", "-o", os.path.join(work, "sweep.png"))
ok(r.returncode == 2 and "leaves the x-y plane" in r.stderr and
   not os.path.exists(os.path.join(work, "sweep.png")),
   f"an orbit sweep (theta in the plane) of a 3-D scene is refused, not run flat "
   f"({r.stderr.strip()[:160]}); lyapunov and precession sweep it (test sweep3d)")
done()
