#!/usr/bin/env python3
"""springpend tests: `springpend sweep`, end to end. Shards merged equal the
whole run byte for byte; the thread count changes nothing; Lyapunov exponents
against scipy's DOP853 on the tangent equations (written here, in the lab
frame); a regular orbit's exponent falls like 1/T; blow-ups are NaN and
counted; bad input and Ctrl-C leave nothing; Poincare points lie at the
asked energy; SVG and PDF read back.
usage: test_sweep.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import csv
import io
import math
import os
import shutil
import signal
import struct
import subprocess
import sys
import time

from sptest import done, ok, skip, wait_caught

# The independent reference needs scipy; a python3 without it (a virtual
# environment) hands over to the system's, which Debian's python3-scipy serves.
try:
    import scipy  # noqa: F401
except ImportError:
    if os.path.exists("/usr/bin/python3") and os.path.realpath(sys.executable) != os.path.realpath("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3", *sys.argv])

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "sweep"))
scenes = os.path.join(src, "..", "scenes")
chaotic = os.path.join(scenes, "chaotic.ini")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def run(*args):
    return subprocess.run([exe, "sweep", *args], capture_output=True, text=True, cwd=work)


def read(name):
    with open(os.path.join(work, name), "rb") as f:
        return f.read()


def rows(name):
    """The rows of a CSV sweep wrote: no comment lines, the header first."""
    with open(os.path.join(work, name)) as f:
        return list(csv.DictReader(f))


# ---- shards and threads: the same bytes -----------------------------------
grid = ["--vary", "initial.angle=20:160:7", "--vary", "initial.length=0.9:1.5:5",
        "--measure", "lyapunov", "--time", "4", "--set", "integrator.dt=0.002", "-q"]
r = run(chaotic, *grid, "-o", "whole.png", "--csv", "whole.csv")
ok(r.returncode == 0, f"a 7x5 Lyapunov map runs (exit {r.returncode}) {r.stderr.strip()}")
r1 = run(chaotic, *grid, "--threads", "1", "-o", "one.png", "--csv", "one.csv")
ok(r1.returncode == 0 and read("one.csv") == read("whole.csv") and read("one.png") == read("whole.png"),
   "one thread gives the same CSV and PNG bytes as one per core")
for n in (2, 3, 7):
    parts = []
    for i in range(1, n + 1):
        rr = run(chaotic, *grid, "--shard", f"{i}/{n}", "--csv", f"part{n}_{i}.csv")
        parts.append(f"part{n}_{i}.csv")
        if rr.returncode:
            print("#", rr.stderr)
    parts.reverse()  # any order
    rr = run("--merge", *parts, "-o", f"merged{n}.png", "--csv", f"merged{n}.csv", "-q")
    ok(rr.returncode == 0 and read(f"merged{n}.csv") == read("whole.csv") and
       read(f"merged{n}.png") == read("whole.png"),
       f"{n} shards merged give the whole run's CSV and PNG bytes (exit {rr.returncode}) {rr.stderr.strip()}")
rr = run("--merge", "part3_1.csv", "part3_2.csv", "-o", "bad.png")
ok(rr.returncode == 2 and "give all 3" in rr.stderr and not os.path.exists(os.path.join(work, "bad.png")),
   f"a missing shard is refused: {rr.stderr.strip()}")
rr = run("--merge", "part3_1.csv", "part2_2.csv", "part3_3.csv", "-o", "bad.png")
ok(rr.returncode == 2 and not os.path.exists(os.path.join(work, "bad.png")),
   f"shards of another sweep are refused: {rr.stderr.strip()}")

orbit = ["--vary", "pivot.amplitude=0:0.05:13", "--measure", "orbit", "--transient", "2",
         "--time", "6", "-q"]
parametric = os.path.join(scenes, "parametric.ini")
run(parametric, *orbit, "-o", "orbit.png", "--csv", "orbit.csv")
for i in (1, 2, 3, 4):
    run(parametric, *orbit, "--shard", f"{i}/4", "--csv", f"orbit_{i}.csv")
rr = run("--merge", *[f"orbit_{i}.csv" for i in (1, 2, 3, 4)], "-o", "orbit_m.png", "--csv", "orbit_m.csv")
ok(rr.returncode == 0 and read("orbit_m.csv") == read("orbit.csv") and read("orbit_m.png") == read("orbit.png"),
   "an orbit diagram's 4 shards merged give the whole run's bytes")
samples = rows("orbit.csv")
ok(len(samples) == 13 * 11 and all(abs(float(s["t"]) * 1.8 - round(float(s["t"]) * 1.8)) < 1e-9 for s in samples),
   f"orbit samples fall once per drive period, t = k / f, after the transient ({len(samples)} rows)")

# ---- Lyapunov exponents against scipy -------------------------------------
try:
    import numpy as np
    from scipy.integrate import solve_ivp
except ImportError:
    np = None


def lyapunov_scipy(theta0_deg, r0, k=39.24, m=1.0, L0=0.75, g=9.81, T=40.0):
    """Benettin with scipy's DOP853 on the state and one tangent vector,
    renormalised every second; returns lambda at T/2 and T."""
    km = k / m

    def f(t, s):
        x, y, vx, vy, dx, dy, dvx, dvy = s
        rho = math.hypot(x, y)
        c = km * (1 - L0 / rho)
        a = km * L0 / rho ** 3
        jxx, jxy, jyy = -c - a * x * x, -a * x * y, -c - a * y * y
        return [vx, vy, -c * x, -c * y - g, dvx, dvy, jxx * dx + jxy * dy, jxy * dx + jyy * dy]

    th = math.radians(theta0_deg)
    s = np.array([r0 * math.sin(th), -r0 * math.cos(th), 0, 0, 1, 0, 0, 0], float)
    total, out = 0.0, {}
    for k1 in range(1, int(T) + 1):
        sol = solve_ivp(f, (k1 - 1, k1), s, method="DOP853", rtol=1e-11, atol=1e-12)
        s = sol.y[:, -1]
        n = math.sqrt(sum(s[4:] ** 2))
        total += math.log(n)
        s[4:] /= n
        if k1 in (T / 2, T):
            out[k1] = total / k1
    return out[T / 2], out[T]


if np is None:
    ok(True, "# SKIP scipy is missing: no independent Lyapunov check")
else:
    # chaotic.ini's start, and chaotic.ini's regular neighbour (60 deg, 1.6 m
    # with L0 = 0.5, k = 19.62, l = 1 m)
    cases = [("chaotic.ini's start", 85.94, 1.2, 39.24, 0.75),
             ("a regular orbit", 60.0, 1.6, 19.62, 0.5)]
    for what, th, r0, k, L0 in cases:
        rr = run(chaotic, "--vary", f"initial.angle={th}:{th}:1", "--set", f"initial.length={r0}",
                 "--set", f"pendulum.stiffness={k}", "--set", f"pendulum.natural_length={L0}",
                 "--set", "integrator.dt=0.0005", "--measure", "lyapunov", "--time", "40",
                 "-o", "l.png", "--csv", "l.csv", "-q")
        got = rows("l.csv")[0]
        lam, half = float(got["lyapunov"]), float(got["lyapunov_half"])
        ref_half, ref = lyapunov_scipy(th, r0, k=k, L0=L0)
        ok(rr.returncode == 0 and abs(lam - ref) <= 0.02 * abs(ref) + 2e-3 and
           abs(half - ref_half) <= 0.02 * abs(ref_half) + 2e-3,
           f"{what}: lambda {lam:.5f} (T/2: {half:.5f}) 1/s; scipy DOP853 {ref:.5f} ({ref_half:.5f})")
        if what.startswith("a regular"):
            ok(0.35 < lam / half < 0.65, f"{what}: lambda(T) / lambda(T/2) = {lam / half:.3f}, "
               "about 1/2: it falls like 1/T")
        else:
            ok(lam > 0.1 and 0.6 < lam / half < 1.6,
               f"{what}: lambda(T) / lambda(T/2) = {lam / half:.3f}: converging to a positive value")

# ---- --fast: the batch's fast kernel (FMA, 1/rho without the divider) -------
fast_ok = subprocess.run([exe, "sweep", chaotic, "--vary", "initial.angle=10:10:1", "--measure",
                          "lyapunov", "--time", "1", "--fast", "-o", "-", "-q"],
                         capture_output=True, text=True, cwd=work)
if "lacks" in fast_ok.stderr:
    ok(fast_ok.returncode == 2, f"--fast on a CPU without AVX-512F is refused: {fast_ok.stderr.strip()}")
else:
    # within rounding of the exact kernel: over 4 s (before chaos has grown the
    # last bits' difference) the exponents agree to 1e-9 at every point
    fgrid = ["--vary", "initial.angle=1:179:33", "--vary", "initial.length=0.9:1.5:3", "--measure",
             "lyapunov", "--time", "4", "-q"]
    a, b = run(chaotic, *fgrid, "--csv", "exact.csv", "-o", "exact.png"), \
        run(chaotic, *fgrid, "--fast", "--csv", "fast.csv", "-o", "fast.png")
    ea, eb = rows("exact.csv"), rows("fast.csv")
    worst = max((abs(float(x["lyapunov"]) - float(y["lyapunov"])) for x, y in zip(ea, eb)), default=1)
    ok(a.returncode == 0 and b.returncode == 0 and len(ea) == len(eb) == 99 and worst < 1e-9,
       f"--fast: 99 points over 4 s, lambda within {worst:.1e} 1/s of the exact kernel's")
    ok(b"kernel=fast" in read("fast.csv-metadata.json") and b"kernel=fast" not in read("exact.csv-metadata.json"),
       "--fast is recorded in the sweep's description (kernel=fast); the exact kernel's is unchanged")
    # and against scipy, as the exact kernel above
    if np is not None:
        for what, th, r0, k, L0 in cases:
            rr = run(chaotic, "--vary", f"initial.angle={th}:{th}:1", "--set", f"initial.length={r0}",
                     "--set", f"pendulum.stiffness={k}", "--set", f"pendulum.natural_length={L0}",
                     "--set", "integrator.dt=0.0005", "--measure", "lyapunov", "--time", "40",
                     "--fast", "-o", "-", "-q")
            got = list(csv.DictReader(io.StringIO(rr.stdout)))[0]
            lam, half = float(got["lyapunov"]), float(got["lyapunov_half"])
            ref_half, ref = lyapunov_scipy(th, r0, k=k, L0=L0)
            ok(rr.returncode == 0 and abs(lam - ref) <= 0.02 * abs(ref) + 2e-3 and
               abs(half - ref_half) <= 0.02 * abs(ref_half) + 2e-3,
               f"--fast, {what}: lambda {lam:.5f} (T/2: {half:.5f}) 1/s; scipy DOP853 {ref:.5f} ({ref_half:.5f})")
    # shards of the two kernels are two sweeps
    for i, f in ((1, []), (2, ["--fast"])):
        run(chaotic, *fgrid, *f, "--shard", f"{i}/2", "--csv", f"mixed_{i}.csv")
    rr = run("--merge", "mixed_1.csv", "mixed_2.csv", "-o", "mixed.png")
    ok(rr.returncode == 2 and "kernel=fast" in rr.stderr and not os.path.exists(os.path.join(work, "mixed.png")),
       f"an exact and a fast shard do not merge: {rr.stderr.strip()[:200]}")
# what the fast kernel does not step is refused, not silently stepped exactly
for args, why in (([os.path.join(scenes, "damped.ini")], "damping"), ([chaotic, "--set", "integrator.method=yoshida4"], "yoshida4"),
                  ([chaotic, "--set", "pendulum.damping=0.1"], "damping"),
                  ([chaotic, "--measure", "spectrum"], "spectrum")):
    meas = [] if "--measure" in args else ["--measure", "lyapunov"]
    rr = run(*args, "--vary", "initial.angle=10:20:2", *meas, "--time", "1", "--fast", "-o", "x.png")
    ok(rr.returncode == 2 and "--fast" in rr.stderr and not os.path.exists(os.path.join(work, "x.png")),
       f"--fast with {why}: refused ({rr.stderr.strip()[:160]})")

# ---- the route to chaos against scipy ----------------------------------------
def strobe_scipy(amp, f=1.8, k=400.0, m=1.0, L0=0.25, g=9.81, b=0.3, r0=0.2745, th0=5.0,
                 t0=100.0, t1=120.0):
    """theta (degrees) once per drive period, t = n / f in [t0, t1], integrated
    in the lab frame (pivot at y_p = A sin(2 pi f t), air at rest)."""
    w = 2 * math.pi * f

    def rhs(t, s):
        x, y, vx, vy = s
        dy = y - amp * math.sin(w * t)
        rho = math.hypot(x, dy)
        c = k / m * (1 - L0 / rho)
        return [vx, vy, -c * x - b / m * vx, -c * dy - g - b / m * vy]

    th = math.radians(th0)
    s0 = [r0 * math.sin(th), -r0 * math.cos(th), 0.0, amp * w]  # at rest relative to the pivot
    times = [n / f for n in range(math.ceil(t0 * f), math.floor(t1 * f) + 1)]
    sol = solve_ivp(rhs, (0, times[-1]), s0, method="DOP853", rtol=1e-10, atol=1e-12, t_eval=times)
    return [math.degrees(math.atan2(x, -(y - amp * math.sin(w * t))))
            for t, x, y in zip(sol.t, sol.y[0], sol.y[1])]


def distinct(values, tol=0.5):
    out = []
    for v in sorted(values):
        if not out or v - out[-1] > tol:
            out.append(v)
    return out


if np is not None:
    rr = run(parametric, "--vary", "pivot.amplitude=0.005:0.031:3", "--measure", "orbit",
             "--transient", "100", "--time", "20", "-o", "route.png", "--csv", "route.csv", "-q")
    got = rows("route.csv")
    for amp, kind in ((0.005, "period 1"), (0.018, "period 2"), (0.031, "chaos")):
        ours = [float(s["theta"]) for s in got if abs(float(s["pivot.amplitude"]) - amp) < 1e-9]
        ref = strobe_scipy(amp)
        a, b = distinct(ours), distinct(ref)
        if kind == "chaos":
            good = len(a) > 10 and len(b) > 10
        else:
            n = 1 if kind == "period 1" else 2
            good = len(a) == n and len(b) == n and all(abs(x - y) < 0.2 for x, y in zip(a, b))
        ok(rr.returncode == 0 and good, f"parametric.ini at A = {amp} m: {kind}; springpend's "
           f"stroboscopic theta takes {len(a)} values {[round(x, 2) for x in a[:4]]}, scipy's "
           f"(lab frame, DOP853) {len(b)} {[round(x, 2) for x in b[:4]]}")

# ---- blow-ups, bad input, interruption -------------------------------------
rr = run(os.path.join(scenes, "default.ini"), "--vary", "pendulum.stiffness=2:5e6:2",
         "--measure", "lyapunov", "--time", "2", "-o", "blow.png", "--csv", "blow.csv", "-q")
got = rows("blow.csv")
ok(rr.returncode == 0 and "1 of 2 points blew up" in rr.stderr and got[1]["lyapunov"] == "nan" and
   got[0]["lyapunov"] != "nan" and os.path.exists(os.path.join(work, "blow.png")),
   f"an unstable grid point is NaN and counted, the sweep goes on: {rr.stderr.strip()}")

bad = [(["--vary", "video.width=100:200:3"], "only the physics can be varied"),
       (["--vary", "pendulum.mas=1:2:3"], "no such numeric key"),
       (["--vary", "pendulum.mass=-1:2:3"], "pendulum.mass = -1 is out of range"),
       (["--vary", "initial.angle=1:2"], "expected KEY=FROM:TO:COUNT"),
       (["--vary", "initial.angle=1:2:100000", "--vary", "initial.length=1:2:1000"], "at most 50000000"),
       (["--vary", "initial.angle=1:2:3", "--measure", "nope"], "use lyapunov, spectrum, orbit, poincare, basins or precession")]
for args, want in bad:
    rr = run(chaotic, *args, "--measure", "lyapunov", "--time", "1", "-o", "bad.png", "--csv", "bad.csv")
    if "--measure" in args[2:]:
        rr = run(chaotic, *args, "--time", "1", "-o", "bad.png", "--csv", "bad.csv")
    ok(rr.returncode == 2 and want in rr.stderr and not any(f.startswith("bad.") for f in os.listdir(work)),
       f"bad input {' '.join(args)}: exit 2, nothing written: {rr.stderr.strip()}")

# --time is measured as given, or refused: fixed steps renormalise on the grid
# every tau = 1 s, so T is a whole number of seconds, at least 2 (0.001 used to
# measure 2 s, 2.6 measured 3 s, silently); dop853 splits T into equal
# intervals of at most a second (2.5 s used to be 3); 1e-300 gave NaN rows.
damped, driven = os.path.join(scenes, "damped.ini"), os.path.join(scenes, "driven.ini")
for scene, t, want in ((damped, "0.001", "at least 2; use --time 2"), (damped, "2.6", "use --time 2 or 3"),
                       (driven, "1e-300", "too short to measure")):
    for measure in ("lyapunov", "spectrum"):
        rr = run(scene, "--vary", "initial.angle=0:10:3", "--measure", measure, "--time", t,
                 "-o", "short.png", "--csv", "short.csv")
        ok(rr.returncode == 2 and f"--time {t}:" in rr.stderr and want in rr.stderr and
           not any(f.startswith("short.") for f in os.listdir(work)),
           f"{measure} --time {t} on {os.path.basename(scene)}: refused, exit 2: {rr.stderr.strip()}")
rr = run(driven, "--vary", "initial.angle=0:10:2", "--measure", "spectrum", "--time", "2.5", "-q",
         "-o", "t25.png", "--csv", "t25.csv")
ts = [float(r["T"]) for r in rows("t25.csv")] if rr.returncode == 0 else []
ok(ts and max(ts) == 2.5, f"spectrum --time 2.5 with dop853 measures T = 2.5 s (checkpoints {sorted(set(ts))})")

p = subprocess.Popen([exe, "sweep", chaotic, "--vary", "initial.angle=1:179:2000", "--measure",
                      "lyapunov", "--time", "200", "-o", "int.png", "--csv", "int.csv"],
                     cwd=work, stderr=subprocess.PIPE, text=True)
wait_caught(p, signal.SIGINT)
time.sleep(1.0)
p.send_signal(signal.SIGINT)
try:
    err = p.communicate(timeout=30)[1]
except subprocess.TimeoutExpired:
    p.kill()
    err = p.communicate()[1]
left = [f for f in os.listdir(work) if f.startswith("int.")]
ok(p.returncode == 130 and not left, f"Ctrl-C stops a sweep: exit {p.returncode}, nothing left {left}: {err.strip()}")

# A long --transient is one integration call per chunk of points: a signal
# during it still stops the sweep at once (fixed steps look every 65536 steps,
# dop853 every step), leaving nothing. Without the look it ran for minutes.
for scene, sig in (("damped.ini", signal.SIGINT), ("driven.ini", signal.SIGTERM)):
    for measure in ("lyapunov", "spectrum"):
        p = subprocess.Popen([exe, "sweep", os.path.join(scenes, scene), "--vary",
                              "initial.angle=1:10:3", "--measure", measure, "--time", "2",
                              "--transient", "1e6", "-q", "-o", "tr.png", "--csv", "tr.csv"],
                             cwd=work, stderr=subprocess.PIPE, text=True)
        wait_caught(p, sig)
        time.sleep(1.5)
        t0 = time.monotonic()
        p.send_signal(sig)
        try:
            err = p.communicate(timeout=20)[1]
        except subprocess.TimeoutExpired:
            p.kill()
            err = p.communicate()[1] + " (still running 20 s after the signal: killed)"
        took = time.monotonic() - t0
        left = [f for f in os.listdir(work) if f.startswith("tr.")]
        ok(p.returncode == 128 + sig and took < 10 and not left,
           f"{measure} on {scene} (--transient 1e6): {sig.name} during the transient stops it in "
           f"{took:.2f} s, exit {p.returncode}, nothing left {left}: {err.strip()}")

# ---- the progress bar, on a terminal only ------------------------------------
import pty
master, slave = pty.openpty()
p = subprocess.Popen([exe, "sweep", chaotic, "--vary", "initial.angle=1:179:64", "--measure", "lyapunov",
                      "--time", "2", "-o", "bar.png"], cwd=work, stderr=slave, stdout=subprocess.DEVNULL)
os.close(slave)
seen = b""
while True:
    try:
        chunk = os.read(master, 4096)
    except OSError:
        break
    if not chunk:
        break
    seen += chunk
p.wait()
os.close(master)
text = seen.decode(errors="replace")
ok(p.returncode == 0 and "point 64/64" in text and "ETA" in text and "wrote bar.png" in text,
   f"a terminal gets a progress bar with the ETA: {text.strip().splitlines()[-1] if text.strip() else ''}")
rr = run(chaotic, "--vary", "initial.angle=1:179:64", "--measure", "lyapunov", "--time", "2", "-o", "nobar.png")
ok(rr.returncode == 0 and "ETA" not in rr.stderr, "a pipe gets no progress bar")

# ---- Poincare points at one energy ------------------------------------------
rr = run(chaotic, "--vary", "initial.length=0.7:1.5:9", "--set", "initial.angle=0",
         "--measure", "poincare", "--energy", "-6", "--time", "20", "-o", "pm.png", "--csv", "pm.csv", "-q")
got = rows("pm.csv")
m, k, L0, g = 1.0, 39.24, 0.75, 9.81
worst = max(abs(0.5 * m * (float(s["r_dot"]) ** 2 + (float(s["r"]) * float(s["theta_dot"])) ** 2) +
                0.5 * k * (float(s["r"]) - L0) ** 2 - m * g * float(s["r"]) + 6) for s in got
            if s["r"] != "nan")  # not the rows of starts that cannot have E (one each)
ok(rr.returncode == 0 and len(got) > 50 and worst < 1e-3,
   f"Poincare mosaic: {len(got)} section points, all at E = -6 J within {worst:.2g} J")
ok("cannot have energy" in rr.stderr, f"starts that cannot reach the energy are skipped and said: {rr.stderr.strip()}")

# ---- vector outputs ----------------------------------------------------------
small = ["--vary", "initial.angle=20:160:4", "--vary", "initial.length=1:1.4:3", "--measure",
         "lyapunov", "--time", "2", "-q"]
for ext in ("svg", "pdf"):
    rr = run(chaotic, *small, "-o", f"map.{ext}")
    path = os.path.join(work, f"map.{ext}")
    if ext == "svg" and shutil.which("rsvg-convert"):
        conv = subprocess.run(["rsvg-convert", path, "-o", path + ".png"], capture_output=True)
        ok(rr.returncode == 0 and conv.returncode == 0 and os.path.getsize(path + ".png") > 1000,
           "the SVG map reads back with rsvg-convert")
    elif ext == "pdf" and shutil.which("pdftotext"):
        text = subprocess.run(["pdftotext", path, "-"], capture_output=True, text=True).stdout
        ok(rr.returncode == 0 and "Lyapunov" in text and "initial.length" in text,
           "the PDF map keeps its text (title and axis labels)")
    else:
        ok(rr.returncode == 0 and os.path.getsize(path) > 1000, f"the {ext} map is written")

# ---- --merge refuses what is not a whole shard, for every measure ----------
# An orbit or Poincare shard cut at a line boundary, a Lyapunov row copied
# over another, nan, inf and hex floats: all were merged and drawn, exit 0.
# Each damage is tried as it is (the metadata's SHA-256 no longer matches)
# and with the metadata's row count and SHA-256 made to match again (the row
# checks alone).
import hashlib  # noqa: E402
import json  # noqa: E402


def reseal(text, meta):
    """The shard's metadata written for what the CSV now holds."""
    m = dict(meta)
    m["dc:extent"] = len(text.splitlines()) - 1
    m["schema:sha256"] = hashlib.sha256(text.encode()).hexdigest()
    return m


