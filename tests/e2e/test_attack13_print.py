#!/usr/bin/env python3
"""springpend tests (issue 28): the thirteenth attacker's pass
(doc/notes/2026-11-27/attack13.md), #19: a still at a printed size
(`--size 8.6cm`, SVG/PDF/PNG) is exempt from the small-frame rule, and
nothing took its place: resonance.ini's panels at 8.6 cm (one journal
column) drew the energy and modes legends under their curves, at 1 in
square text ran over text, at 10 x 1 in the legends over the next panels;
exit 0, no word. Now a layout whose panel cannot hold its title, legend and
a plot, or whose title or legend entry crosses the panel's edge, is refused:
exit 2, nothing written, the message naming the panel and what to do (fewer
panels, a smaller view.font_size, a larger --size).

The oracle for the figures that are drawn (the README's and doc/'s own
commands, and the remedies the message names) is the PDF, not springpend:
`pdftotext -bbox` gives the words' boxes, `pdftoppm` the pixels. A still at
--at T and one at T - 2 s share their static text (the same word in the
same box) and differ in the data (curves, markers, the pendulum): no pixel
that differs may lie inside a static word's box (the curves drawn over a
legend or title), and no two words' boxes may overlap (text over text).
usage: test_attack13_print.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import re
import shutil
import subprocess

import sptest
from sptest import done, ok, skip

exe, src, work, run, path, scenes, asan = sptest.attack_setup("attack13-print")
tools = all(shutil.which(t) for t in ("pdftotext", "pdftoppm"))
DPI = 150


def words(pdf):
    """[(text, x0, y0, x1, y1)] in pt, from pdftotext -bbox."""
    out = subprocess.run(["pdftotext", "-bbox", pdf, "-"], capture_output=True, timeout=60).stdout.decode()
    return [(m.group(5), *map(float, m.group(1, 2, 3, 4))) for m in
            re.finditer(r'<word xMin="([-\d.]+)" yMin="([-\d.]+)" xMax="([-\d.]+)" yMax="([-\d.]+)">([^<]*)</word>', out)]


def pixels(pdf):
    """(width, height, bytes) of the page at DPI, RGB, from pdftoppm."""
    data = subprocess.run(["pdftoppm", "-r", str(DPI), "-singlefile", pdf], capture_output=True,
                          timeout=60).stdout
    parts = data.split(b"\n", 3) if data.startswith(b"P6") else None
    w, h = map(int, parts[1].split())
    return w, h, parts[3]


def still(scene, at, size, out, *more):
    return run("still", os.path.join(scenes, scene), "--at", str(at), "--size", size, "-o", path(out),
               "-q", *more)


def problems(scene, at, size, name, *more):
    """None when the still is refused; else the list of what the oracle
    finds wrong in it (data pixels in a static word's box, words over
    words), or ['exit N'] when it failed otherwise."""
    a, b = still(scene, at, size, name + "-a.pdf", *more), still(scene, at - 2, size, name + "-b.pdf", *more)
    if a.returncode == 2:
        return None
    if a.returncode or b.returncode:
        return [f"exit {a.returncode}/{b.returncode}: {sptest.err(a)}"]
    wa, wb = words(path(name + "-a.pdf")), words(path(name + "-b.pdf"))
    static = [w for w in wa if any(w[0] == v[0] and all(abs(w[i] - v[i]) < 0.05 for i in range(1, 5))
                                   for v in wb)]
    W, H, pa = pixels(path(name + "-a.pdf"))
    _, _, pb = pixels(path(name + "-b.pdf"))
    s = DPI / 72
    bad = []
    for t, x0, y0, x1, y1 in static:
        # the glyphs' ink: the box less a tenth of its height at the top and bottom (ascent/descent room)
        m = 0.1 * (y1 - y0)
        n = 0
        for y in range(max(0, int((y0 + m) * s) + 1), min(H, int((y1 - m) * s))):
            row = y * W * 3
            for x in range(max(0, int(x0 * s) + 1), min(W, int(x1 * s))):
                i = row + 3 * x
                n += pa[i:i + 3] != pb[i:i + 3]
        if n > 2:
            bad.append(f"'{t}' ({x0:.1f},{y0:.1f})-({x1:.1f},{y1:.1f}) pt: {n} px of data in it")
    for i, (t, x0, y0, x1, y1) in enumerate(wa):
        for u, u0, v0, u1, v1 in wa[i + 1:]:
            ox, oy = min(x1, u1) - max(x0, u0), min(y1, v1) - max(y0, v0)
            # more than a quarter of the lower box's height and 0.5 pt across: not two lines' leading
            if ox > 0.5 and oy > 0.25 * min(y1 - y0, v1 - v0):
                bad.append(f"'{t}' over '{u}' ({ox:.1f} x {oy:.1f} pt)")
    return bad


if not tools:
    skip("attack13 #19 printed sizes", "pdftotext or pdftoppm (poppler-utils) is not installed")
    done()

# --- the finding's figures, and the same at each format: refused, nothing written
cases = [("resonance.ini", "8.6cm", "c86.pdf", []), ("resonance.ini", "1inx1in", "w1.pdf", []),
         ("resonance.ini", "10inx1in", "w2.pdf", []), ("resonance.ini", "8.6cm", "c86.svg", []),
         ("resonance.ini", "8.6cm", "c86.png", ["--dpi", "150"]), ("default.ini", "8.6cm", "d86.pdf", [])]
for scene, size, out, more in cases:
    r = still(scene, 20, size, out, *more)
    e = sptest.err(r)
    ok(r.returncode == 2 and not os.path.exists(path(out)) and " panel (" in e and "fewer panels" in e
       and "font_size" in e and "--size" in e,
       f"{scene} --size {size} -o {out}: refused, nothing written, saying which panel and what to do "
       f"(exit {r.returncode}, written {os.path.exists(path(out))}: {e[:300]})")

# --- the finding's figures as the oracle sees them, where drawn: on the old build the curves in the
# legends (resonance 8.6 cm: tot/kin/spr/grav, bounce/swing) and text over text (1 in square)
for scene, size, name in [("resonance.ini", "8.6cm", "o-c86"), ("resonance.ini", "1inx1in", "o-w1"),
                          ("default.ini", "8.6cm", "o-d86")]:
    bad = problems(scene, 20, size, name)
    ok(bad is None or not bad, f"{scene} --size {size}: refused, or drawn with no data in its words and "
       f"no word over another ({'refused' if bad is None else '; '.join(bad[:6])})")

# --- shipped commands (README.md, doc/figures.md) and the remedies the message names: drawn, clean
light = ["--set", "view.theme=light"]
drawn = [
    ("chaotic.ini", 30, "8.6cm", "doc-poincare", ["--set", "view.panels=poincare", "--set", "view.pendulum=false",
                                                  "--set", "view.hud=false", *light]),
    ("chaotic.ini", 30, "8.6cm", "doc-chaotic", []),  # doc/figures.md: --size 8.6cm --dpi 600 -o poincare.png
    ("chaotic.ini", 30, "8.6cmx8cm", "doc-fig2", ["--set", "view.pendulum=false", "--set",
                                                  "view.panels=poincare,phase", "--set", "view.panel_labels=a",
                                                  *light]),
    ("chaotic.ini", 60, "8.6cm", "doc-still", ["--set", "view.panels=poincare", "--set", "view.pendulum=false",
                                               "--set", "view.hud=false", *light]),
    ("resonance.ini", 20, "17.8cm", "larger", []),  # a larger --size (two columns)
    ("default.ini", 20, "8.6cm", "fewer", ["--set", "view.panels=r,energy"]),  # fewer panels
    ("default.ini", 20, "8.6cm", "smaller", ["--set", "view.font_size=7"]),  # a smaller font_size
]
for scene, at, size, name, more in drawn:
    bad = problems(scene, at, size, name, *more)
    ok(bad == [], f"{scene} --at {at} --size {size} {' '.join(more)}: drawn (exit 0), no data in its words, "
       f"no word over another ({'refused' if bad is None else '; '.join(bad[:6]) or 'clean'})")
r = run("still", os.path.join(scenes, "chaotic.ini"), "--at", "30", "--size", "8.6cm", "--dpi", "600", "-o",
        path("poincare.png"), "-q")
ok(r.returncode == 0 and os.path.getsize(path("poincare.png")) > 0,
   f"doc/figures.md's still chaotic.ini --at 30 --size 8.6cm --dpi 600 -o poincare.png: exit 0 "
   f"(exit {r.returncode}: {sptest.err(r)[:200]})")
done()
