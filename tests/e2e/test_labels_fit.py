#!/usr/bin/env python3
"""springpend tests: [view] colorbar_label, xlabel and ylabel that are too
long are wrapped or refused, never drawn over the pendulum or off the
figure (issue 28; the attacker's fourth pass, doc/notes/2026-11-26d/
attack4.md, finding 4). As the attacker ran it:
- a still with a 45-character colour bar label keeps the pendulum in its
  column: the bob is found where a still without the bar draws it, whole
  (it was squeezed against the left edge and cut; with panels theta and
  energy it was not drawn at all);
- a colour bar label that wraps to more lines than half the bar's column
  is exit 2 saying it cannot fit and the limit, naming FILE:LINE or --set,
  and no file is written;
- a still's xlabel or ylabel wider than its panel is exit 2 the same way
  (the xlabel crossed the frame into the pendulum's column, a ylabel was
  dropped without a word); one that fits is drawn;
- a sweep figure's xlabel, ylabel and colorbar_label wider than the room
  the figure has are exit 2, no figure (they ran off the page); one that
  no figure has room for is refused before the grid runs.
The bob is found from its colour in the picture (ffmpeg decodes it), never
from the program's own layout.
usage: test_labels_fit.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os

import sptest
from sptest import done, err, ffmpeg_rgb, need_scipy, ok, part_files

exe, src, work, _ = sptest.setup("labels_fit", ["ffmpeg"])
need_scipy()
import numpy as np  # noqa: E402

run = sptest.runner_bytes(exe, work)
scenes = os.path.join(src, "..", "scenes")
default = os.path.join(scenes, "default.ini")
chaotic = os.path.join(scenes, "chaotic.ini")
STILL = ["--at", "5", "--size", "640x360", "--set", "view.trail=0"]
GRID = ["--vary", "initial.angle=1:179:8", "--vary", "initial.length=0.8:1.6:4",
        "--measure", "lyapunov", "--time", "2"]


def path(*names):
    return os.path.join(work, *names)


def bob(png):
    """(pixel count, mean x) of the bob's orange-red in the left 200 px of a
    640x360 still (the pendulum's column; no trail drawn), or (0, None)."""
    a = ffmpeg_rgb(png, 640, 360)[:, :200].astype(int)
    m = (a[:, :, 0] > 150) & (a[:, :, 1] < 110) & (a[:, :, 2] < 90)
    xs = np.nonzero(m)[1]
    return int(m.sum()), (float(xs.mean()) if len(xs) else None)


def refused(r, out, *words):
    e = err(r)
    return (r.returncode == 2 and not os.path.exists(out) and not part_files(os.path.dirname(out))
            and all(w in e for w in words) and "\x1b" not in e)


ref = path("ref.png")
r = run("still", default, *STILL, "-o", ref)
n_ref, x_ref = bob(ref) if r.returncode == 0 else (0, None)
ok(n_ref > 30, f"the reference still shows the bob ({n_ref} px; {err(r)[-200:]})")

# 1. a long colour bar label wraps in the bar's column: the bob stays put
for name, extra, label in [
        ("cb45", [], "speed of the bob along its helical path (m/s)"),
        ("labs2", ["--set", "view.panels=theta,energy"], "Wide label " * 5)]:
    out = path(name + ".png")
    r = run("still", default, *STILL, *extra, "--set", "view.colorbar=true",
            "--set", "view.colorbar_label=" + label.strip(), "-o", out)
    n, x = bob(out) if r.returncode == 0 else (0, None)
    ok(r.returncode == 0 and x_ref is not None and x is not None and 0.8 * n_ref <= n <= 1.25 * n_ref
       and abs(x - x_ref) < 30,
       f"{name}: a {len(label.strip())}-character colorbar_label keeps the pendulum in its "
       f"column (bob {n} px at x {x}, without the bar {n_ref} px at x {x_ref}; "
       f"exit {r.returncode} {err(r)[-200:]})")

# 2. a label that cannot fit is refused, where it was set, with the limit
long_label = ("speed of the bob " * 14).strip()
out = path("cbx.png")
r = run("still", default, *STILL, "--set", "view.colorbar=true",
        "--set", "view.colorbar_label=" + long_label, "-o", out)
ok(refused(r, out, "--set view.colorbar_label", "cannot fit", "allowed: at most half"),
   f"a colorbar_label of 21 lines is refused, no file ({r.returncode}: {err(r)[-300:]})")
scene = path("wide.ini")
with open(scene, "w") as f:
    f.write("[view]\npanels = r, theta\nxlabel = " + "Wide axis label " * 6 + "\n")
out = path("x.png")
r = run("still", scene, *STILL, "-o", out)
ok(refused(r, out, scene + ":3: [view] xlabel", "cannot fit the r panel", "allowed: at most"),
   f"a still's xlabel wider than its panel is refused at FILE:LINE ({err(r)[-300:]})")
out = path("y.png")
r = run("still", default, *STILL, "--set", "view.ylabel=" + "Wide axis label " * 6, "-o", out)
ok(refused(r, out, "--set view.ylabel", "cannot fit the r panel", "allowed: at most"),
   f"a still's ylabel wider than its panel is refused, not dropped ({err(r)[-300:]})")
out = path("y2.png")
r = run("still", default, *STILL, "--set", "view.ylabel=r in metres", "-o", out)
ok(r.returncode == 0 and os.path.getsize(out) > 0,
   f"a ylabel that fits is drawn ({err(r)[-200:]})")

# 3. sweep figures: nothing off the page
d = path("sweep")
os.makedirs(d)
wide = ("Wide axis label " * 12).strip()
out = os.path.join(d, "lab.png")
r = run("sweep", chaotic, *GRID, "--set", "view.xlabel=" + wide, "--set", "view.ylabel=" + wide,
        "--set", "view.colorbar_label=" + wide, "-o", out)
ok(refused(r, out, "--set view.xlabel", "cannot fit", "widest plot", "allowed: at most")
   and not os.listdir(d),
   f"sweep: labels wider than any figure's plot are refused before the grid, nothing written "
   f"({r.returncode}: {err(r)[-300:]}; {os.listdir(d)})")
out = os.path.join(d, "bar.png")
r = run("sweep", chaotic, *GRID, "--set", "view.colorbar_label=speed of the bob along its path",
        "-o", out)
ok(refused(r, out, "--set view.colorbar_label", "right of the plot", "allowed: at most"),
   f"sweep: a colour bar label wider than the room beside the plot is refused "
   f"({r.returncode}: {err(r)[-300:]})")
out = os.path.join(d, "bar.pdf")
r = run("sweep", chaotic, *GRID, "--size", "8.6cm", "--set",
        "view.colorbar_label=" + ("speed of the bob " * 3).strip(), "-o", out)
ok(refused(r, out, "--set view.colorbar_label", "bar's height", "allowed: at most"),
   f"sweep at 8.6 cm: a colour bar label longer than the bar is refused "
   f"({r.returncode}: {err(r)[-300:]})")
out = os.path.join(d, "fit.png")
r = run("sweep", chaotic, *GRID, "--set", "view.colorbar_label=λ (1/s) here",
        "--set", "view.xlabel=initial angle of the pendulum (degrees)",
        "--set", "view.ylabel=rest length (m)", "-o", out)
ok(r.returncode == 0 and os.path.getsize(out) > 0,
   f"sweep: labels that fit are drawn ({err(r)[-200:]})")

done()
