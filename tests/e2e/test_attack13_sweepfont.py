#!/usr/bin/env python3
"""springpend tests (issue 28): the thirteenth attacker's pass, #26
(doc/notes/2026-11-27/attack13.md; fix20's notes): the default sweep figure
(no --size) took any view.font_size but kept its fixed margins: at 24 the x
axis's name was cut off at the page's foot, at 40 it was gone and the y
axis's name ran over the tick labels, at 80-200 the legend covered the plot,
the title stayed at 17 pt; exit 0. Now its margins come from its text at
the size in force, and a size whose plot would be too small for it is
refused before the sweep runs (exit 2, no file, the largest that fits).

The oracle is the figure itself, not springpend's layout: `pdftotext -bbox`
gives each word's box in a PDF; every word lies inside the 900 x 600 pt page,
no word lies over another, the x axis's name lies under every x tick label
and the y axis's name left of every y tick label, and the title is larger
than the tick labels in the same proportion at every size. The PNG, the SVG
(rsvg-convert) and the PDF (pdftoppm) have no ink in their outermost 2 px.
usage: test_attack13_sweepfont.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import re
import shutil
import subprocess
import time
from collections import Counter

import sptest
from sptest import done, ok, skip

exe, src, work, run, path, scenes, asan = sptest.attack_setup("attack13-sweepfont")
tools = all(shutil.which(t) for t in ("pdftotext", "pdftoppm", "rsvg-convert", "ffmpeg"))
NUMBER = re.compile(r"^[−-]?\d+(\.\d+)?$")

chaotic, parametric = (os.path.join(scenes, s) for s in ("chaotic.ini", "parametric.ini"))
# name: (sweep arguments, the x axis's name's words, the y axis's name's words)
FIGURES = {
    "line": ([chaotic, "--vary", "initial.angle=10:170:5", "--measure", "lyapunov", "--time", "2"],
             ["initial.angle", "(degrees)"], ["λ", "(1/s)"]),
    "map": ([chaotic, "--vary", "initial.angle=10:170:5", "--vary", "initial.length=0.8:1.6:4",
             "--measure", "lyapunov", "--time", "2"], ["initial.angle", "(degrees)"],
            ["initial.length", "(m)"]),
    "orbit": ([parametric, "--vary", "pivot.amplitude=0:0.05:11", "--measure", "orbit", "--transient",
               "5", "--time", "5"], ["pivot.amplitude", "(m)"], ["θ", "(degrees)"]),
    "continued": ([parametric, "--vary", "pivot.amplitude=0:0.05:11", "--measure", "orbit",
                   "--continue", "both", "--peak", "theta", "--transient", "5", "--time", "5"],
                  ["pivot.amplitude", "(m)"], ["θ", "(degrees)"]),
    "poincare": ([chaotic, "--vary", "initial.length=0.9:1.3:6", "--measure", "poincare", "--time",
                  "20"], ["r", "(m)"], ["ṙ", "(m/s)"]),
    "basins": ([parametric, "--set", "pivot.amplitude=0.01", "--vary", "initial.angle=-180:180:9",
                "--vary", "initial.angle_rate=-10:10:9", "--measure", "basins", "--transient", "5",
                "--time", "20"], ["initial.angle", "(degrees)"], ["initial.angle_rate", "(rad/s)"]),
    "spectrum": ([chaotic, "--measure", "spectrum", "--vary", "initial.angle=90:90:1", "--time",
                  "20"], ["log10", "T", "(s)"], ["λ", "(1/s)"]),
}


def sweep(fig, out, size=None, timeout=120):
    args, _, _ = FIGURES[fig]
    more = ["--set", f"view.font_size={size}"] if size is not None else []
    return run("sweep", *args, *more, "-o", path(out), "-q", timeout=timeout)


def words(pdf):
    """[(text, x0, y0, x1, y1)] in pt, from pdftotext -bbox."""
    out = subprocess.run(["pdftotext", "-bbox", pdf, "-"], capture_output=True, timeout=60).stdout.decode()
    return [(m.group(5), *map(float, m.group(1, 2, 3, 4))) for m in
            re.finditer(r'<word xMin="([-\d.]+)" yMin="([-\d.]+)" xMax="([-\d.]+)" yMax="([-\d.]+)">([^<]*)</word>', out)]


def ppm(data):
    """(width, height, RGB bytes) of a binary PPM."""
    parts = data.split(b"\n", 3)
    w, h = map(int, parts[1].split())
    return w, h, parts[3]


def raster(name):
    """A figure's pixels (width, height, RGB bytes): a PDF by pdftoppm, an
    SVG by rsvg-convert (to a PDF of its page, then pdftoppm), a PNG by
    ffmpeg."""
    p = path(name)
    if name.endswith(".svg"):
        subprocess.run(["rsvg-convert", "-f", "pdf", "-o", p + ".pdf", p], check=True, timeout=60)
        p += ".pdf"
    if p.endswith(".pdf"):
        return ppm(subprocess.run(["pdftoppm", "-r", "144", "-singlefile", p], capture_output=True,
                                  timeout=60).stdout)
    return ppm(subprocess.run(["ffmpeg", "-v", "error", "-i", p, "-f", "image2pipe", "-vcodec", "ppm",
                               "-pix_fmt", "rgb24", "-"], capture_output=True, timeout=60).stdout)


def ink_at_edge(name):
    """Pixels in the outermost 2 px of the figure unlike its corner (the
    background): text or lines cut by the page's edge."""
    w, h, px = raster(name)
    bg = px[0:3]
    n = 0
    for y in range(h):
        xs = range(w) if y < 2 or y >= h - 2 else (0, 1, w - 2, w - 1)
        for x in xs:
            i = 3 * (y * w + x)
            n += max(abs(px[i + k] - bg[k]) for k in range(3)) > 24
    return n