poinc = ["--vary", "initial.length=0.7:1.5:6", "--set", "initial.angle=0", "--measure", "poincare",
         "--time", "10", "-q"]
for i in (1, 2):
    run(chaotic, *poinc, "--shard", f"{i}/2", "--csv", f"poinc_{i}.csv")
shards = {"lyapunov": ["part2_1.csv", "part2_2.csv"],
          "orbit": [f"orbit_{i}.csv" for i in (1, 2, 3, 4)],
          "poincare": ["poinc_1.csv", "poinc_2.csv"]}
whole4 = [f"orbit_{i}.csv" for i in (1, 2, 3, 4)]
rr = run("--merge", *whole4, "-o", "orbit_again.png", "--csv", "orbit_again.csv")
meta1 = json.loads(read("orbit_1.csv-metadata.json"))
ok(rr.returncode == 0 and read("orbit_again.csv") == read("orbit.csv") and
   meta1["schema:position"] == "1/4" and
   meta1["schema:sha256"] == hashlib.sha256(read("orbit_1.csv")).hexdigest() and
   meta1["dc:extent"] == len(read("orbit_1.csv").splitlines()) - 1 and
   not any(l.startswith(b"#") for l in read("orbit_1.csv").splitlines()),
   "a shard's metadata holds its position, row count and SHA-256, the CSV no comment line; "
   "the merge gives the same bytes as one run")


