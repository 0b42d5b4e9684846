#!/usr/bin/env python3
"""springpend tests: smooth trails. The trail is sampled between frames
finely enough that its chords stay within half a pixel of the path, and
`trail = 5s` is a stretch of simulated time, so the same still at fps 10 and
fps 120, or at speed 1 and speed 3, draws the same trail. The rule: RMS of
the RGB differences at most 1 level (springpend compare --metric rms --tol 1;
one sample per frame, as before, gave 7.2 at fps 10 against 120).
usage: test_trails.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil
import subprocess
import sys

from sptest import done, ok, runner

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "trails"))
scene = os.path.join(src, "..", "scenes", "chaotic.ini")
if not shutil.which("ffmpeg"):
    print("1..0 # SKIP ffmpeg not installed")
    sys.exit(77)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
PLAIN = ["--set", "view.panels=none", "--set", "view.hud=false", "--set", "view.colorbar=false",
         "--size", "960x540", "-q"]


run = runner(exe, work)


def still(name, *args):
    r = run("still", scene, "--at", "20", "-o", name, *PLAIN, *args)
    if r.returncode:
        print("# " + r.stderr.strip())
    return r.returncode == 0


def same(a, b, tol="1"):
    r = run("compare", a, b, "--metric", "rms", "--tol", tol)
    print("# " + r.stdout.strip().splitlines()[0] if r.stdout.strip() else "# " + r.stderr.strip())
    return r.returncode == 0


made = all(still(f"fps{f}.png", "--fps", str(f), "--set", "view.trail=5s") for f in (10, 30, 120))
ok(made, "trail = 5s stills at fps 10, 30 and 120")
ok(same("fps120.png", "fps10.png"), "fps 10 draws the trail fps 120 draws (rms <= 1)")
ok(same("fps120.png", "fps30.png"), "fps 30 draws the trail fps 120 draws (rms <= 1)")
made = all(still(f"speed{v}.png", "--fps", "30", "--set", f"video.speed={v}",
                 "--set", "view.trail=5s", "--set", "video.duration=30",
                 "--set", "view.title=Chaos") for v in (1, 3))  # the speed mark goes beside the title
# the motion below the title band, where only speed 3 says "speed ×3"
for v in (1, 3):
    subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", os.path.join(work, f"speed{v}.png"), "-vf",
                    "crop=iw:ih-80:0:80", os.path.join(work, f"speed{v}_motion.png")], check=True)
ok(made and same("speed1_motion.png", "speed3_motion.png"), "speed 3 at 30 fps draws the trail speed 1 draws")
# A trail of frames is still a count of frames: 50 frames at fps 10 are 5 s,
# the same stretch as trail = 5s.
ok(still("frames.png", "--fps", "10", "--set", "view.trail=51") and same("frames.png", "fps10.png", "0.5"),
   "trail = 51 frames at fps 10 is the trail of 5 s")
# The rule sees a shorter trail.
ok(still("short.png", "--fps", "120", "--set", "view.trail=2s") and not same("fps120.png", "short.png"),
   "a 2 s trail differs from a 5 s one under the same rule")
# trail = all: what is older than its 10 s fade is drawn once into an
# accumulated picture; the video's last frame must equal a still of it.
SMALL = ["--size", "320x180", "--fps", "30", "--set", "view.trail=all", "--set", "video.duration=14",
         "--set", "view.panels=none", "--set", "view.hud=false", "-q"]
r = run("render", scene, "-o", "all_%03d.png", *SMALL)
s = run("still", scene, "--at", repr(419 / 30), "-o", "all_still.png", *SMALL)
ok(r.returncode == 0 and s.returncode == 0 and
   run("compare", "all_419.png", "all_still.png").returncode == 0,
   "trail = all: frame 419 of the video (accumulated) equals the still at its time")
for bad in ("0s", "5x", "-1s", "1e9s"):
    r = run("still", scene, "--set", f"view.trail={bad}", "-o", "bad.png")
    ok(r.returncode == 2 and "view.trail" in r.stderr and not os.path.exists(os.path.join(work, "bad.png")),
       f"view.trail = {bad} is refused")
done()
