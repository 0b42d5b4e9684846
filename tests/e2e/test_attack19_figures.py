#!/usr/bin/env python3
"""springpend tests (issue 28): the nineteenth attacker's pass
(doc/notes/2026-11-28/attack19.md), findings 4 and 7.

#4: a still of printed size past 10:1 (drawn without its heads-up text and
panels) whose title is too tall was refused with "laid out again, no larger
--size ..., view.font_size down to 5 pt or shorter view.panels list fits",
while font_size 5, 10 and 20 each drew: the trials were laid out with the
panels a 10:1 figure never has. Now every trial is laid out as the refused
figure: the 12inx1in case (PDF and PNG) names a font_size and a --size, and
each is run here and draws (the title on the page), half a point more is
refused (the advice says "the largest"), and the title refusal speaks pt as
the note beside it does (half of 1 in is 36 pt, worked out here).

#7: a sweep over one value (`--vary KEY=V:V:1`) drew an empty line figure:
a lone point has no segment. Each isolated point is now marked. Checked in
PNG, SVG and PDF of a lyapunov and a precession sweep: coloured ink at the
point's place, found from the figure's own tick labels (pdftotext -bbox:
each label's number at its centre, a straight line through them) and the
CSV's value, not from anything springpend says about where it drew.
usage: test_attack19_figures.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import re
import subprocess

import sptest
from sptest import done, ok

sptest.need_scipy()  # numpy, through Debian's python3 where the shim lacks it
import numpy as np  # noqa: E402

exe, src, work, run = sptest.setup("attack19-figures", ["pdftotext", "pdftoppm", "rsvg-convert",
                                                        "ffmpeg"])
scenes = os.path.abspath(os.path.join(src, "..", "scenes"))


def p(*names):
    return os.path.join(work, *names)


def words(pdf):
    """The PDF's first page size (pt) and its words as (text, xMin, yMin,
    xMax, yMax), from pdftotext -bbox."""
    out = subprocess.run(["pdftotext", "-bbox", pdf, "-"], capture_output=True,
                         text=True).stdout
    page = re.search(r'<page width="([\d.]+)" height="([\d.]+)"', out)
    ws = [(m.group(5), *map(float, m.group(1, 2, 3, 4))) for m in re.finditer(
        r'<word xMin="([-\d.]+)" yMin="([-\d.]+)" xMax="([-\d.]+)" yMax="([-\d.]+)">([^<]*)</word>',
        out)]
    return (float(page.group(1)), float(page.group(2))) if page else None, ws


# ---- #4: a too-tall title past 10:1 ----

def still(out, *sets):
    args = ["still", os.path.join(scenes, "default.ini"), "--at", "1", "--size", "12inx1in",
            "--set", "view.title=Hello"]
    for s in sets:
        args += ["--set", s]
    return run(*args, "-o", p(out))


def title_on_page(pdf):
    """Whether the PDF's page shows the word Hello: across inside the page,
    its box's middle on it (pdftotext's box is the font's ascent to its
    descent, taller than the letters)."""
    size, ws = words(pdf)
    return size is not None and any(
        w[0] == "Hello" and 0 <= w[1] and w[3] <= size[0] and 0 < (w[2] + w[4]) / 2 < size[1]
        for w in ws)


for ext in ("pdf", "png"):
    r = still(f"t40.{ext}", "view.font_size=40")
    e = r.stderr
    ok(r.returncode == 2 and not os.path.exists(p(f"t40.{ext}")),
       f"{ext}: 12inx1in at font_size 40, title Hello: refused, nothing written (exit {r.returncode})")
    ok("no larger --size" not in e, f"{ext}: not told that nothing fits: {e.strip()[-300:]}")
    # 1 in is 72 pt: at most half of it for the title, 36 pt; the frame's 72
    ok(re.search(r"of the frame's 72; allowed: at most half the height \(36 pt\)", e) is not None
       and re.search(r"lines at [\d.]+ pt wide", e) is not None,
       f"{ext}: the title refusal in pt, as the note beside it (36 of the frame's 72 pt): "
       + " | ".join(ln for ln in e.splitlines() if "cannot fit" in ln)[:400])
    font = re.search(r"--set view\.font_size=([\d.]+)", e)
    size = re.search(r"--size (\S+)", e)
    if not ok(font is not None and size is not None,
              f"{ext}: the advice names a view.font_size and a --size: {e.strip()[-300:]}"):
        continue
    fs = float(font.group(1))
    r = still(f"f.{ext}", f"view.font_size={fs:g}")
    ok(r.returncode == 0 and os.path.getsize(p(f"f.{ext}")) > 0,
       f"{ext}: the named view.font_size={fs:g} draws (exit {r.returncode}: {r.stderr.strip()[-200:]})")
    if ext == "pdf":
        ok(title_on_page(p("f.pdf")), "pdf: at that font_size the title Hello is on the page")
    r = still(f"f1.{ext}", f"view.font_size={fs + 0.5:g}")
    ok(r.returncode == 2, f"{ext}: half a point more ({fs + 0.5:g} pt) is refused: it was the "
       f"largest (exit {r.returncode})")
    r = run("still", os.path.join(scenes, "default.ini"), "--at", "1", "--size", size.group(1),
            "--set", "view.title=Hello", "--set", "view.font_size=40", "-o", p(f"s.{ext}"))
    ok(r.returncode == 0 and os.path.getsize(p(f"s.{ext}")) > 0,
       f"{ext}: the named --size {size.group(1)} draws font_size 40 (exit {r.returncode}: "
       f"{r.stderr.strip()[-200:]})")
    if ext == "pdf":
        ok(title_on_page(p("s.pdf")), "pdf: at that size the title Hello is on the page")

# the attacker's: 5, 10 and 20 pt fit at 12inx1in
for fs in (5, 10, 20):
    r = still(f"a{fs}.pdf", f"view.font_size={fs}")
    ok(r.returncode == 0, f"12inx1in at font_size {fs} draws (exit {r.returncode})")


# ---- #7: a lone point of a line figure ----

def number(text):
    try:
        return float(text.replace("\u2212", "-"))
    except ValueError:
        return None


def axes_map(pdf):
    """From the PDF's tick labels: x(value) and y(value) in pt. The x
    axis's labels are the numbers on the lowest row that holds at least
    three; the y axis's, the numbers right-aligned at one x left of the
    plot. Each label's number stands at its box's centre; a straight line
    through them (least squares) maps a value to the page."""
    _, ws = words(pdf)
    nums = [(number(w[0]), *w[1:]) for w in ws if number(w[0]) is not None]
    rows = {}
    for w in nums:
        rows.setdefault(round(w[2], 1), []).append(w)
    xs = max((r for r in rows.values() if len(r) >= 3), key=lambda r: r[0][2])
    cols = {}
    for w in nums:
        if w not in xs:
            cols.setdefault(round(w[3], 1), []).append(w)
    ys = max(cols.values(), key=len)
    fx = np.polyfit([w[0] for w in xs], [(w[1] + w[3]) / 2 for w in xs], 1)
    fy = np.polyfit([w[0] for w in ys], [(w[2] + w[4]) / 2 for w in ys], 1)
    return (lambda v: np.polyval(fx, v)), (lambda v: np.polyval(fy, v)), len(xs), len(ys)


def raster(name, w, h):
    """The figure at w x h px (a PNG as it is; an SVG or PDF rasterised at
    that size) as an RGB array; None when the rasteriser fails."""
    base, ext = os.path.splitext(p(name))
    if ext == ".png":
        return sptest.ffmpeg_rgb(p(name), w, h)
    out = base + "_" + ext[1:] + ".png"
    cmd = (["rsvg-convert", "-w", str(w), "-h", str(h), p(name), "-o", out] if ext == ".svg" else
           ["pdftoppm", "-scale-to-x", str(w), "-scale-to-y", str(h), "-png", "-singlefile",
            p(name), out[:-4]])
    if subprocess.run(cmd, capture_output=True).returncode:
        return None
    return sptest.ffmpeg_rgb(out, w, h)


def coloured_near(img, x, y, r):
    """How many pixels within r px of (x, y) are coloured (their channels
    more than 60 apart: the grid, axes and text are grey, the page dark)."""
    h, w, _ = img.shape
    yy, xx = np.mgrid[0:h, 0:w]
    near = (xx - x) ** 2 + (yy - y) ** 2 <= r * r
    sat = img.max(axis=2) - img.min(axis=2) > 60
    return int((near & sat).sum())


def lone(what, csv, column, scene, *args):
    r = run("sweep", os.path.join(scenes, scene), *args, "--shard", "1/1", "--csv", p(csv), "-q")
    if not ok(r.returncode == 0, f"{what}: swept one value (exit {r.returncode}: {r.stderr.strip()})"):
        return
    rows = [ln.split(",") for ln in open(p(csv)) if not ln.startswith("#")]
    head, vals = rows[0], rows[1:]
    ok(len(vals) == 1, f"{what}: one row: {vals}")
    key, value = float(vals[0][1]), float(vals[0][head.index(column)])
    base = csv[:-4]
    for e in ("pdf", "png", "svg"):
        r = run("sweep", "--merge", p(csv), "-o", p(f"{base}.{e}"), "-q")
        ok(r.returncode == 0, f"{what}: {e} drawn (exit {r.returncode}: {r.stderr.strip()})")
    size, _ = words(p(f"{base}.pdf"))
    X, Y, nx, ny = axes_map(p(f"{base}.pdf"))
    x, y = X(key), Y(value)
    ok(nx >= 3 and ny >= 3 and 0 < x < size[0] and 0 < y < size[1],
       f"{what}: {head[1]} = {key:g}, {column} = {value:g} at ({x:.1f}, {y:.1f}) pt on the "
       f"{size[0]:g}x{size[1]:g} pt page, from {nx} x and {ny} y tick labels")
    with open(p(f"{base}.png"), "rb") as f:  # the PNG's IHDR: its width and height
        ihdr = f.read(24)
    w, h = int.from_bytes(ihdr[16:20], "big"), int.from_bytes(ihdr[20:24], "big")
    for e in ("png", "svg", "pdf"):
        img = raster(f"{base}.{e}", w, h)
        k = w / size[0]  # px a pt
        n = 0 if img is None else coloured_near(img, x * k, y * k, 2 * k)
        far = 0 if img is None else coloured_near(img, x * k, Y(0.5 * value) * k, 2 * k)
        ok(n >= 4 * k * k and far == 0,
           f"{what} {e}: {n} coloured px within 2 pt of the point's place ({x * k:.0f}, {y * k:.0f}) "
           f"px, at least {4 * k * k:.0f}; none at half its value ({far})")


lone("lyapunov at initial.angle 30 alone", "l.csv", "lyapunov", "chaotic.ini",
     "--vary", "initial.angle=30:30:1", "--measure", "lyapunov", "--time", "5")
lone("precession at stiffness 20 alone", "pr.csv", "precession", "swinging-spring.ini",
     "--set", "initial.azimuth_rate=0.5", "--vary", "pendulum.stiffness=20:20:1",
     "--measure", "precession", "--time", "100")

done()
