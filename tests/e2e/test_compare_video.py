#!/usr/bin/env python3
"""springpend tests: the videos' default rule (issue 24). The same frames
re-encoded at nearby quality (CRF 22 and 24 against 23, preset medium, WebM
against MP4) pass; a changed parameter (stiffness, damping) fails, and the
failure names the scene key that changed, from the videos' tags. A rule set
for a video (command line or compare.ini) replaces the default.
usage: test_compare_video.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR (TAP)"""
import json
import os
import shutil
import subprocess
import sys

from sptest import done, ok

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "compare_video"))
default = os.path.join(src, "..", "scenes", "default.ini")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def run(*args):
    return subprocess.run([exe, *args], capture_output=True, text=True, cwd=work, timeout=120)


common = ["--size", "320x180", "--fps", "20", "--set", "video.duration=1.5"]
renders = {"base.mp4": [], "crf22.mp4": ["--set", "video.crf=22"],
           "crf24.mp4": ["--set", "video.crf=24"], "medium.mp4": ["--set", "video.preset=medium"],
           "base.webm": [], "stiff.mp4": ["--set", "pendulum.stiffness=2.2"],
           "damped.mp4": ["--set", "pendulum.damping=0.05"]}
for name, extra in renders.items():
    run("render", default, *common, *extra, "-o", name, "-q")


def judge(name):
    r = run("compare", "base.mp4", name, "--json")
    return r.returncode, json.loads(r.stdout)["results"][0]


for name in ("crf22.mp4", "crf24.mp4", "medium.mp4", "base.webm"):
    rc, rec = judge(name)
    ref = run("compare", "base.mp4", name, "--max-diff", "3")  # the still images' rule
    ok(rc == 0 and rec["tolerance"]["metric"] == "blocks" and ref.returncode == 1,
       f"{name}: the same frames re-encoded pass the videos' default rule (largest block "
       f"difference {rec['measured'].get('max_channel_diff')}), the still images' rule fails them")
for name, key in (("stiff.mp4", "pendulum.stiffness"), ("damped.mp4", "pendulum.damping")):
    rc, rec = judge(name)
    keys = [c["key"] for c in rec["scene_changes"]]
    ok(rc == 1 and rec["video"]["failed_frames"] > 0 and keys == [key],
       f"{name}: a changed parameter fails ({rec['video']['failed_frames']} of "
       f"{rec['video']['frames']} frames, worst {rec['measured'].get('differing_pixels')} "
       f"blocks) and names {keys}")
r = run("compare", "base.mp4", "stiff.mp4")
ok("scene: pendulum.stiffness = 2 (expected) vs 2.2 (actual)" in r.stdout,
   f"the text names the key with both values ({r.stdout.strip()[-120:]})")
# A rule given for the video replaces the default.
r = run("compare", "base.mp4", "crf22.mp4", "--metric", "rms", "--tol", "0.5")
ok(r.returncode == 1 and "blocks" not in r.stdout, "an explicit rule replaces the videos' default")
with open(os.path.join(work, "compare.ini"), "w") as f:
    f.write("[base.mp4]\nmax_diff = 0\nmax_pixels = 0\n")
r = run("compare", "base.mp4", "crf22.mp4")
ok(r.returncode == 1 and "blocks" not in r.stdout, "so does a compare.ini section")

done()
