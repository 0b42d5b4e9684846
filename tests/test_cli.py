#!/usr/bin/env python3
"""springpend tests: the command line, end to end, as a user meets it.
usage: test_cli.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import os
import shutil
import subprocess
import sys

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "cli"))
scenes = os.path.join(src, "..", "scenes")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
count = failed = 0


def ok(cond, what):
    global count, failed
    count += 1
    failed += not cond
    print(f"{'' if cond else 'not '}ok {count} - {what}", flush=True)
    return cond


def run(*args):
    return subprocess.run([exe, *args], capture_output=True, text=True, cwd=work)


def write(name, text):
    path = os.path.join(work, name)
    with open(path, "w") as f:
        f.write(text)
    return path


# Bad input: exit 2, FILE:LINE naming the key and the range, no output file.
bad = [
    ("[pendulum]\nmass = 0\n", "bad.ini:2: pendulum.mass = 0 is out of range", "0 < mass"),
    ("[pendulum]\nstiffness = nan\n", "bad.ini:2: pendulum.stiffness = nan is not finite", "stiffness"),
    ("[pendulum]\nmas = 1\n", "bad.ini:2: unknown key 'mas' in [pendulum]", "did you mean 'mass'"),
    ("[video]\nfps = abc\n", "bad.ini:2: video.fps = 'abc' is not a number", "0 < fps"),
    ("[integrator]\ndt = -1\n", "bad.ini:2: integrator.dt = -1 is out of range", "0 < dt"),
    ("[video]\nwidth = 99999\n", "bad.ini:2: video.width = 99999 is out of range", "16 to 7680"),
    ("[initial]\nlength = 0\n[video]\nfps = 0\n", "bad.ini:2: initial.length", "bad.ini:4: video.fps"),
    ("[integrator]\nmethod = rk5\n", "bad.ini:2: integrator.method = 'rk5' is not a method",
     "rk4, verlet, yoshida4, dopri5, dop853, rkn1210"),
    ("[integrator]\nmethod = rkn1210\n[pendulum]\ndamping = 0.1\n",
     "integrator.method = rkn1210 needs a force that depends on the position only", "dop853"),
    ("[integrator]\ntolerance = 1\n", "bad.ini:2: integrator.tolerance = 1 is out of range", "0.01"),
    ("[pivot]\namplitud = 1\n", "bad.ini:2: unknown key 'amplitud' in [pivot]", "did you mean 'amplitude'"),
    ("", None, None),
]
for text, want1, want2 in bad:
    scene = write("bad.ini", text)
    out = os.path.join(work, "bad.mp4")
    r = run("render", scene, "-o", out, "-q")
    if want1 is None:  # an empty scene is all defaults: valid; check with a short render
        continue
    ok(r.returncode == 2 and want1 in r.stderr and want2 in r.stderr and not os.path.exists(out),
       f"bad scene {text.strip()!r}: exit 2, says {want1!r} and {want2!r}, no file "
       f"(got {r.returncode}: {r.stderr.strip()[:200]!r})")

default = os.path.join(scenes, "default.ini")
r = run("render", default, "--set", "video.fps=0", "-o", "x.mp4")
ok(r.returncode == 2 and "--set video.fps=0: video.fps = 0 is out of range" in r.stderr
   and not os.path.exists(os.path.join(work, "x.mp4")), "a bad --set names the override")
r = run("render", default, "--size", "12x", "-o", "x.mp4")
ok(r.returncode == 2 and "--size" in r.stderr, "a malformed --size is refused")
r = run("render", os.path.join(work, "missing.ini"))
ok(r.returncode == 2 and "missing.ini: cannot open scene" in r.stderr, "a missing scene file")
r = run("render", default, "-o", os.path.join(work, "x.avi"))
ok(r.returncode == 2 and ".avi" in r.stderr and not os.path.exists(os.path.join(work, "x.avi")),
   "an unknown output extension is refused with exit 2")
r = run("render", default, "-o", default)
ok(r.returncode == 2 and "scene file itself" in r.stderr, "the output may not overwrite the scene")
r = run("frobnicate")
ok(r.returncode == 2 and "unknown command" in r.stderr, "an unknown command")
for cmd in ([], ["render"], ["still"], ["data"], ["info"]):
    r = run(*cmd, "--help")
    ok(r.returncode == 0 and "usage:" in r.stdout, f"springpend {' '.join(cmd)} --help")

# A blow-up is an error with exit 3, never a file.
r = run("render", default, "--set", "pendulum.stiffness=5e6", "--set", "pendulum.mass=0.5",
        "-o", "unstable.mp4", "-q")
ok(r.returncode == 3 and "unstable" in r.stderr and "integrator.dt <=" in r.stderr
   and not os.path.exists(os.path.join(work, "unstable.mp4")),
   f"an unstable scene exits 3 with a fix and writes nothing ({r.returncode})")

# A short MP4 that ffprobe reads back: codec, frames, duration.
r = run("render", default, "--set", "video.duration=2", "--size", "320x240", "--fps", "30",
        "-o", "short.mp4", "-q")
mp4 = os.path.join(work, "short.mp4")
ok(r.returncode == 0 and os.path.exists(mp4) and not os.path.exists(mp4 + ".part"),
   f"render writes an mp4 ({r.stderr.strip()[:200]})")
if shutil.which("ffprobe") and os.path.exists(mp4):
    p = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-show_streams", "-show_format",
                        "-of", "json", mp4], capture_output=True, text=True)
    info = json.loads(p.stdout)
    v = info["streams"][0]
    ok(v["codec_name"] == "h264" and v["pix_fmt"] == "yuv420p" and v["width"] == 320
       and int(v["nb_read_frames"]) == 60 and abs(float(info["format"]["duration"]) - 2.0) < 0.05,
       f"ffprobe: {v['codec_name']} {v['pix_fmt']} {v['width']}x{v['height']}, "
       f"{v['nb_read_frames']} frames, {info['format']['duration']} s")

# A PNG sequence: one file per frame, folders created.
r = run("render", default, "--set", "video.duration=0.5", "--size", "160x120", "--fps", "10",
        "-o", "seq/deep/%03d.png", "-q")
files = sorted(os.listdir(os.path.join(work, "seq/deep"))) if r.returncode == 0 else []
ok(files == [f"{i:03d}.png" for i in range(5)], f"PNG sequence of 5 frames: {files}")

# Defaults: out/<scene>.png for a still.
r = run("still", default, "--at", "1.5", "--size", "320x180")
ok(r.returncode == 0 and os.path.exists(os.path.join(work, "out", "default.png")),
   "still without -o writes out/default.png")

# Stills for slides: --scale supersamples to the same size; a transparent
# background writes RGBA with see-through corners and an opaque bob.
def png_header(path):
    with open(path, "rb") as f:
        head = f.read(33)
    return int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big"), head[25]


r = run("still", default, "--at", "2", "--size", "320x180", "--scale", "3", "-o", "ss.png", "-q")
ok(r.returncode == 0 and png_header(os.path.join(work, "ss.png"))[:2] == (320, 180),
   f"still --scale 3 writes the asked size ({r.stderr.strip()[:200]})")
r = run("still", default, "--scale", "9", "-o", "ss9.png")
ok(r.returncode == 2 and "--scale" in r.stderr and not os.path.exists(os.path.join(work, "ss9.png")),
   "--scale beyond 4 is refused")
r = run("render", default, "--scale", "2", "-o", "x.mp4")
ok(r.returncode == 2 and "--scale" in r.stderr, "--scale is for stills only")
r = run("still", default, "--at", "2", "--size", "320x180", "--set", "view.background=transparent",
        "-o", "alpha.png", "-q")
ok(r.returncode == 0 and png_header(os.path.join(work, "alpha.png"))[2] == 6,
   "a transparent background writes an RGBA PNG (its alpha: see the golden test)")
r = run("still", default, "--set", "view.panels=r,bogus", "-o", "bogus.png")
ok(r.returncode == 2 and "'bogus' is not a panel" in r.stderr
   and not os.path.exists(os.path.join(work, "bogus.png")), "an unknown panel is refused")

# Every preset renders a still with its panels.
for name in sorted(os.listdir(scenes)):
    if name.endswith(".ini"):
        out = os.path.join(work, name[:-4] + ".png")
        r = run("still", os.path.join(scenes, name), "--at", "3", "--size", "480x270", "-o", out, "-q")
        # A blank 480x270 frame compresses to well under 1 kB.
        ok(r.returncode == 0 and os.path.getsize(out) > 2000, f"preset {name} renders a still")

# data: CSV rows at the requested times, physics that holds, every method.
import csv
import io
import math

cols = "t,x,y,vx,vy,r,theta,r_dot,theta_dot,kinetic,spring,gravity,energy".split(",")
for method in ("rk4", "verlet", "yoshida4", "dopri5", "dop853", "rkn1210"):
    r = run("data", default, "--every", "0.25", "--set", f"integrator.method={method}", "-o", "-")
    rows = list(csv.DictReader(io.StringIO(r.stdout))) if r.returncode == 0 else []
    ts = [float(x["t"]) for x in rows]
    e = [float(x["energy"]) for x in rows]
    polar_ok = all(abs(float(x["r"]) * math.sin(float(x["theta"])) - float(x["x"])) < 1e-9
                   and abs(float(x["bounce"]) + float(x["swing"]) - float(x["energy"])
                           - (float(rows[0]["bounce"]) + float(rows[0]["swing"])
                              - float(rows[0]["energy"]))) < 1e-9 for x in rows)
    ok(r.returncode == 0 and len(rows) == 41 and ts[0] == 0 and ts[-1] == 10
       and all(c in rows[0] for c in cols) and polar_ok
       and max(e) - min(e) < {"verlet": 1e-4, "dopri5": 1e-6, "dop853": 1e-6, "rkn1210": 1e-6}.get(method, 1e-7),
       f"data --every 0.25 with {method}: 41 rows t = 0..10, r/theta match x, "
       f"energy spread {max(e) - min(e) if e else -1:.1e} J ({r.stderr.strip()[:200]})")
r = run("data", default, "--set", "video.duration=1", "-q")
path = os.path.join(work, "out", "default.csv")
n = sum(1 for _ in open(path)) if os.path.exists(path) else 0
ok(r.returncode == 0 and n == 61, f"data without -o writes out/default.csv, 60 frame rows + header ({n})")
r = run("data", default, "--set", "pendulum.stiffness=5e6", "-o", "blow.csv")
ok(r.returncode == 3 and "stability limit" in r.stderr and not os.path.exists(os.path.join(work, "blow.csv"))
   and not os.path.exists(os.path.join(work, "blow.csv.part")),
   "an unstable data run exits 3, names the stability limit, and leaves no file")
r = run("data", default, "--every", "0", "-o", "-")
ok(r.returncode == 2 and "--every 0" in r.stderr, "--every 0 is refused with exit 2")
r = run("data", default, "--set", "pendulum.stiffness=5e6", "--set", "pendulum.mass=0.5",
        "--set", "integrator.method=dop853", "--set", "video.duration=0.5", "-o", "-")
ok(r.returncode == 0 and len(r.stdout.splitlines()) == 31,
   "the same stiff scene runs clean with dop853")

# info: the resonance check, with l = L0 + m g / k, and the stability warning.
r = run("info", default)
ok(r.returncode == 0 and "l = L0 + m g / k = 2.9525 m" in r.stdout
   and "sqrt(g/l) = 1.8228" in r.stdout and "not near 2:1" in r.stdout and "warning" not in r.stdout,
   "info on the default scene: l = 2.9525 m, omega_p = sqrt(g/l), not near 2:1")
r = run("info", default, "--set", "pendulum.stiffness=29.43", "--set", "initial.length=0.8")
ok(r.returncode == 0 and "near 2:1 (+0.00%)" in r.stdout and "growth rate" in r.stdout,
   f"info at k L0 = 3 m g: near 2:1 with the exchange estimate")
r = run("info", default, "--set", "pendulum.stiffness=5e6")
ok(r.returncode == 0 and "warning: dt = 0.001 s is above rk4's stability limit" in r.stdout
   and "integrator.dt <= 0.0004" in r.stdout, "info warns about an unstable dt with a safe one")

print(f"1..{count}")
sys.exit(1 if failed else 0)