def damages(text, measure):
    lines = text.splitlines(True)
    body = list(range(1, len(lines)))
    # the first measured row (a point without a crossing, or that cannot
    # have the energy, writes one row of nan of its own)
    first, last = next(i for i in body if "nan" not in lines[i]), body[-1]
    cells = lines[first].rstrip("\n").split(",")
    out = {"cut at a line boundary": "".join(lines[:last]),
           "a row's number changed": text.replace(lines[first], ",".join(cells[:-1] + [cells[-1] + "1"]) + "\n", 1),
           "a comment line": "# springpend\n" + text}
    for bad in ("nan", "inf", "-inf", "0x1p-2", " 1", "1e999"):
        out[f"value {bad!r}"] = text.replace(lines[first], ",".join(cells[:-1] + [bad]) + "\n", 1)
    # finite decimals that printf's %g and %f never write: an edit, even with
    # the SHA-256 recomputed (attacker's pass 2, finding 13)
    for bad in ("+0.5", ".5", "-0", "5.", "1E5", "1e5", "05", "1e+5"):
        out[f"value in a form springpend never writes {bad!r}"] = text.replace(
            lines[first], ",".join(cells[:-1] + [bad]) + "\n", 1)
    out["key value edited"] = text.replace(lines[first], ",".join([cells[0], cells[1] + "5"] + cells[2:]) + "\n", 1)
    out["point out of the shard"] = text.replace(lines[first], ",".join(["999"] + cells[1:]) + "\n", 1)
    if measure == "lyapunov":
        dup = lines[:]
        dup[first + 1] = dup[first]
        out["a row copied over the next"] = "".join(dup)
    else:
        swap = lines[:]
        swap[first], swap[last] = swap[last], swap[first]
        out["rows out of order"] = "".join(swap)
    return out


