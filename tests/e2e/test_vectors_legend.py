#!/usr/bin/env python3
"""springpend tests: the arrows' legend (`[view] vectors`) never covers the
pendulum. At small frames no corner of the view is free of the motion, and
the legend used to sit on the spring (480x270 and 640x360). The motion over
the whole run is computed here (scipy's DOP853 on the planar equations,
sptest.model) and put into px with the PNG's springpend.overlay scale and
origin; no bob position (with the bob's radius) and not the pivot may lie in
the legend's box (vectors.legend_px), and the legend lies inside the frame.
usage: test_vectors_legend.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil
import sys

from sptest import done, model, need_scipy, ok, png_overlay, runner, solve, start

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "vectors_legend"))
need_scipy()
import numpy as np  # noqa: E402
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
run = runner(exe, work)
scenes = os.path.join(src, "..", "scenes")

# scene, its physics (L0, k, m; r0, theta0 in degrees; duration s), --set
CASES = [("resonance.ini", (1.0, 29.43, 1.0), (1.4333, 1.0), 40,
          ["view.vectors=forces,velocity", "view.panels=r,energy_bars"]),
         ("default.ini", (0.5, 2.0, 0.5), (0.55, 10.0), 10, ["view.vectors=forces,velocity"])]
for name, (L0, k, m), (r0, th0), dur, sets in CASES:
    ts = np.linspace(0, dur, 20001)
    sol = solve(model(L0, k, m), start(r0, th0), dur, ts)
    x, y = sol.y[0], sol.y[1]
    for size in ("480x270", "640x360", "1280x720"):
        W, H = map(int, size.split("x"))
        out = os.path.join(work, f"{name[:-4]}-{size}.png")
        args = [a for s in sets for a in ("--set", s)]
        r = run("still", os.path.join(scenes, name), "--at", "3", "--size", size, "-q", "-o", out,
                *args)
        ov = png_overlay(out) if r.returncode == 0 else {}
        if not ok("vectors.legend_px" in ov, f"{name} {size}: still with vectors, overlay states "
                  f"the legend's box (exit {r.returncode}: {r.stderr.strip()[:100]})"):
            continue
        lx0, ly0, lx1, ly1 = map(float, ov["vectors.legend_px"].split(","))
        s = float(ov["camera.px_per_m"])
        ox, oy = map(float, ov["camera.origin_px"].split(","))
        px, py = ox + s * x, oy - s * y
        rad = 0.02 * min(W, H)  # about the bob's drawn radius
        inside = (px > lx0 - rad) & (px < lx1 + rad) & (py > ly0 - rad) & (py < ly1 + rad)
        pivot = lx0 - rad < ox < lx1 + rad and ly0 - rad < oy < ly1 + rad
        ok(not inside.any() and not pivot and lx0 >= 0 and ly0 >= 0 and lx1 <= W and ly1 <= H,
           f"{name} {size}: the legend ({lx0:.0f}-{lx1:.0f}, {ly0:.0f}-{ly1:.0f} px) is off the "
           f"pendulum: {int(inside.sum())} of {len(px)} bob positions and "
           f"{'the' if pivot else 'not the'} pivot in it")
done()
