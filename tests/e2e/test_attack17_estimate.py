#!/usr/bin/env python3
"""springpend tests (issue 28): the seventeenth attacker's pass
(doc/notes/2026-11-27/attack17.md), findings 1, 5 and 11, work estimates:
- #1: a sweep with an adaptive integrator estimated every point from the
  base scene: a grid over pendulum.stiffness near 1e10 (a step 1e4 times
  shorter than the base's k = 39) ran silently for weeks, past the 1e12
  refusal. The estimate now probes the grid's own points: such a grid is
  refused (lyapunov, spectrum, orbit), its per-point estimate is the one
  the same point gets as the base scene (--set), a shard is estimated from
  its own points, and a grid over k = 1e8 and 1e10 names the costlier end,
  in the ratio the physics gives (a stiff spring's steps go as its
  frequency, sqrt(k/m): 2 / (1 + 1/10) of the mean);
- #5: a Poincare mosaic out of the reach of the scene's own energy was
  refused as "--energy 3.13958: ... (omit --energy for the scene's own)"
  with no --energy given; it is now named by where the energy came from,
  with the least energy the grid's starts need (computed here);
- #11: the trail samples of a render's estimate were counted over
  duration x fps, not the frames a [timeline] makes.
usage: test_attack17_estimate.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import math
import os
import re
import signal
import subprocess

import sptest
from sptest import done, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack17-estimate")
chaotic = os.path.join(scenes, "chaotic.ini")
lesson = os.path.join(scenes, "lesson-exchange.ini")
DOP = ["--set", "integrator.method=dop853"]


def sweep(args, wait=15):
    """A sweep's exit code and stderr; one that does not answer within
    `wait` s (it runs: no refusal) is stopped, code None."""
    p = subprocess.Popen([exe, "sweep", chaotic, *args], cwd=work, stderr=subprocess.PIPE,
                         stdout=subprocess.DEVNULL, text=True)
    try:
        e = p.communicate(timeout=wait)[1]
        return p.returncode, e
    except subprocess.TimeoutExpired:
        p.send_signal(signal.SIGTERM)
        return None, p.communicate(timeout=60)[1]


def per_point(text):
    m = re.search(r"about ([0-9.e+]+) steps a point", text)
    return float(m.group(1)) if m else float("nan")


def clean():
    for f in os.listdir(work):
        os.remove(os.path.join(work, f))


# ---- 1: the grid's own points set the estimate ---------------------------------------------
STIFF = ["--vary", "pendulum.stiffness=1e10:1.0001e10:100"]
for measure, time in (("lyapunov", "1e6"), ("spectrum", "1e5"), ("orbit", "1e5")):
    code, e = sweep([*STIFF, "--measure", measure, "--time", time, *DOP, "-o", "a.png"])
    ok(code == 2 and "at most 5e+10 are allowed" in e and "100 points" in e and not os.listdir(work),
       f"#1 a {measure} grid over k near 1e10 (--time {time}) is refused with the numbers: "
       f"exit {code}, {e.strip()[:300]}")
    clean()
# the same point as the base scene (--set) is estimated alike
_, grid = sweep([*STIFF, "--measure", "lyapunov", "--time", "1e6", *DOP, "-o", "a.png"])
_, alone = sweep(["--set", "pendulum.stiffness=1e10", "--vary", "initial.angle=85:86:100",
                  "--measure", "lyapunov", "--time", "1e6", *DOP, "-o", "a.png"])
g, a = per_point(grid), per_point(alone)
ok(a > 1e11 and abs(g / a - 1) < 0.05,
   f"#1 the grid's points cost what the same point costs alone: {g:.3g} vs {a:.3g} steps a point")
clean()
# 1e8 and 1e10: steps go as sqrt(k/m) for a stiff spring, so the mean of the two is
# (1 + 1/10) / 2 of the costlier's; and the costlier is named
_, e = sweep(["--vary", "pendulum.stiffness=1e8:1e10:2", "--measure", "lyapunov", "--time", "1e7",
              *DOP, "-o", "a.png"])
m = re.search(r"the costliest probed about ([0-9.e+]+) \(pendulum\.stiffness = 1e\+10\)", e)
most = float(m.group(1)) if m else float("nan")
want = 2 / (1 + math.sqrt(1e8 / 1e10))
ok(abs(most / per_point(e) / want - 1) < 0.08 and "at most 5e+10 are allowed" in e,
   f"#1 k = 1e8 and 1e10: the costliest (k = 1e10) {most:.3g} steps, {most / per_point(e):.3f} x the "
   f"mean (sqrt(k) says {want:.3f}), refused: {e.strip()[:300]}")
clean()
# a shard is estimated from its own points: the k = 39 end runs, the k = 1e10 end is refused
SPAN = ["--vary", "pendulum.stiffness=39.24:1e10:100", "--measure", "lyapunov", "--time", "1e7", *DOP]
code_hi, e_hi = sweep([*SPAN, "--shard", "100/100", "--csv", "s.csv"])
ok(code_hi == 2 and "1 points" in e_hi and "at most 5e+10" in e_hi and not os.listdir(work),
   f"#1 the shard holding k = 1e10 is refused: exit {code_hi}, {e_hi.strip()[:300]}")
clean()
code_lo, e_lo = sweep([*SPAN, "--shard", "1/100", "--csv", "s.csv"], wait=3)
ok(code_lo in (None, 0) and "at most 5e+10" not in e_lo,
   f"#1 the shard holding k = 39 runs (stopped here): exit {code_lo}, {e_lo.strip()[:200]}")
clean()

# ---- 5: the refusal says where the energy came from ---------------------------------------
# chaotic.ini: k = 39.24, L0 = 0.75, m = 1, g = 9.81, r = 1.2, theta = 85.94 degrees, at rest
k, L0, mass, g, r = 39.24, 0.75, 1.0, 9.81, 1.2
E0 = 0.5 * k * (r - L0) ** 2 - mass * g * r * math.cos(math.radians(85.94))
least = min(0.5 * k * (r - L0) ** 2 - mass * g * r * math.cos(math.radians(a))
            for a in (100 + 10 * i for i in range(8)))
ANGLES = ["--vary", "initial.angle=100:170:8", "--measure", "poincare", "--time", "400"]
code, e = sweep([*ANGLES, "-o", "p.png"])
m = re.search(r"need at least ([0-9.]+) J", e)
ok(code == 2 and "--energy 3" not in e and "omit --energy" not in e and
   f"the scene's own energy, {E0:.6g} J" in e and m and abs(float(m.group(1)) / least - 1) < 1e-5
   and not os.listdir(work),
   f"#5 no --energy: the scene's own {E0:.6g} J named, the grid's least {least:.6g} J: exit {code}, "
   f"{e.strip()[:300]}")
clean()
code, e = sweep([*ANGLES, "--energy", "1", "-o", "p.png"])
ok(code == 2 and e.startswith("springpend: --energy 1: no point") and f"E >= {least:.6g}" in e,
   f"#5 --energy 1: named as given, E >= {least:.6g} allowed: exit {code}, {e.strip()[:300]}")
clean()

# ---- 11: trail samples over the frames a [timeline] makes ---------------------------------
# lesson-exchange: 40 s at 30 fps; an ensemble of 5000 with trails, the pendulum's trail
# (64 samples a frame); a pause of 100 s makes (40 + 100) * 30 frames
with open(lesson) as f:
    text = re.split(r"^\[timeline\]", f.read(), flags=re.M)[0]
text = "\n".join(line for line in text.splitlines() if not line.startswith("trail"))
text += "\n[ensemble]\ncount = 5000\ntrails = true\nspread = 1\n"
for name, extra, frames in (("tp.ini", "[timeline]\n10 = pause 100\n", (40 + 100) * 30),
                            ("t0.ini", "", 40 * 30)):
    scene = path(name)
    with open(scene, "w") as f:
        f.write(text + extra)
    p = subprocess.Popen([exe, "render", scene, "--size", "320x180", "--frames", "0:2", "-o",
                          path("t.mp4")], cwd=work, stderr=subprocess.PIPE, text=True)
    first = p.stderr.readline()
    p.send_signal(signal.SIGTERM)
    p.communicate(timeout=60)
    m = re.search(r"trail samples ([0-9.e+]+)", first)
    got, want = float(m.group(1)) if m else float("nan"), (5000 + 64) * frames
    ok(abs(got / want - 1) < 0.03,
       f"#11 {name}: trail samples {got:.3g}, (5000 + 64) x {frames} frames = {want:.3g}")
done()