for measure, (a, *rest) in shards.items():
    base = read(a).decode()
    meta = json.loads(read(a + "-metadata.json"))
    for what, text in damages(base, measure).items():
        for sealed in (False, True):
            # a resealed shard of fewer rows or another number is whole to
            # the row rules (a point's crossings may be any number): only
            # the SHA-256 of the original knows
            if sealed and (what == "a row's number changed" or
                           (what.startswith("cut") and measure != "lyapunov")):
                continue
            name = f"bad_{measure}.csv"
            with open(os.path.join(work, name), "w") as f:
                f.write(text)
            with open(os.path.join(work, name + "-metadata.json"), "w") as f:
                json.dump(reseal(text, meta) if sealed else meta, f)
            if os.path.exists(os.path.join(work, "bad_merge.png")):
                os.remove(os.path.join(work, "bad_merge.png"))
            rr = run("--merge", name, *rest, "-o", "bad_merge.png", "-q")
            ok(rr.returncode == 2 and name + ":" in rr.stderr and
               not os.path.exists(os.path.join(work, "bad_merge.png")) and
               not [f for f in os.listdir(work) if f.endswith(".part")],
               f"--merge refuses a {measure} shard with {what}{' (metadata resealed)' if sealed else ''}: "
               f"exit {rr.returncode} {rr.stderr.strip()[:160]}")

