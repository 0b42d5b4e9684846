#!/usr/bin/env python3
"""springpend benchmark (issue 19): what text costs per frame on the shipped
scenes, for one or more builds side by side (say, the last commit before
HarfBuzz text, main, and a change). Each scene is rendered to raw frames
at SIZE, per build:
  - under valgrind's callgrind, collecting only inside sp_compose_frame
    (the CPU side of a frame), at SECONDS and at a quarter of that: the
    instructions of the whole compose stage, and of the text layout module
    alone (every call into a sp_font_* function from outside it, with all
    it calls: shaping, measuring, wrapping, laying out quads, rasterising
    new glyphs). Per frame is the difference between the two lengths
    divided by the frames between them: what each further frame costs,
    without the first frame's rasterising and shaping (reported apart, as
    "first": the short run's text instructions, most of them its first
    frame's). Instruction counts do not change with the machine's load;
    CPU time here swings by 15% and more;
  - with --verbose: the compose stage's ms per frame (load-dependent) and
    the text lines it prints: glyphs rasterised, by the first frame and in
    all, and lines shaped by HarfBuzz or joined from cached pieces.
A build that cannot read a scene (a key it predates) is marked so.
Not a unit test: nothing is asserted; it prints a table. Slow (callgrind
renders every frame with llvmpipe under valgrind): about half a minute a
scene and build.
usage: bench_text.py SCENES_DIR NAME=SPRINGPEND [NAME=SPRINGPEND ...]
                     [--seconds S] [--size WxH] [--jobs N]
  S: video length per scene (default 2); WxH: default 640x360; N: runs at
  once (default 2)."""
import glob
import os
import re
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

args = [a for a in sys.argv[1:]]
if "-h" in args or "--help" in args:
    sys.exit(print(__doc__))
if len(args) < 2:
    print(__doc__, file=sys.stderr)
    sys.exit(2)


def option(name, default):
    if name in args:
        i = args.index(name)
        value = args[i + 1]
        del args[i:i + 2]
        return value
    return default


seconds = float(option("--seconds", "2"))
size = option("--size", "640x360")
jobs = int(option("--jobs", "2"))
scenes_dir, builds = args[0], []
for a in args[1:]:
    name, _, path = a.partition("=")
    if not path:
        sys.exit(f"bench_text.py: {a}: expected NAME=SPRINGPEND")
    builds.append((name, os.path.abspath(path)))
scenes = sorted(glob.glob(os.path.join(scenes_dir, "*.ini")))


def render_args(exe, scene, length):
    return [exe, "render", scene, "--set", f"video.duration={length:g}", "--size", size,
            "--format", "raw", "-o", "-"]


def text_cost(annotated):
    """Instructions in calls into sp_font_* from outside the text module,
    from callgrind_annotate --tree=caller: each function's '*' line follows
    its callers' '<' lines, each with the cost of that caller's calls."""
    total, callers = 0, []
    for line in annotated.splitlines():
        m = re.match(r"\s*([\d,]+)\s+\([^)]*\)\s+([<*>])\s+\S*?:(\S+)", line)
        if not m:
            continue
        cost, kind, fn = int(m.group(1).replace(",", "")), m.group(2), m.group(3)
        if kind == "<":
            callers.append((cost, fn))
        elif kind == "*":
            if fn.startswith("sp_font_"):
                total += sum(c for c, caller in callers if not caller.startswith("sp_font_"))
            callers = []
    return total


def frames_of(stderr):
    return int(re.search(r"stage times for (\d+) frames", stderr).group(1))


def callgrind(exe, scene, length, tmp):
    """(frames, compose instructions, text instructions) of one run."""
    out = os.path.join(tmp, f"cg.{length:g}")
    v = subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                        "--toggle-collect=sp_compose_frame"] + render_args(exe, scene, length) +
                       ["--verbose"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                       check=True)
    ann = subprocess.run(["callgrind_annotate", "--tree=caller", "--threshold=100", out],
                         capture_output=True, text=True, check=True).stdout
    total = int(re.search(r"([\d,]+)\s+(?:\([^)]*\)\s+)?PROGRAM TOTALS", ann).group(1).replace(",", ""))
    return frames_of(v.stderr), total, text_cost(ann)


def measure(build, scene):
    name, exe = build
    v = subprocess.run(render_args(exe, scene, seconds) + ["--verbose"], stdout=subprocess.DEVNULL,
                       stderr=subprocess.PIPE, text=True)
    if v.returncode:
        return {"error": v.stderr.strip().splitlines()[-1] if v.stderr.strip() else f"exit {v.returncode}"}
    compose_ms = float(re.search(r"compose draw list\s+[\d.]+\s+([\d.]+)", v.stderr).group(1))
    text = [l.strip() for l in v.stderr.splitlines() if l.strip().startswith("text:")]
    with tempfile.TemporaryDirectory() as tmp:
        f1, c1, t1 = callgrind(exe, scene, seconds / 4, tmp)
        f2, c2, t2 = callgrind(exe, scene, seconds, tmp)
    return {"compose": (c2 - c1) / (f2 - f1), "text": (t2 - t1) / (f2 - f1), "first": t1,
            "compose_ms": compose_ms, "verbose": text}


runs = [(b, s) for s in scenes for b in builds]
with ThreadPoolExecutor(max_workers=jobs) as pool:
    results = dict(zip(runs, pool.map(lambda r: measure(*r), runs)))

print(f"instructions per frame (callgrind, {seconds / 4:g} s and {seconds:g} s at {size}): the compose "
      "stage and the text module in it; first: the text module's in the short run (first frame's "
      "shaping and rasterising); ms: compose ms/frame from --verbose (load-dependent)")
head = "scene".ljust(22) + "".join(f"{n + ': compose':>22}{'text':>9}{'first':>11}{'ms':>6}"
                                   for n, _ in builds)
print(head)
for s in scenes:
    row = os.path.basename(s).ljust(22)
    for b in builds:
        r = results[(b, s)]
        if "error" in r:
            row += f"{'(cannot read the scene)':>48}"
        else:
            row += (f"{r['compose']:>22,.0f}{r['text']:>9,.0f}{r['first']:>11,.0f}"
                    f"{r['compose_ms']:>6.2f}")
    print(row)
print()
for s in scenes:
    for b in builds:
        r = results[(b, s)]
        what = r["error"] if "error" in r else "; ".join(x[len("text: "):] for x in r["verbose"])
        print(f"{os.path.basename(s)} [{b[0]}]: {what}")
