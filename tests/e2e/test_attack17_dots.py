#!/usr/bin/env python3
"""springpend tests (issue 28): the seventeenth attacker's pass
(doc/notes/2026-11-27/attack17.md), finding 10: an orbit diagram or a
Poincare mosaic drawn as SVG or PDF held and wrote every dot, one a row, so
its memory and file grew with --time (833 MB of RAM and a 163 MB SVG at
T = 1000 s) while the PNG stayed flat. Dots that fall in one small cell of
the plot are now drawn as one, with the opacity they make together: the
vector figure's dots, file and memory are bounded by the figure's size.

What is checked, from the CSV rows and the pictures (never from
springpend's own counts): the SVG's dots and bytes and the PDF's filled
rectangles at T = 1000 s are not ten times those at T = 100 s (the rows
are), and far fewer than the rows; the SVG and PDF, rasterised at the PNG's
size, show ink wherever the PNG does and nowhere it does not (within a
pixel), and the PNG's dense spots (many dots at one place) stay dense in
them. A Poincare mosaic likewise.
usage: test_attack17_dots.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import re
import subprocess
import zlib

import sptest
from sptest import done, ok

sptest.need_scipy()  # numpy, through Debian's python3 where the shim lacks it
import numpy as np  # noqa: E402

exe, src, work, run = sptest.setup("attack17-dots", ["rsvg-convert", "pdftoppm", "ffmpeg"])
scenes = os.path.abspath(os.path.join(src, "..", "scenes"))


def p(*names):
    return os.path.join(work, *names)


def sweep(csv, scene, *args):
    """The rows of a one-shard sweep into csv, then its figure in PNG, SVG
    and PDF from those rows (sweep --merge): the number of rows, or None."""
    r = run("sweep", os.path.join(scenes, scene), *args, "--shard", "1/1", "--csv", p(csv), "-q")
    if r.returncode:
        print(f"# {csv}: {r.stderr.strip()}")
        return None
    for e in ("png", "svg", "pdf"):
        r = run("sweep", "--merge", p(csv), "-o", p(csv[:-4] + "." + e), "-q")
        if r.returncode:
            print(f"# {csv} {e}: {r.stderr.strip()}")
            return None
    return sum(1 for _ in open(p(csv))) - 1


def svg_dots(name):
    """The SVG's dots: filled paths that are squares of 1 to 2.5 pt a side."""
    n = 0
    for d in re.findall(r'<path style="[^"]*fill:[^"]*" d="([^"]*)"', open(p(name)).read()):
        m = re.fullmatch(r"M ([-\d.e]+) ([-\d.e]+) L ([-\d.e]+) \2 L \3 ([-\d.e]+) L \1 \4 Z M \1 \2 ",
                         d)
        if m:
            side = abs(float(m.group(3)) - float(m.group(1)))
            n += 1 <= side <= 2.5 and abs(abs(float(m.group(4)) - float(m.group(2))) - side) < 1e-3
    return n


def pdf_rects(name):
    """The PDF's filled rectangles ('re f'), its streams inflated."""
    data, n = open(p(name), "rb").read(), 0
    for m in re.finditer(rb"stream\r?\n(.*?)endstream", data, re.S):
        try:
            n += zlib.decompress(m.group(1)).count(b" re f")
        except zlib.error:
            pass
    return n


def raster(name):
    """The SVG or PDF rasterised at the PNG's size (2 px a pt: 1800 x 1200),
    as an RGB array; None when the rasteriser fails."""
    base, ext = os.path.splitext(p(name))
    out = base + "_" + ext[1:] + ".png"
    cmd = (["rsvg-convert", "-w", "1800", "-h", "1200", p(name), "-o", out] if ext == ".svg" else
           ["pdftoppm", "-r", "144", "-png", "-singlefile", p(name), out[:-4]])
    if subprocess.run(cmd, capture_output=True).returncode:
        return None
    return sptest.ffmpeg_rgb(out, 1800, 1200)


def ink(img, bg):
    """How far each pixel is from the background, 0..255."""
    return np.abs(img - bg).max(axis=2)


def grown(mask):
    """mask with each pixel's 8 neighbours set too."""
    g = mask.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            g |= np.roll(np.roll(mask, dy, 0), dx, 1)
    return g