# ---- --merge refuses shards of different sweeps, naming the difference ------
# The sweep CSV's header lacked the --set overrides and the physics, so halves
# computed with different stiffness were merged without a word.
lyap = ["--vary", "initial.angle=10:40:6", "--measure", "lyapunov", "--time", "2", "-q"]
run(chaotic, *lyap, "--shard", "1/2", "--csv", "mm_1.csv")
run(chaotic, *lyap, "--shard", "2/2", "--csv", "mm_2.csv")
run(chaotic, *lyap, "--shard", "1/2", "--csv", "mm_set.csv", "--set", "pendulum.stiffness=40")
with open(chaotic) as f:
    stiffer = f.read().replace("stiffness      = 39.24", "stiffness      = 40")
assert stiffer != open(chaotic).read()
with open(os.path.join(work, "chaotic.ini"), "w") as f:
    f.write(stiffer)
run(os.path.join(work, "chaotic.ini"), *lyap, "--shard", "1/2", "--csv", "mm_file.csv")
run(chaotic, *lyap, "--shard", "1/2", "--csv", "mm_ver.csv")
m = json.loads(read("mm_ver.csv-metadata.json"))
m["schema:softwareVersion"] = "0.0.1"
with open(os.path.join(work, "mm_ver.csv-metadata.json"), "w") as f:
    json.dump(m, f)
