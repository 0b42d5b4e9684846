#!/usr/bin/env python3
"""springpend benchmark (issue 22): what the teaching aids cost. The default
scene as shipped rendered to a 1080p60 MP4, against the same with arrows and
energy bars (view.vectors = velocity, forces; the energy_bars panel added to
the shipped r, theta, energy, extension), and against the default scene
beside scenes/stiff.ini (side by side, one frame). The three runs alternate
(A B C, A B C, ...), REPEAT rounds, so that the load of a shared machine
falls on all three alike; each run's CPU time is user + sys of the process
and its threads (wait4's rusage), which the load inflates much less than
the wall time. Prints every run, then per round the ratios B/A and C/A, and
their median with the lowest and highest round.
With --callgrind instead: each run once under valgrind's callgrind at 6 and
at 30 frames (0.1 and 0.5 s of video), and the instructions each executes
(all threads; valgrind runs them one at a time): the totals, and per frame
the difference between the two lengths (what a longer video adds), which
no other process on the machine changes. Slow: about 2 to 5 minutes a run.
usage: bench_teach.py SPRINGPEND SCENES_DIR [REPEAT] [SECONDS]
       bench_teach.py SPRINGPEND SCENES_DIR --callgrind
  REPEAT: rounds (default 8); SECONDS: video length (default 5, 300 frames)."""
import os
import statistics
import subprocess
import sys
import tempfile
import time

if "-h" in sys.argv or "--help" in sys.argv:
    sys.exit(print(__doc__))
if len(sys.argv) < 3:
    print(__doc__, file=sys.stderr)
    sys.exit(2)
exe, scenes = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
CALLGRIND = "--callgrind" in sys.argv
args_ = [a for a in sys.argv[3:] if not a.startswith("--")]
REPEAT = int(args_[0]) if args_ else 8
SECONDS = float(args_[1]) if len(args_) > 1 else 5
default, stiff = os.path.join(scenes, "default.ini"), os.path.join(scenes, "stiff.ini")
common = ["--size", "1920x1080", "--set", f"video.duration={SECONDS:g}", "-q"]
RUNS = {
    "A base": [default],
    "B arrows+bars": [default, "--set", "view.vectors=velocity,forces",
                      "--set", "view.panels=r,theta,energy,extension,energy_bars"],
    "C side by side": [default, stiff],
}


def instructions(args, seconds, d):
    """Instructions (callgrind's Ir, every thread) of one render."""
    log = os.path.join(d, "cg.log")
    cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={os.path.join(d, 'cg.out')}",
           f"--log-file={log}", exe, "render", *args, "--size", "1920x1080", "--set",
           f"video.duration={seconds:g}", "-q", "-o", os.path.join(d, "cg.mp4")]
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    with open(log) as fp:
        return int(next(line for line in fp if "Collected" in line).split(":")[-1].replace(",", ""))


if CALLGRIND:
    with tempfile.TemporaryDirectory() as d:
        ir = {k: {s_: instructions(a, s_, d) for s_ in (0.1, 0.5)} for k, a in RUNS.items()}
    for k, v in ir.items():
        print(f"{k:15s} instructions: 6 frames {v[0.1]:,}, 30 frames {v[0.5]:,}; "
              f"per frame (30 - 6) {(v[0.5] - v[0.1]) / 24:,.0f}")
    base = ir["A base"]
    for k in ("B arrows+bars", "C side by side"):
        v = ir[k]
        print(f"{k} / base: 30 frames {v[0.5] / base[0.5]:.4f}, per frame "
              f"{(v[0.5] - v[0.1]) / (base[0.5] - base[0.1]):.4f}")
    sys.exit(0)


def run(args, out):
    t0 = time.monotonic()
    p = subprocess.Popen([exe, "render", *args, *common, "-o", out], stdout=subprocess.DEVNULL,
                         stderr=subprocess.PIPE)
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.monotonic() - t0
    err = p.stderr.read().decode()
    p.stderr.close()
    if status:
        sys.exit(f"springpend failed ({status}): {err}")
    return ru.ru_utime + ru.ru_stime, wall


with tempfile.TemporaryDirectory(dir="/dev/shm" if os.path.isdir("/dev/shm") else None) as d:
    out = os.path.join(d, "bench.mp4")
    cpu = {k: [] for k in RUNS}
    wall = {k: [] for k in RUNS}
    load0 = os.getloadavg()[0]
    for r in range(REPEAT):
        for k, args in RUNS.items():
            c, w = run(args, out)
            cpu[k].append(c)
            wall[k].append(w)
            print(f"round {r + 1} {k:15s} CPU {c:7.2f} s  wall {w:6.2f} s", flush=True)
    load1 = os.getloadavg()[0]
print(f"load average (1 min) at the start {load0:.2f}, at the end {load1:.2f}; "
      f"{os.cpu_count()} CPUs; {REPEAT} rounds of {SECONDS:g} s of 1080p60 video")
for k in ("B arrows+bars", "C side by side"):
    ratio = [b / a for a, b in zip(cpu["A base"], cpu[k])]
    wr = [b / a for a, b in zip(wall["A base"], wall[k])]
    print(f"{k} / base, CPU: median {statistics.median(ratio):.3f} "
          f"(rounds {min(ratio):.3f} .. {max(ratio):.3f}); wall: median {statistics.median(wr):.3f} "
          f"(rounds {min(wr):.3f} .. {max(wr):.3f})")
for k in RUNS:
    print(f"{k:15s} CPU median {statistics.median(cpu[k]):.2f} s, wall median {statistics.median(wall[k]):.2f} s")
