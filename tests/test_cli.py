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
for cmd in ([], ["render"], ["still"]):
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
        ok(r.returncode == 0 and os.path.getsize(out) > 5000, f"preset {name} renders a still")

print(f"1..{count}")
sys.exit(1 if failed else 0)