run(chaotic, *lyap[:1], "initial.angle=10:40:7", *lyap[2:], "--shard", "1/2", "--csv", "mm_grid.csv")
rr = run("--merge", "mm_1.csv", "mm_2.csv", "-o", "mm.png")
ok(rr.returncode == 0, f"the two halves of one sweep merge: {rr.stderr.strip()}")
for part, want in (("mm_set.csv", "the --set overrides differ (mm_set.csv: --set pendulum.stiffness=40; mm_2.csv: no --set)"),
                   ("mm_file.csv", "the scene differs (mm_file.csv: [pendulum] stiffness = 40; mm_2.csv: [pendulum] stiffness = 39.24)"),
                   ("mm_ver.csv", "springpend's version differs (mm_ver.csv: 0.0.1; mm_2.csv: 0.1.0)"),
                   ("mm_grid.csv", "the sweep (grid, measure or span) differs (mm_grid.csv: vary=initial.angle=10:40:7; mm_2.csv: vary=initial.angle=10:40:6)")):
    rr = run("--merge", part, "mm_2.csv", "-o", "mm_bad.png", "--csv", "mm_bad.csv")
    ok(rr.returncode == 2 and want in rr.stderr and
       not [f for f in os.listdir(work) if f.startswith("mm_bad")],
       f"--merge refuses {part}: {want}: exit {rr.returncode} {rr.stderr.strip()[:300]}")
