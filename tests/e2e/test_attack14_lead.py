#!/usr/bin/env python3
"""springpend tests (issue 28): the fourteenth attacker's pass
(doc/notes/2026-11-27/attack14.md), the lead's findings:
- #1: the heads-up time-fit check (attack12 #19's fix) refused four scenes
  side by side on a 360x640 portrait frame once video.duration passed
  10 s, though the time was drawn clear of the panels: the time may use
  the gap right of its column, never the panel's box. The oracle is the
  picture (decoded by ffmpeg): the time's ink ends left of the first
  panel's box, found by its fill colour;
- #5: side by side refused scenes whose encoder gets the same settings:
  crf 0 (automatic: H.264's 23) beside crf = 23, preset auto beside
  superfast (what auto is); the values the encoder gets are compared (a
  WebM's automatic crf is VP9's 32, so 0 beside 23 is refused there);
- #4: a video retagged BT.2020/PQ (or full range) without re-encoding was
  compared as identical, though players convert its colours: refused, exit
  2, naming the tag (ffmpeg's h264_metadata writes the tags here); an
  untagged re-encode and springpend's own WebM and GIF are still read.
usage: test_attack14_lead.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import re
import shutil
import subprocess

import sptest
from sptest import done, err, ok, skip

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack14-lead")
default = os.path.join(scenes, "default.ini")

# 1: four masses side by side, 360x640 (two columns of 180x320 cells)
text = open(default).read()
names = []
for m in (1, 2, 3, 4):
    names.append(path(f"v{m}.ini"))
    with open(names[-1], "w") as f:
        f.write(re.sub(r"^mass\s*=.*$", f"mass = {m}", text, flags=re.M))
for duration in (11, 100):
    out = path(f"four-{duration}.png")
    r = run("still", *names, "--set", f"video.duration={duration}", "--at", str(duration - 0.01),
            "--size", "360x640", "-o", out, "-q")
    ok(r.returncode == 0 and os.path.exists(out),
       f"1: four scenes side by side at 360x640, video.duration = {duration}: drawn "
       f"(exit {r.returncode}: {err(r)[-160:]})")


def pixels(name):
    """The picture's RGB bytes, decoded by ffmpeg (not by springpend)."""
    return subprocess.run(["ffmpeg", "-v", "error", "-i", name, "-f", "rawvideo", "-pix_fmt", "rgb24",
                           "-"], capture_output=True, check=True).stdout


if not shutil.which("ffmpeg"):
    skip("1: the time's ink keeps off the first panel's box", "ffmpeg missing")
elif not os.path.exists(path("four-100.png")):
    ok(False, "1: the time's ink keeps off the first panel's box (no picture drawn)")
else:
    W, CELL = 360, 180
    img = pixels(path("four-100.png"))
    at = lambda x, y: img[(y * W + x) * 3:(y * W + x) * 3 + 3]
    # the first panel's box: its fill, read by its right edge in the time's
    # rows, and the first column of that fill from the left
    fill_y = 40
    fill = at(CELL - 8, fill_y)
    edge = next((x for x in range(CELL // 4, CELL) if at(x, fill_y) == fill), CELL)
    # the time's rows: below the title, the first rows with ink at the
    # cell's left ("t ="), to the first row with none left of the box
    bg = at(edge - 1, fill_y)
    inked = lambda y: any(at(x, y) != bg for x in range(edge))
    first = next(y for y in range(26, 160) if any(at(x, y) != bg for x in range(20)))
    last = next(y for y in range(first, 160) if not inked(y))
    right = max(x for y in range(first, last) for x in range(edge) if at(x, y) != bg)
    ok(edge < CELL - 20 and right < edge - 1,
       f"1: the time (rows {first}..{last - 1}) has its ink to x {right}, clear of the first "
       f"panel's box from x {edge}")

# 5: the encoder's own values, not the keys' spellings (23 and superfast:
# x264's defaults as springpend's sink_video.c sets them, doc/outputs.md)
def variant(name, key, value):
    out = path(name)
    with open(out, "w") as f:
        f.write(re.sub(rf"^{key}\s*=.*$", f"{key} = {value}",
                       re.sub(r"^mass\s*=.*$", "mass = 2", text, flags=re.M), flags=re.M))
    return out


short = ["--set", "video.duration=0.2", "--set", "video.fps=10", "--size", "320x180"]
for other, out, want in [(variant("crf23.ini", "crf", 23), "crf.mp4", 0),
                         (variant("superfast.ini", "preset", "superfast"), "preset.mp4", 0),
                         (variant("crf30.ini", "crf", 30), "crf30.mp4", 2),
                         (path("crf23.ini"), "crf.webm", 2)]:
    r = run("render", default, other, *short, "-o", path(out), "-q", timeout=120)
    ok(r.returncode == want and os.path.exists(path(out)) == (want == 0),
       f"5: default.ini (crf 0, preset auto) beside {os.path.basename(other)} -o {out}: exit "
       f"{r.returncode}, want {want} ({err(r)[-140:]})")

# 4: colour tags players honour
vid = path("v.mp4")
r = run("render", default, "--set", "video.duration=1", "--set", "video.fps=10", "--size", "320x180",
        "-o", vid, "-q", timeout=120)
if not shutil.which("ffmpeg") or r.returncode != 0:
    skip("4: a video's colour tags", "ffmpeg missing or the render failed")
else:
    for name, bsf, said in [("hdr.mp4", "colour_primaries=9:transfer_characteristics=16:"
                             "matrix_coefficients=9", "bt2020"),
                            ("full.mp4", "video_full_range_flag=1", "full range")]:
        subprocess.run(["ffmpeg", "-loglevel", "error", "-y", "-i", vid, "-c", "copy", "-bsf:v",
                        f"h264_metadata={bsf}", path(name)], check=True)
        r = run("compare", vid, path(name))
        ok(r.returncode == 2 and said in err(r) and "tagged" in err(r),
           f"4: compare v.mp4 {name} (retagged: {bsf}): refused, exit 2, naming '{said}' "
           f"(exit {r.returncode}: {err(r)[-160:]})")
    subprocess.run(["ffmpeg", "-loglevel", "error", "-y", "-i", vid, "-c:v", "libx264",
                    path("re.mp4")], check=True)
    r = run("compare", vid, path("re.mp4"))
    ok(r.returncode == 0, f"4: an untagged re-encode is still compared (exit {r.returncode}: "
       f"{err(r)[-120:]})")
done()
