#!/usr/bin/env python3
"""springpend tests (issue 28): the seventeenth attacker's pass
(doc/notes/2026-11-27/attack17.md), finding 10's second half: a still with
`view.trail = all` drew every segment of the whole run into its settled
layer, so an SVG's size and the memory behind it grew with --at (a 106 MB
SVG at --at 10000), and as translucent strokes stacked, the SVG's trail
grew brighter with every lap while the PNG's (GL_MAX) did not. A segment
that crosses only cells an earlier one crossed in its colour is now left
out (src/frame/cover.h), and the SVG draws the settled trail in the colour
GL_MAX gives it over an opaque background.

What is checked, from the files and their pixels (never springpend's own
counts):
- the SVG and PDF at --at 3000 are not much larger than at --at 300 (ten
  times the laps; before, 9.3 times the SVG's bytes);
- the SVG, rasterised at the PNG's size, shows the trail as the PNG does:
  over the pixels the trail inks, their mean difference is small, and no
  brighter than the PNG on the whole (before, the stacked strokes were
  saturated);
- a PNG sequence's last frame and the still at its time are the same pixels
  (the segments left out depend only on those before them);
- a transparent background keeps the translucent strokes (nothing to mix
  with), and its SVG is bounded too.
usage: test_attack17_trail.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import subprocess

import sptest
from sptest import done, ok

sptest.need_scipy()  # numpy, through Debian's python3 where the shim lacks it
import numpy as np  # noqa: E402

exe, src, work, run = sptest.setup("attack17-trail", ["rsvg-convert", "ffmpeg"])
scene = os.path.abspath(os.path.join(src, "..", "scenes", "default.ini"))
W, H = 480, 270
ALL = ["--size", f"{W}x{H}", "--set", "view.trail=all", "-q"]


def still(at, out, *more):
    r = run("still", scene, "--at", str(at), "-o", out, *ALL, *more)
    if r.returncode:
        sptest.diag(r.stderr)
    return r.returncode == 0


def size(name):
    return os.path.getsize(os.path.join(work, name))


# 1. Bounded by the picture: ten times the laps, not ten times the file.
made = all(still(at, f"t{at}.{e}") for at in (300, 3000) for e in ("svg", "pdf", "png"))
ok(made, "stills with trail = all at --at 300 and 3000 (SVG, PDF, PNG)")
for e in ("svg", "pdf"):
    a, b = (size(f"t{at}.{e}") if made else 0 for at in (300, 3000))
    sptest.diag(f"{e}: {a} bytes at --at 300, {b} at --at 3000 ({b / max(a, 1):.2f}x)")
    ok(made and b < 1.5 * a, f"the {e.upper()} at --at 3000 is under 1.5x the one at --at 300")

# 2. The SVG looks as the PNG does where the trail is.
png = sptest.ffmpeg_rgb(os.path.join(work, "t3000.png"), W, H) if made else None
ok(still(3000, "bare.png", "--set", "view.trail=0"), "the same still without a trail")
if made:
    subprocess.run(["rsvg-convert", "-w", str(W), "-h", str(H), "-o", os.path.join(work, "svg.png"),
                    os.path.join(work, "t3000.svg")], check=True)
    svg = sptest.ffmpeg_rgb(os.path.join(work, "svg.png"), W, H)
    bare = sptest.ffmpeg_rgb(os.path.join(work, "bare.png"), W, H)
    inked = np.abs(png - bare).max(axis=2) > 24  # what the trail draws in the PNG
    diff = np.abs(svg - png)[inked].mean() if inked.any() else 999
    brighter = (svg - png)[inked].mean() if inked.any() else 999
    sptest.diag(f"trail pixels {int(inked.sum())}: mean |SVG - PNG| {diff:.1f} levels, "
                f"mean SVG - PNG {brighter:+.1f}")
    # cairo and GL antialias a 1-2 px line differently: 26 levels here, 44 before
    ok(inked.sum() > 500 and diff < 32, "the SVG's trail is within 32 levels of the PNG's on average")
    ok(inked.sum() > 500 and brighter < 12, "the SVG's trail is not brighter than the PNG's (laps do not stack)")
else:
    ok(False, "the SVG's trail is within 32 levels of the PNG's on average")
    ok(False, "the SVG's trail is not brighter than the PNG's (laps do not stack)")

# 3. A video's frame and the still at its time leave out the same segments.
os.makedirs(os.path.join(work, "seq"))
LONG = ["--fps", "2", "--set", "video.duration=60", "--set", "view.panels=none"]
r = run("render", scene, "-o", "seq/%05d.png", *LONG, *ALL)
ok(r.returncode == 0, "a 60 s PNG sequence at 2 fps with trail = all")
ok(still(59.5, "at59.5.png", *LONG), "the still at its last frame's time, 59.5 s")
last = os.path.join(work, "seq", "00119.png")
if r.returncode == 0 and os.path.exists(last):
    same = np.array_equal(sptest.ffmpeg_rgb(last, W, H),
                          sptest.ffmpeg_rgb(os.path.join(work, "at59.5.png"), W, H))
else:
    same = False
ok(same, "the sequence's last frame and the still are the same pixels")

# 4. A transparent background: strokes stay translucent, the SVG bounded.
made = all(still(at, f"clear{at}.svg", "--set", "view.background=transparent")
           for at in (300, 3000))
ok(made, "transparent stills at --at 300 and 3000")
a, b = (size(f"clear{at}.svg") if made else 0 for at in (300, 3000))
sptest.diag(f"transparent svg: {a} bytes at --at 300, {b} at --at 3000")
ok(made and b < 1.5 * a, "the transparent SVG at --at 3000 is under 1.5x the one at --at 300")
done()