rr = run("--merge", *whole4[:3], "orbit_4.csv", "-o", "orbit_ok.png", "-q")
ok(rr.returncode == 0, "the same shards, undamaged, merge")

# A FIFO (or a device) as a shard blocked the merge forever; SIGTERM then gave
# exit 2. Refused at once now, without waiting for a writer.
fifo = os.path.join(work, "fifo.csv")
os.mkfifo(fifo)
t0 = time.monotonic()
try:
    rr = subprocess.run([exe, "sweep", "--merge", "fifo.csv", "part2_2.csv", "-o", "fifo.png", "-q"],
                        capture_output=True, text=True, cwd=work, timeout=20)
    ok(rr.returncode == 2 and "FIFO" in rr.stderr and time.monotonic() - t0 < 10 and
       not os.path.exists(os.path.join(work, "fifo.png")),
       f"a FIFO shard is refused at once: exit {rr.returncode} {rr.stderr.strip()}")
except subprocess.TimeoutExpired:
    ok(False, "a FIFO shard is refused at once (it blocked for 20 s)")
# A signal that cuts a wait gives 128 + N, whatever the cut call reports: the
# figure is a FIFO with no reader, so opening it waits until SIGTERM.
out_fifo = os.path.join(work, "fig_fifo.png")
os.mkfifo(out_fifo)
p = subprocess.Popen([exe, "sweep", "--merge", "part2_1.csv", "part2_2.csv", "-o", "fig_fifo.png", "-q"],
                     cwd=work, stderr=subprocess.PIPE, text=True)