def sequence(ws, names, turned):
    """The words of an axis's name, in order: on one line left to right, or
    turned (the y axis's, reading upward) in one column, each above the
    last; [] when the page has no such run."""
    for first in (w for w in ws if w[0] == names[0]):
        run_, last = [first], first
        for name in names[1:]:
            nxt = [w for w in ws if w[0] == name and (
                abs(w[1] - last[1]) < 0.5 and abs(w[3] - last[3]) < 0.5 and w[4] <= last[2] + 0.5
                if turned else abs(w[2] - last[2]) < 0.5 and w[1] >= last[3] - 0.5)]
            if not nxt:
                break
            last = min(nxt, key=lambda w: abs(w[4] - run_[-1][2]) if turned else w[1] - run_[-1][3])
            run_.append(last)
        if len(run_) == len(names):
            return run_
    return []


def problems(fig, pdf):
    """What the word oracle finds wrong in a figure's PDF."""
    ws = words(path(pdf))
    _, xname, yname = FIGURES[fig]
    bad = []
    for t, x0, y0, x1, y1 in ws:
        if x0 < 0 or y0 < 0 or x1 > 900 or y1 > 600:
            bad.append(f"'{t}' ({x0:.1f},{y0:.1f})-({x1:.1f},{y1:.1f}) pt: off the 900 x 600 pt page")
    for i, (t, x0, y0, x1, y1) in enumerate(ws):
        for u, u0, v0, u1, v1 in ws[i + 1:]:
            ox, oy = min(x1, u1) - max(x0, u0), min(y1, v1) - max(y0, v0)
            if ox > 0.5 and oy > 0.25 * min(y1 - y0, v1 - v0):
                bad.append(f"'{t}' over '{u}' ({ox:.1f} x {oy:.1f} pt)")
    nums = [w for w in ws if NUMBER.match(w[0])]
    # the x tick labels: the numbers of the commonest row in the lower half; the y tick labels:
    # the numbers right-aligned at the commonest right edge in the left half
    low = [w for w in nums if w[2] > 300]
    row = Counter(round(w[2]) for w in low).most_common(1)
    xt = [w for w in low if row and abs(w[2] - row[0][0]) < 1.5]
    left = [w for w in nums if w[3] < 450]
    col = Counter(round(w[3]) for w in left).most_common(1)
    yt = [w for w in left if col and abs(w[3] - col[0][0]) < 1.5]
    xn, yn = sequence(ws, xname, False), sequence(ws, yname, True)
    if len(xn) < len(xname):
        bad.append(f"the x axis's name {xname} is not all on the page ({[w[0] for w in xn]})")
    if len(yn) < len(yname):
        bad.append(f"the y axis's name {yname} is not all on the page ({[w[0] for w in yn]})")
    for w in xn:
        if xt and w[2] < max(v[4] for v in xt) - 0.5:
            bad.append(f"the x axis's name '{w[0]}' (top {w[2]:.1f} pt) is not under the x tick labels "
                       f"(bottom {max(v[4] for v in xt):.1f} pt)")
    for w in yn:
        if yt and w[3] > min(v[1] for v in yt) + 0.5:
            bad.append(f"the y axis's name '{w[0]}' (right {w[3]:.1f} pt) is not left of the y tick "
                       f"labels (left {min(v[1] for v in yt):.1f} pt)")
    return bad, ws, yt


