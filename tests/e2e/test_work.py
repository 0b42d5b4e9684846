#!/usr/bin/env python3
"""springpend tests: work that may run for hours is estimated first, the same
way for every command: refused beyond a limit with the numbers and what to
change, said beyond a smaller one. Ensembles count their members (each
integrated twice), trails and the camera's pre-pass; sweeps count their
points (a shard's only).
usage: test_work.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil
import signal
import subprocess
import sys
import time

from sptest import done, ok

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "work"))
scenes = os.path.join(src, "..", "scenes")
default, chaotic = os.path.join(scenes, "default.ini"), os.path.join(scenes, "chaotic.ini")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def refused(what, args, words, within=20):
    """A run refused at once: exit 2, the words on stderr, no file made. A run
    that starts instead (it would take hours) is stopped at `within` s."""
    t0 = time.monotonic()
    try:
        r = subprocess.run([exe, *args], capture_output=True, text=True, cwd=work, timeout=within)
        code, err = r.returncode, r.stderr
    except subprocess.TimeoutExpired:
        code, err = None, f"still running after {within} s: no estimate"
    made = [f for f in os.listdir(work)]
    ok(code == 2 and all(w in err for w in words) and not made and time.monotonic() - t0 < within,
       f"{what}: exit {code}, {err.strip()[:300]} {made or ''}")


# An ensemble of 10000 members over 10000 s at dt = 1 ms: 2e11 member-steps
# (each member runs twice: the camera's pre-pass and the run). It started
# with no word.
refused("an ensemble of 1e4 members over 1e4 s is refused, members counted",
        ["still", default, "--set", "ensemble.count=10000", "--set", "video.duration=10000",
         "--fps", "1", "-o", "ens.png"], ["10000 ensemble members", "2e+11", "ensemble.count"])
# One pendulum whose run (6.25e9 steps) is under the limit but whose camera
# pre-pass doubles it past 1e10: the pre-pass was not counted.
refused("the camera's pre-pass is counted (6.25e9 steps twice)",
        ["still", default, "--set", "video.duration=1e6", "--set", "video.fps=0.1",
         "--set", "integrator.dt=1.6e-4", "-o", "cam.png"], ["camera's pre-pass 6.2e+09", "1e+10"])
# Trails: the pendulum's trail is sampled up to 64 times a frame
# (1e6 frames of a 1e-3 s step: 6.4e7 samples) -- counted, below the limit.
try:
    r = subprocess.run([exe, "render", default, "--set", "video.duration=2000", "--set", "video.fps=500",
                        "--set", "integrator.dt=2e-7", "--set", "view.trail=all", "--frames", "0:1",
                        "-o", "trail.mp4"], capture_output=True, text=True, cwd=work, timeout=20)
    code, err = r.returncode, r.stderr
except subprocess.TimeoutExpired:
    code, err = None, "still running after 20 s: no estimate"
ok(code == 2 and "trail samples 6.4e+07" in err and "1e+10" in err,
   f"a render's trail samples are in the estimate it refuses: {code} {err.strip()[:300]}")
for f in os.listdir(work):
    os.remove(os.path.join(work, f))

def wait_line(p, within=20):
    """Whether p wrote to stderr within `within` s (a run without a word
    would block readline for as long as it runs)."""
    import select
    return bool(select.select([p.stderr], [], [], within)[0])


# Sweeps had no estimate at all: --vary ...:100000 --time 1e6 ran for weeks.
refused("a sweep of 1e5 points over 1e6 s is refused with the numbers",
        ["sweep", chaotic, "--vary", "initial.angle=1:179:100000", "--measure", "lyapunov",
         "--time", "1e6", "-o", "big.png"], ["100000 points", "2e+14 steps", "at most 1e+12",
                                              "--shard"])
# A spectrum point steps four copies of its trajectory, each with a tangent:
# 1e4 points over 3e4 s at 0.5 ms are 6e11 trajectory-steps for lyapunov
# (allowed) and 2.4e12 for spectrum, counted as 6e11 before.
refused("a spectrum sweep counts its four copies",
        ["sweep", chaotic, "--vary", "initial.angle=1:179:100", "--vary", "initial.length=1:1.4:100",
         "--measure", "spectrum", "--time", "3e4", "-o", "big.png"],
        ["10000 points", "four copies with tangents", "2.4e+12 steps", "at most 1e+12"])
refused("an orbit sweep with dop853 is estimated too",
        ["sweep", chaotic, "--vary", "initial.angle=1:179:20000", "--measure", "orbit",
         "--time", "1e6", "--set", "integrator.method=dop853", "-o", "big.png"], ["20000 points"])
# A long one that is allowed says so first (then SIGTERM: 143, nothing left). 5e5 s: at 1e6 s
# the bound on its rows from each start's energy passes 1e8 (attack15 #3), refused.
p = subprocess.Popen([exe, "sweep", chaotic, "--vary", "initial.angle=1:179:100", "--measure", "orbit",
                      "--time", "5e5", "-o", "long.png", "--csv", "long.csv"],
                     cwd=work, stderr=subprocess.PIPE, text=True)
first = p.stderr.readline() if wait_line(p) else ""
p.send_signal(signal.SIGTERM)
rest = p.communicate(timeout=60)[1]
ok("100 points" in first and "1e+11 steps in all" in first and "will take a while" in first and
   p.returncode == 128 + signal.SIGTERM and not os.listdir(work),
   f"a sweep past 1.5e10 steps says so before it starts: {first.strip()} (then exit {p.returncode}, "
   f"{os.listdir(work) or 'nothing left'})")
# A shard is estimated for its own points: 1/1000 of the refused grid runs.
p = subprocess.Popen([exe, "sweep", chaotic, "--vary", "initial.angle=1:179:100000", "--measure",
                      "lyapunov", "--time", "1e6", "--shard", "1/1000", "--csv", "s.csv"],
                     cwd=work, stderr=subprocess.PIPE, text=True)
first = p.stderr.readline() if wait_line(p) else ""
p.send_signal(signal.SIGTERM)
p.communicate(timeout=60)
ok("sweeping 100 points" in first and "will take a while" in first,
   f"a shard is estimated for its own points: {first.strip()}")
r = subprocess.run([exe, "sweep", chaotic, "--vary", "initial.angle=1:179:8", "--measure", "lyapunov",
                    "--time", "2", "-o", "small.png"], capture_output=True, text=True, cwd=work)
ok(r.returncode == 0 and "steps in all" not in r.stderr, "a small sweep says nothing of its work")
done()
