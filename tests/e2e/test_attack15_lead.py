#!/usr/bin/env python3
"""springpend tests (issue 28): the fifteenth attacker's pass
(doc/notes/2026-11-27/attack15.md), the lead's findings:
- #2: a [timeline] speed so slow that the video passed 2^31 frames was
  taken, and info printed a negative (or zero) frame count: the scene is
  refused at that speed's line, as video.speed is past 1e9 frame times;
- #6: a --candidates run stopped by a signal left its diffs and no
  candidate, printed an approve hint for nothing, and the next run then
  refused the folder for images "--approve would install" (diffs, which
  --approve leaves): the interrupted run leaves the folder as it found it
  and says so, and a folder of diffs is named as such;
- #9: a still past the video's end drew no trail: the frames go on at the
  last speed, so the still equals the one of a scene whose video reaches it.
usage: test_attack15_lead.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import os
import re
import shutil
import signal
import subprocess
import time

import sptest
from sptest import done, err, ok, skip

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack15-lead")
default = os.path.join(scenes, "default.ini")
stiff = os.path.join(scenes, "stiff.ini")
lesson = os.path.join(scenes, "lesson-exchange.ini")


def pixels(name):
    """The picture's RGB bytes, decoded by ffmpeg (not by springpend)."""
    return subprocess.run(["ffmpeg", "-v", "error", "-i", path(name), "-f", "rawvideo",
                           "-pix_fmt", "rgb24", "-"], capture_output=True, check=True).stdout


# ---- 2: a timeline speed past 1e9 frame times is refused at its line -----------------------
head = re.split(r"^\[timeline\]", open(lesson).read(), flags=re.M)[0]
duration = float(re.search(r"^duration\s*=\s*([0-9.eE+-]+)", head, re.M).group(1))
fps = float(re.search(r"^fps\s*=\s*([0-9.eE+-]+)", head, re.M).group(1))
line = head.count("\n") + 2  # the cue's line: after the section's
for speed in ("1e-7", "2e-8", "1e-300", "4.9e-324"):
    name = path(f"slow{speed}.ini")
    with open(name, "w") as f:
        f.write(head + "[timeline]\n1 = speed " + speed + "\n")
    r = run("info", name, "--json")
    said = err(r)
    ok(r.returncode == 2 and f"slow{speed}.ini:{line}:" in said and "at most 1000000000" in said
       and not r.stdout.strip(),
       f"2: [timeline] speed {speed}: refused at line {line}, exit 2, nothing printed "
       f"(exit {r.returncode}: {said[:200]})")
# a slow speed within the limit: the frames info counts are the video's length times fps,
# and the length is at least the part before the cue plus the rest at the slow speed
name = path("slow-ok.ini")
with open(name, "w") as f:
    f.write(head + "[timeline]\n1 = speed 0.001\n")
r = run("info", name, "--json")
j = json.loads(r.stdout) if r.returncode == 0 else {}
length, frames = j.get("video_length", 0), j.get("video_frames", -1)
ok(r.returncode == 0 and frames == round(length * fps) and length >= 1 + (duration - 1) / 0.001 * 0.99,
   f"2: speed 0.001 ({duration:g} s at {fps:g} fps): {frames} frames = round({length} s x {fps:g}), "
   f"the length at least {1 + (duration - 1) / 0.001 * 0.99:.0f} s (exit {r.returncode})")

# ---- 6: an interrupted --candidates run leaves the folder as it found it ---------------------
d = path("cand")
shutil.rmtree(d, ignore_errors=True)
for sub in ("e", "a"):
    os.makedirs(os.path.join(d, sub))
first = [os.path.join(d, "e", "x0.png"), os.path.join(d, "a", "x0.png")]
run("still", default, "--at", "0.5", "--size", "640x360", "-o", first[0], "-q")
run("still", stiff, "--at", "0.5", "--size", "640x360", "-o", first[1], "-q")
for i in range(1, 40):
    for f, sub in zip(first, ("e", "a")):
        shutil.copy(f, os.path.join(d, sub, f"x{i}.png"))
cand = os.path.join(d, "c")
p = subprocess.Popen([exe, "compare", "e", "a", "--candidates", "c", "--summary", "s.md", "--jobs", "1"],
                     cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
end = time.time() + 60
while time.time() < end and p.poll() is None and not (
        os.path.isdir(cand) and any(n.endswith(".diff.png") for n in os.listdir(cand))):
    time.sleep(0.005)
p.send_signal(signal.SIGTERM)
out, e = p.communicate(timeout=60)
left = sorted(os.listdir(cand)) if os.path.isdir(cand) else []
summary = open(os.path.join(d, "s.md")).read() if os.path.exists(os.path.join(d, "s.md")) else ""
ok(p.returncode == 143 and not left and "--approve" not in out
   and "interrupted: no candidate kept in c" in out and ".diff.png" not in summary,
   f"6: --candidates stopped by SIGTERM: exit {p.returncode}, the folder left as found "
   f"({left[:3]}), no approve hint, said so ({out.strip().splitlines()[-1:]}), the summary "
   f"names no removed diff")
r = run("compare", os.path.join(d, "e"), os.path.join(d, "a"), "--candidates", cand, "-q")
made = sorted(n for n in os.listdir(cand) if not n.endswith(".diff.png")) if os.path.isdir(cand) else []
ok(r.returncode == 1 and len(made) == 40,
   f"6: the next --candidates run into the same folder runs: exit {r.returncode} (1: they "
   f"differ), {len(made)} candidates of 40 ({err(r)[:160]})")
shutil.rmtree(cand)
os.makedirs(cand)
for i in range(2):
    shutil.copy(first[1], os.path.join(cand, f"x{i}.diff.png"))
r = run("compare", os.path.join(d, "e"), os.path.join(d, "a"), "--candidates", cand, "-q")
ok(r.returncode == 2 and "2 diff images of an earlier run" in err(r) and "would install" not in err(r),
   f"6: a candidates folder holding diffs only is refused as such, not as images --approve "
   f"would install (exit {r.returncode}: {err(r)[:200]})")

# ---- 9: a still past the video's end draws the trail a longer video would --------------------
if shutil.which("ffmpeg"):
    common = ["--size", "640x360", "--set", "view.panels=none", "-q"]
    run("still", default, "--at", "100", *common, "-o", "past.png")
    run("still", default, "--at", "100", "--set", "video.duration=200", *common, "-o", "within.png")
    run("still", default, "--at", "100", "--set", "view.trail=0", *common, "-o", "bare.png")
    past, within, bare = (pixels(n) for n in ("past.png", "within.png", "bare.png"))
    worst = max(abs(a - b) for a, b in zip(past, within)) if len(past) == len(within) else 255
    trail = sum(a != b for a, b in zip(past, bare))
    ok(worst <= 3 and trail > 1000,
       f"9: default.ini (10 s) at --at 100: the trail drawn ({trail} bytes unlike the same "
       f"frame without a trail), as with video.duration = 200 (largest difference {worst})")
else:
    skip("9: a still past the video's end", "ffmpeg missing")

done()