def same_dots(what, png, vec):
    """The vector picture vec shows ink where the PNG png does, within a
    pixel, both ways, over the plot (where the dots are); and the PNG's dense
    spots (ink past 70% of its darkest) are dense in vec too (past 45%)."""
    if vec is None:
        return ok(False, f"{what}: rasterised")
    bg = png[700, 5]  # the page's margin, left of the axes
    a, b = ink(png, bg), ink(vec, bg)
    a[:, :180] = b[:, :180] = 0  # the axes' labels and ticks: text, antialiased differently
    pa, pb = a > 40, b > 40
    miss = (pa & ~grown(pb)).sum() / max(pa.sum(), 1)
    extra = (pb & ~grown(pa)).sum() / max(pb.sum(), 1)
    ok(miss < 0.005 and extra < 0.005,
       f"{what}: ink where the PNG has ink, within a pixel (missing {miss:.4f}, extra {extra:.4f} "
       f"of {pa.sum()} and {pb.sum()} px; at most 0.005)")
    dense = a > 0.7 * a.max()
    kept = (grown(b > 0.45 * a.max()) & dense).sum() / max(dense.sum(), 1)
    ok(dense.sum() > 100 and kept > 0.98,
       f"{what}: the PNG's {dense.sum()} dense px (many dots at one spot) dense too: {kept:.4f} "
       "(at least 0.98)")


# An orbit diagram of 40 amplitudes over 100 s and 1000 s (one row a drive period).
rows = {T: sweep(f"o{T}.csv", "parametric.ini", "--vary", "pivot.amplitude=0.05:0.2:40",
                 "--measure", "orbit", "--time", str(T)) for T in (100, 1000)}
if ok(None not in rows.values(), "orbit diagrams at T = 100 and 1000 s drawn (PNG, SVG, PDF)"):
    ok(rows[1000] > 9 * rows[100], f"the rows grow with T: {rows[100]} and {rows[1000]}")
    d = {T: svg_dots(f"o{T}.svg") for T in rows}
    ok(d[100] > 500 and d[1000] < 1.5 * d[100],
       f"the SVG's dots do not grow with T: {d[100]} at 100 s, {d[1000]} at 1000 s (rows: "
       f"{rows[100]}, {rows[1000]}); at most 1.5 times")
    ok(d[1000] < rows[1000] / 4, f"the SVG at 1000 s: {d[1000]} dots for {rows[1000]} rows "
       "(dots at one spot drawn once; fewer than a quarter of the rows)")
    s = {T: os.path.getsize(p(f"o{T}.svg")) for T in rows}
    ok(s[1000] < 1.5 * s[100], f"the SVG's bytes do not grow with T: {s[100]} and {s[1000]}")
    r = {T: pdf_rects(f"o{T}.pdf") for T in rows}
    ok(r[100] > 500 and r[1000] < 1.5 * r[100],
       f"the PDF's filled rectangles do not grow with T: {r[100]} and {r[1000]}")
    png = sptest.ffmpeg_rgb(p("o1000.png"), 1800, 1200)
    same_dots("orbit SVG at 1000 s", png, raster("o1000.svg"))
    same_dots("orbit PDF at 1000 s", png, raster("o1000.pdf"))

# A Poincare mosaic of 10 starts at one energy over 300 s and 3000 s.
prow = {T: sweep(f"p{T}.csv", "chaotic.ini", "--set", "initial.angle=0", "--vary",
                 "initial.length=0.4:1.8:10", "--measure", "poincare", "--energy", "3.13958",
                 "--time", str(T)) for T in (300, 3000)}
if ok(None not in prow.values(), "Poincaré mosaics at T = 300 and 3000 s drawn (PNG, SVG, PDF)"):
    d = {T: svg_dots(f"p{T}.svg") for T in prow}
    # a mosaic's closed curves fill in with T, so its dots only level off
    # once they are drawn whole: here fewer than the rows, not all of them
    ok(d[3000] < 0.8 * prow[3000] and d[3000] < 8 * d[300],
       f"the mosaic's SVG dots: {d[300]} and {d[3000]} for {prow[300]} and {prow[3000]} rows "
       "(fewer than 0.8 of the rows; under 8 times the shorter run's)")
    png = sptest.ffmpeg_rgb(p("p3000.png"), 1800, 1200)
    same_dots("mosaic SVG at 3000 s", png, raster("p3000.svg"))
    same_dots("mosaic PDF at 3000 s", png, raster("p3000.pdf"))

done()
