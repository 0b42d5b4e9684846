#!/usr/bin/env python3
"""springpend tests (issue 28): the nineteenth attacker's pass
(doc/notes/2026-11-28/attack19.md), finding 1: the adaptive work estimate's
own probe spanned 100 radians of the pendulum's motion, not of a fast
drive's, so at a 1e6 Hz drive one probe integrated 1.6e7 drive periods
(about 20 s) with no cancel flag: a sweep probing 256 points ran for tens of
minutes before its first word and ignored SIGTERM and SIGINT. The probe now
spans 100 radians of the fastest motion (the drive's too), stops after about
2e4 steps and scales what it took, and a signal stops it. A batched DOP853
step costs about 20 rk4 steps, so a sweep's limits count them so.

What is checked:
- the driven one-point sweep says its estimate at once and stops within
  seconds of SIGTERM, exit 143, nothing written (before: 20 s deaf);
- the 300-point grid over the drive frequency is refused at once, exit 2,
  naming the limit (before: 20+ minutes of probes, no word);
- data and still with that drive stop within seconds of SIGTERM;
- the estimate's steps per simulated second are within a factor of 4 of
  scipy's DOP853 at the same tolerance, counted in the test;
- a DOP853 Lyapunov map of about 4 minutes announces itself (before: under
  the note, silent).
usage: test_attack19_probe.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import re
import signal
import subprocess
import time

import sptest
from sptest import done, ok

sptest.need_scipy()
from scipy.integrate import solve_ivp  # noqa: E402

exe, src, work, _ = sptest.setup("attack19-probe", [])
scenes = os.path.abspath(os.path.join(src, "..", "scenes"))
chaotic = os.path.join(scenes, "chaotic.ini")
DRIVE = ["--set", "pivot.amplitude=0.001", "--set", "integrator.method=dop853"]


def started(*args):
    return subprocess.Popen([exe, *args], cwd=work, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)


def stopped_by_term(args, after, out, what):
    """Starts springpend, sends SIGTERM `after` s later, and checks it leaves
    within 10 s with 143 and no output."""
    p = started(*args)
    sptest.wait_caught(p, signal.SIGTERM)
    time.sleep(after)
    t0 = time.time()
    p.send_signal(signal.SIGTERM)
    try:
        _, err = p.communicate(timeout=10)
        left = time.time() - t0
    except subprocess.TimeoutExpired:
        p.kill()
        _, err = p.communicate()
        left = 99
    sptest.diag(f"{what}: exit {p.returncode} {left:.1f} s after SIGTERM; {err.strip()[-200:]}")
    ok(p.returncode == 143 and left < 10 and not os.path.exists(os.path.join(work, out)),
       f"{what}: SIGTERM stops it within 10 s, exit 143, nothing written")
    return err


# 1. The driven point: the estimate at once, then a signal heard.
one = ["sweep", chaotic, "--vary", "pivot.frequency=1e6:1e6:1", "--measure", "lyapunov",
       "--time", "100", *DRIVE, "-o", "one.png"]
err = stopped_by_term(one, 3, "one.png", "a sweep of one point driven at 1e6 Hz")
m = re.search(r"\(([0-9.e+]+) steps per simulated second|about ([0-9.e+]+) steps a point", err)
ok("steps in all" in err and "tolerance 1e-09" in err, "it said its estimate before the signal")

# 2. The grid: refused at once.
t0 = time.time()
try:
    r = subprocess.run([exe, "sweep", chaotic, "--vary", "pivot.frequency=1e5:1e6:300", "--measure",
                        "lyapunov", "--time", "1e7", *DRIVE, "-o", "grid.png"], cwd=work,
                       capture_output=True, text=True, timeout=60)
except subprocess.TimeoutExpired:  # before: its probes alone ran 20+ minutes
    r = subprocess.CompletedProcess([], -9, "", "")
took = time.time() - t0
sptest.diag(f"grid: exit {r.returncode} in {took:.1f} s: {r.stderr.strip()[:300]}")
ok(r.returncode == 2 and "allowed" in r.stderr and took < 20 and
   not os.path.exists(os.path.join(work, "grid.png")),
   "300 points driven up to 1e6 Hz for 1e7 s: refused within 20 s, naming the limit")

# 3. data and still with the drive.
drive = ["--set", "pivot.frequency=1e6", *DRIVE]
err = stopped_by_term(["data", chaotic, *drive, "--set", "video.duration=100", "--every", "1",
                       "-o", "d.csv"], 1, "d.csv", "data driven at 1e6 Hz")
stopped_by_term(["still", chaotic, *drive, "--at", "100", "--size", "160x90", "-o", "s.png"], 1,
                "s.png", "a still driven at 1e6 Hz")

# 4. The rate against scipy's DOP853 at the same tolerance (the scene's).
m = re.search(r"\(([0-9.e+]+) steps per simulated second", err)
text = open(chaotic).read()


def key(name):
    return float(re.search(rf"^{name}\s*=\s*([-0-9.e+]+)", text, re.M).group(1))


tol = 1e-9  # integrator.tolerance's default: the sweep's line above says "tolerance 1e-09"
L0, k, mass = key("natural_length"), key("stiffness"), key("mass")
rhs = sptest.model(L0, k, mass, b=key("damping"), A=0.001, f=1e6)
u0 = sptest.start(key("length"), key("angle"))
span = 2e-4  # 200 drive periods
sol = solve_ivp(rhs, (0, span), u0, method="DOP853", rtol=tol, atol=tol)
scipy_rate = (sol.nfev / 12) / span  # DOP853: 12 evaluations a step
ours = float(m.group(1)) if m else 0
sptest.diag(f"steps per simulated second: springpend {ours:.3g}, scipy {scipy_rate:.3g}")
ok(m and scipy_rate / 4 < ours < scipy_rate * 4,
   "the estimate's steps per second are within 4x of scipy's DOP853 at the same tolerance")

# 5. A DOP853 Lyapunov map of minutes says so (20 rk4 steps a step).
p = started("sweep", chaotic, "--vary", "pendulum.stiffness=30:40:64", "--measure", "lyapunov",
            "--time", "1e6", "--set", "integrator.method=dop853", "-o", "map.png")
said = ""
t0 = time.time()
while time.time() - t0 < 20 and p.poll() is None:
    line = p.stderr.readline()
    if "steps in all" in line:
        said = line
        break
p.kill()
p.communicate()
sptest.diag(f"map: {said.strip()}")
ok("take a while" in said, "a DOP853 map of about 1e9 steps says it will take a while")
done()
