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
  last speed, so the still equals the one of a scene whose video reaches it;
  side by side (each cell held at its own end) --at past the longest end is
  refused, naming the duration that would reach it;
- #10: the Markdown summary let GitHub read `$x^2$` as math and `:ok:` as an
  emoji: `$` and `:` are written as character references;
- #14: still --state ./s.png (or d//s.png, the absolute path) wrote the
  state over the image: refused before anything is computed;
- #15: a timeline time followed by `:` (`0:30 = caption: …`, `12:speed 0.5`)
  was split by libinih at the `:`: refused, saying a time is seconds;
- #13: data took --set video.fps (and speed) with --every, where it refuses
  --fps, and ensemble.trails, which it never writes; info took every key:
  refused, and the keys they read still change what they print;
- #17: a video whose caption says "run 7" where its baseline says "run 1"
  passes the block rule: the Markdown summary lists such passing images
  with the text keys that differ.
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
ok(r.returncode == 2 and "2 images already" in err(r) and "diffs of an earlier run" in err(r)
   and "would install" not in err(r),
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


# ---- 9: side by side, --at past the longest scene's end is refused ---------------------------
r = run("still", default, stiff, "--at", "100", "--size", "640x360", "-o", "two.png")
ok(r.returncode == 2 and "longest ends at t = 10 s" in err(r) and "video.duration=100" in err(r)
   and not os.path.exists(path("two.png")),
   f"9: side by side at --at 100 (both 10 s long): refused, naming the end and a duration that "
   f"reaches it (exit {r.returncode}: {err(r)[:200]})")
r = run("still", default, stiff, "--at", "100", "--set", "video.duration=100", "--size", "640x360",
        "-o", "two.png", "-q")
ok(r.returncode == 0 and os.path.exists(path("two.png")),
   f"9: with the duration it names, the same still is drawn (exit {r.returncode}: {err(r)[:160]})")

# ---- 10: the summary writes $ and : as character references ----------------------------------
d = path("md")
shutil.rmtree(d, ignore_errors=True)
for sub in ("e", "a"):
    os.makedirs(os.path.join(d, sub))
run("still", default, "--at", "0", "--size", "80x45", "-o", os.path.join(d, "e0.png"), "-q")
run("still", stiff, "--at", "1", "--size", "80x45", "-o", os.path.join(d, "a0.png"), "-q")
names = ["$x^2$", ":+1:", ":ok:", "$PASS$"]
for n in names:
    shutil.copy(os.path.join(d, "e0.png"), os.path.join(d, "e", n + ".png"))
    shutil.copy(os.path.join(d, "a0.png"), os.path.join(d, "a", n + ".png"))
r = run("compare", os.path.join(d, "e"), os.path.join(d, "a"), "--summary", os.path.join(d, "s.md"), "-q")
md = open(os.path.join(d, "s.md")).read() if os.path.exists(os.path.join(d, "s.md")) else ""
rows = [l for l in md.splitlines() if l.startswith("| ") and ".png" in l]
import html  # noqa: E402
shown = sorted(html.unescape(l.split(" | ")[0][2:]) for l in rows)
ok(r.returncode == 1 and len(rows) == 4 and not any("$" in l or re.search(r":[a-z0-9+]+:", l) for l in rows)
   and shown == sorted(n + ".png" for n in names),
   f"10: the summary's rows hold no raw $ or :name: and read back as the names ({shown})")

# ---- 14: --state at the image's path, however spelled, is refused ----------------------------
d = path("state")
shutil.rmtree(d, ignore_errors=True)
os.makedirs(os.path.join(d, "d"))
for o_, st in (("s.png", "./s.png"), ("d/s.png", "d//s.png"), ("t.png", os.path.join(d, "t.png"))):
    r = subprocess.run([exe, "still", default, "--at", "1", "--size", "320x180", "-o", o_, "--state", st,
                        "-q"], cwd=d, capture_output=True, text=True)
    ok(r.returncode == 2 and "would overwrite the scene or the image" in r.stderr
       and not os.path.exists(os.path.join(d, o_)),
       f"14: still -o {o_} --state {st}: refused, nothing written (exit {r.returncode}: {r.stderr[:140]})")

# ---- 15: a timeline time followed by ':' is refused ------------------------------------------
for cue in ("0:30 = caption: half a minute", "12:speed 0.5", "5: pause 2: note"):
    name = path("colon.ini")
    with open(name, "w") as f:
        f.write(head + "[timeline]\n" + cue + "\n")
    r = run("info", name)
    ok(r.returncode == 2 and f"colon.ini:{line}: [timeline] the line starts" in err(r)
       and "not 0:30" in err(r),
       f"15: [timeline] {cue!r}: refused at its line (exit {r.returncode}: {err(r)[:160]})")
name = path("colon-ok.ini")
with open(name, "w") as f:
    f.write(head + "[timeline]\n3 = caption: a: b\n")
r = run("info", name)
ok(r.returncode == 0, f"15: '3 = caption: a: b' (a ':' in the text) is still taken (exit {r.returncode})")


# ---- 13: data and info refuse the --set keys they do not read --------------------------------
for args, key in [(["data", default, "--every", "0.5", "--set", "video.fps=30"], "video.fps"),
                  (["data", default, "--every", "0.5", "--set", "video.speed=3"], "video.speed"),
                  (["data", default, "--poincare", "--set", "video.fps=30"], "video.fps"),
                  (["data", default, "--set", "ensemble.trails=true"], "ensemble.trails"),
                  (["info", default, "--set", "view.hud=true"], "view.hud"),
                  (["info", default, "--set", "video.crf=20"], "video.crf"),
                  (["info", default, "--set", "ensemble.count=10"], "ensemble.count")]:
    r = run(*args, "-o" if args[0] == "data" else "--json", *(["unread.csv"] if args[0] == "data" else []))
    ok(r.returncode == 2 and f"does not read {key}" in err(r) and not os.path.exists(path("unread.csv"))
       and not r.stdout.strip(),
       f"13: {' '.join(a for a in args[2:])}: {args[0]} refuses {key}, exit 2, nothing written "
       f"(exit {r.returncode}: {err(r)[:140]})")
# what they read still counts: video.fps without --every sets data's rows, pendulum.mass
# sets info's omega_spring = sqrt(k/m)
r = run("data", default, "--set", "video.fps=10", "--set", "video.duration=1", "-o", "-", "-q")
rows = r.stdout.decode().splitlines()[1:] if r.returncode == 0 else []
ok(len(rows) == 10, f"13: data --set video.fps=10 over 1 s (no --every): 10 rows ({len(rows)})")
r = run("info", default, "--set", "pendulum.mass=2", "--json")
k = float(re.search(r"^stiffness\s*=\s*([0-9.eE+-]+)", open(default).read(), re.M).group(1))
w = json.loads(r.stdout).get("omega_spring") if r.returncode == 0 else None
ok(w is not None and abs(w - (k / 2) ** 0.5) < 1e-9,
   f"13: info --set pendulum.mass=2: omega_spring = sqrt(k/m) = {(k / 2) ** 0.5:.6g} ({w})")

# ---- 17: a passing video drawn with another caption is listed in the summary ------------------
d = path("cap")
shutil.rmtree(d, ignore_errors=True)
for sub in ("e", "a"):
    os.makedirs(os.path.join(d, sub))
for sub, cap in (("e", "Energy exchange, run 1"), ("a", "Energy exchange, run 7")):
    run("render", default, "--set", "video.duration=0.5", "--size", "640x360", "--set",
        f"view.caption={cap}", "-o", os.path.join(d, sub, "v.mp4"), "-q")
    run("render", default, "--set", "video.duration=0.5", "--size", "640x360",
        "-o", os.path.join(d, sub, "same.mp4"), "-q")
r = run("compare", os.path.join(d, "e"), os.path.join(d, "a"), "--summary", os.path.join(d, "s.md"))
md = open(os.path.join(d, "s.md")).read() if os.path.exists(os.path.join(d, "s.md")) else ""
listed = [l for l in md.splitlines() if l.startswith("| v.mp4 | view.caption |")]
ok(r.returncode == 0 and "drawn with other text than the baseline" in md and len(listed) == 1
   and "run 1" in listed[0] and "run 7" in listed[0] and "same.mp4" not in md,
   f"17: a caption 'run 1' vs 'run 7' passes the block rule (exit {r.returncode}) and the summary "
   f"lists it with both texts, not the unchanged video ({listed})")

done()