wait_caught(p, signal.SIGTERM)
time.sleep(1.5)
p.send_signal(signal.SIGTERM)
try:
    err = p.communicate(timeout=20)[1]
except subprocess.TimeoutExpired:
    p.kill()
    err = p.communicate()[1]
ok(p.returncode == 128 + signal.SIGTERM and not [f for f in os.listdir(work) if f.endswith(".part")],
   f"SIGTERM while waiting to write the figure: exit 143, no .part: {p.returncode} {err.strip()[:160]}")

# ---- a map wider than cairo's 32767 pixels ----------------------------------
# 40000 x 2 points crashed (SIGSEGV: cairo refused the image, the plotter wrote
# through NULL) and left .part files. The map's image is downsampled to 2048.
rr = run(chaotic, "--vary", "initial.angle=10:170:40000", "--vary", "initial.length=1:1.2:2",
         "--measure", "lyapunov", "--time", "2", "--set", "integrator.dt=0.01", "-o", "wide.png", "-q")
head = b""
if os.path.exists(os.path.join(work, "wide.png")):
    with open(os.path.join(work, "wide.png"), "rb") as f:
        head = f.read(24)
ok(rr.returncode == 0 and head[:8] == b"\x89PNG\r\n\x1a\n" and
   struct.unpack(">II", head[16:24]) == (1800, 1200) and
   not [f for f in os.listdir(work) if f.endswith(".part")],
   f"a 40000-column Lyapunov map is drawn (downsampled), no .part left: exit {rr.returncode} "
   f"{rr.stderr.strip()[:160]}")

# ---- memory stays flat in --time ---------------------------------------------
# An orbit sweep held every row of the chunks in flight: 19, 54 and 122 MB
# peak at T = 30, 100 and 300 s (256 points, 8 threads). Rows now stream
# through a temporary file; the peak must not follow T (the CSV grows 10x).


def peak_rss(*args):
    """Exit status and peak resident set (MiB) of one sweep, from GNU time
    (a child forked from this Python would count the interpreter's pages)."""
    r = subprocess.run(["/usr/bin/time", "-f", "maxrss %M", exe, "sweep", *args], cwd=work,
                       capture_output=True, text=True)
    kib = [int(l.split()[1]) for l in r.stderr.splitlines() if l.startswith("maxrss ")]
    return r.returncode, kib[-1] / 1024 if kib else float("nan")


# A sanitizer build keeps freed memory in quarantine (peak RSS then follows
# what was ever allocated), so only a plain build is measured.
sanitized = "libasan" in subprocess.run(["ldd", exe], capture_output=True, text=True).stdout
mem = []
for T in (15, 150) if os.path.exists("/usr/bin/time") and not sanitized else ():
    mem.append(peak_rss(os.path.join(scenes, "default.ini"), "--set", "pivot.amplitude=0.001",
                        "--vary", "pivot.frequency=20:40:128", "--measure", "orbit", "--time", str(T),
                        "--threads", "8", "-q", "-o", f"mem{T}.png", "--csv", f"mem{T}.csv"))
if not mem:
    skip("orbit sweep peak memory does not follow --time",
         "a sanitizer build" if sanitized else "/usr/bin/time (GNU time) is missing")
else:
    sizes = [os.path.getsize(os.path.join(work, f"mem{T}.csv")) / 2 ** 20 for T in (15, 150)]
    ok(mem[0][0] == 0 and mem[1][0] == 0 and mem[1][1] < mem[0][1] + 8,
       f"orbit sweep peak memory does not follow --time: {mem[0][1]:.0f} MiB at T = 15 s, "
       f"{mem[1][1]:.0f} MiB at 150 s (CSV {sizes[0]:.1f} -> {sizes[1]:.1f} MiB)")

done()