def title_ratio(ws, yt):
    """The title's first word's height over a y tick label's (pdftotext
    boxes: the font's size): 17/11.9 when the title scales with the text."""
    return (ws[0][4] - ws[0][2]) / (yt[0][4] - yt[0][2]) if ws and yt else 0


if not tools:
    skip("attack13 #26 sweep text sizes", "pdftotext, pdftoppm, rsvg-convert or ffmpeg is not installed")
    done()

# --- the finding's sizes and a video scene's: drawn inside the page, nothing over anything; or
# refused up front with the largest size that fits, which then draws clean
for fig in FIGURES:
    ratios = {}
    for size in (None, 10, 24, 30):
        tag = f"{fig}-{size or 'default'}"
        r = sweep(fig, tag + ".pdf", size)
        e = sptest.err(r)
        m = re.search(r"at most view\.font_size ([\d.]+)", e)
        if r.returncode == 2 and size is not None:
            ok(not os.path.exists(path(tag + ".pdf")) and m and "font_size" in e and
               float(m.group(1)) < size, f"{fig} at font_size {size}: refused, nothing written, naming "
               f"the largest size that fits ({e[:300]})")
            continue
        if r.returncode:
            ok(False, f"{fig} at font_size {size}: exit {r.returncode}: {e[:300]}")
            continue
        bad, ws, yt = problems(fig, tag + ".pdf")
        ratios[size] = title_ratio(ws, yt)
        ok(not bad, f"{fig} at font_size {size or 'default'}: every word inside the page, none over "
           f"another, the axes' names clear of the tick labels ({'; '.join(bad[:5])})")
    if None in ratios and 24 in ratios:
        ok(abs(ratios[24] - ratios[None]) < 0.1 * ratios[None],
           f"{fig}: the title scales with the text: title/tick {ratios[24]:.2f} at 24 pt, "
           f"{ratios[None]:.2f} at the default")

# --- the finding's large sizes: refused before the sweep runs (a long sweep returns at once),
# nothing written, with the largest size that fits; that size draws clean in each format
for fig in FIGURES:
    args, _, _ = FIGURES[fig]
    out = f"{fig}-80.png"
    long_args = [a if not a.isdigit() or args[i - 1] != "--time" else "100000" for i, a in enumerate(args)]
    t = time.monotonic()
    try:
        r = run("sweep", *long_args, "--set", "view.font_size=80", "-o", path(out), "-q", timeout=20)
        code, e = r.returncode, sptest.err(r)
    except subprocess.TimeoutExpired:
        code, e = None, "ran the sweep (still running after 20 s)"
    m = re.search(r"at most view\.font_size ([\d.]+)", e)
    ok(code == 2 and not os.path.exists(path(out)) and m and "font_size 80" in e,
       f"{fig} at font_size 80: refused before the sweep ({time.monotonic() - t:.1f} s), exit "
       f"{code}, nothing written, with the largest size that fits ({e[:300]})")
    if not m:
        continue
    best = float(m.group(1))
    r200 = sweep(fig, f"{fig}-200.svg", 200)
    ok(r200.returncode == 2 and not os.path.exists(path(f"{fig}-200.svg")),
       f"{fig} at font_size 200 -o .svg: refused, nothing written (exit {r200.returncode})")
    for ext in ("pdf", "png", "svg"):
        name = f"{fig}-best.{ext}"
        r = sweep(fig, name, best)
        if r.returncode:
            ok(False, f"{fig} at font_size {best} -o .{ext} (the largest the message names): exit "
               f"{r.returncode}: {sptest.err(r)[:300]}")
            continue
        edge = ink_at_edge(name)
        bad = problems(fig, name)[0] if ext == "pdf" else []
        ok(not bad and edge == 0, f"{fig} at font_size {best} -o .{ext}: drawn inside the page "
           f"({edge} px of ink at its edge), no word over another ({'; '.join(bad[:5])})")
    r = sweep(fig, f"{fig}-over.pdf", round(best + 0.6, 1))
    ok(r.returncode == 2, f"{fig} at font_size {round(best + 0.6, 1)}, past the largest: refused "
       f"(exit {r.returncode})")

# --- the default size's figures in each format: no ink at the page's edge (as before)
for fig in ("line", "basins"):
    for ext in ("png", "svg"):
        name = f"{fig}-default.{ext}"
        r = sweep(fig, name)
        ok(r.returncode == 0 and ink_at_edge(name) == 0,
           f"{fig} at the default size -o .{ext}: drawn inside the page (exit {r.returncode})")
done()
