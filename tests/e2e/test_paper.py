#!/usr/bin/env python3
"""springpend tests: figures of physical size (still --size 8.6cm, --dpi).
usage: test_paper.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)

A journal column is 8.6 cm (243.78 pt). The page size is read back with
pdfinfo, the text sizes with pdftotext -bbox: a word's box is the font's
ascent to descent, so its height over (Ascent - Descent) / 1000 (the PDF's
own FontDescriptor of the embedded font) is the size in pt. The fonts are
read with pdffonts. A PNG's size is its IHDR, its resolution its pHYs chunk.
Exits 77 (skip) without pdfinfo, pdftotext or pdffonts (poppler-utils)."""
import html
import math
import os
import re
import shutil
import struct
import subprocess
import sys

from sptest import done, manual, ok, runner

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "paper"))
root = os.path.join(src, "..")
need = [t for t in ("pdfinfo", "pdftotext", "pdffonts") if not shutil.which(t)]
if need:
    print(f"1..0 # SKIP {', '.join(need)} not installed")
    sys.exit(77)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
run = runner(exe, work)
CM = 72 / 2.54  # pt


def p(name):
    return os.path.join(work, name)


def scene(name):
    return os.path.join(root, "scenes", name)


# Print figures: no heads-up text, the light theme.
PRINT = ["--set", "view.hud=false", "--set", "view.theme=light"]


def still(name, sc, *args):
    r = run("still", scene(sc), "--at", "30", "-o", p(name), "-q", *args)
    if r.returncode:
        print(f"# {name}: {r.stderr.strip()}")
    return r.returncode == 0


def page_size(pdf):
    """(width, height) in pt from pdfinfo."""
    out = subprocess.run(["pdfinfo", pdf], capture_output=True, text=True).stdout
    m = re.search(r"Page size:\s+([\d.]+) x ([\d.]+) pts", out)
    return (float(m.group(1)), float(m.group(2))) if m else (0, 0)


def text_sizes(pdf):
    """Every word's font size, pt: its box's height over the font's ascent
    minus descent (the FontDescriptor's, 1/1000 em); for a word turned a
    quarter (a y axis's name), its box's width. A word of three characters or
    more is turned when its box is taller than wide; shorter ones are left
    out (a turned "λ" looks like an upright one)."""
    data = open(pdf, "rb").read()
    asc = [int(v) for v in re.findall(rb"/Ascent (-?\d+)", data)]
    desc = [int(v) for v in re.findall(rb"/Descent (-?\d+)", data)]
    if not asc or len(set(asc)) != 1 or len(set(desc)) != 1:
        return []  # one font expected here
    em = (asc[0] - desc[0]) / 1000
    out = subprocess.run(["pdftotext", "-bbox", pdf, "-"], capture_output=True, text=True).stdout
    sizes = []
    for x0, y0, x1, y1, w in re.findall(
            r'<word xMin="([^"]+)" yMin="([^"]+)" xMax="([^"]+)" yMax="([^"]+)">([^<]*)<', out):
        if len(html.unescape(w)) < 3:
            continue
        dx, dy = float(x1) - float(x0), float(y1) - float(y0)
        sizes.append((dx if dy > dx else dy) / em)
    return sizes


def words(pdf):
    out = subprocess.run(["pdftotext", "-bbox", pdf, "-"], capture_output=True, text=True).stdout
    return re.findall(r"<word [^>]*>([^<]*)</word>", out)


def fonts(pdf):
    """(name, embedded) per font pdffonts lists."""
    out = subprocess.run(["pdffonts", pdf], capture_output=True, text=True).stdout
    rows = out.splitlines()[2:]
    return [(r.split()[0], r.split()[-5] == "yes") for r in rows if r.strip()]


def png_info(path):
    """(width, height, pixels per metre or None) from the PNG's chunks."""
    d = open(path, "rb").read()
    w, h = struct.unpack(">II", d[16:24])
    i = d.find(b"pHYs")
    ppm = struct.unpack(">IIB", d[i + 4:i + 13]) if i > 0 else None
    return w, h, ppm


# ---- a still at a journal column's width ----
if still("poincare.pdf", "chaotic.ini", "--size", "8.6cm", "--set", "view.panels=poincare",
         "--set", "view.pendulum=false", *PRINT):
    w, h = page_size(p("poincare.pdf"))
    ok(abs(w - 8.6 * CM) < 0.01, f"the Poincare still is 8.6 cm wide: {w} pt = {w / CM:.3f} cm")
    ok(abs(h - 8.6 * CM * 720 / 1280) < 0.01,
       f"its height follows the scene's 1280x720 aspect: {h} pt")
    sizes = text_sizes(p("poincare.pdf"))
    ok(sizes and all(7.9 <= s <= 10.1 for s in sizes),
       f"its {len(sizes)} words are set in 8-10 pt: {sorted(set(round(s, 2) for s in sizes))}")
    ok(max(sizes or [0]) > 9.9, "the panel's title in 10 pt body text (matplotlib's default)")
    f = fonts(p("poincare.pdf"))
    ok(f and all(e for _, e in f) and all("DejaVuSans" in n for n, _ in f),
       f"its font is DejaVu Sans, embedded: {f}")
else:
    ok(False, "still --size 8.6cm -o poincare.pdf")

# The font asked for is the one embedded.
if still("noto.pdf", "chaotic.ini", "--size", "8.6cmx6cm", "--set", "view.panels=poincare",
         "--set", "view.font=Noto Sans", *PRINT):
    f = fonts(p("noto.pdf"))
    ok(f and all(e for _, e in f) and any("NotoSans" in n for n, _ in f),
       f"view.font = Noto Sans embeds Noto Sans: {f}")
    w, h = page_size(p("noto.pdf"))
    ok(abs(w - 8.6 * CM) < 0.01 and abs(h - 6 * CM) < 0.01, f"--size 8.6cmx6cm: {w} x {h} pt")
else:
    ok(False, "still --size 8.6cmx6cm -o noto.pdf")

# Text stays in pt whatever the size: the same words at twice the width.
if still("wide.pdf", "chaotic.ini", "--size", "17.2cm", "--set", "view.panels=poincare",
         "--set", "view.pendulum=false", *PRINT):
    a, b = text_sizes(p("poincare.pdf")), text_sizes(p("wide.pdf"))
    ok(a and b and abs(max(a) - max(b)) < 0.05 and abs(min(a) - min(b)) < 0.05,
       f"text at 17.2 cm is the size it is at 8.6 cm: {min(b):.2f}-{max(b):.2f} pt")

# A two-panel still.
if still("two.pdf", "chaotic.ini", "--size", "8.6cmx8cm", "--set", "view.panels=phase,poincare",
         "--set", "view.pendulum=false", *PRINT):
    w, h = page_size(p("two.pdf"))
    ok(abs(w - 8.6 * CM) < 0.01, f"the two-panel still is 8.6 cm wide: {w / CM:.3f} cm")
    sizes = text_sizes(p("two.pdf"))
    ok(sizes and all(7.9 <= s <= 10.1 for s in sizes),
       f"its words are 8-10 pt: {sorted(set(round(s, 2) for s in sizes))}")
else:
    ok(False, "still --size 8.6cmx8cm -o two.pdf")

# SVG: the size in pt on the root element.
if still("poincare.svg", "chaotic.ini", "--size", "3.4in", "--set", "view.panels=poincare", *PRINT):
    head = open(p("poincare.svg")).read(400)
    m = re.search(r'width="([\d.]+)pt" height="([\d.]+)pt"', head)
    ok(m and abs(float(m.group(1)) - 3.4 * 72) < 0.01,
       f"--size 3.4in SVG is {m.group(1) if m else '?'} pt wide")
else:
    ok(False, "still --size 3.4in -o poincare.svg")

# PNG: pixels from --dpi (300 by default), the dpi in pHYs.
for dpi in (None, 150):
    name = f"png{dpi or 300}.png"
    if still(name, "chaotic.ini", "--size", "246pt", *PRINT, *(["--dpi", str(dpi)] if dpi else [])):
        w, h, ppm = png_info(p(name))
        want = int(246 / 72 * (dpi or 300) + 0.5)  # C round(): halves away from 0
        ok(w == want, f"--size 246pt at {dpi or 300} dpi: {w} px wide (expected {want})")
        ok(ppm and ppm[2] == 1 and abs(ppm[0] - (dpi or 300) / 0.0254) < 1,
           f"its pHYs says {dpi or 300} dpi: {ppm}")
    else:
        ok(False, f"still --size 246pt -o {name}")

# ---- a figure's panels: the order given, (a)/(b) labels, one unit, no video marks ----
def boxes(pdf):
    """(x0, y0, word) for every word pdftotext -bbox finds."""
    out = subprocess.run(["pdftotext", "-bbox", pdf, "-"], capture_output=True, text=True).stdout
    return [(float(x0), float(y0), html.unescape(w)) for x0, y0, w in re.findall(
        r'<word xMin="([^"]+)" yMin="([^"]+)" xMax="[^"]+" yMax="[^"]+">([^<]*)<', out)]


def after(bx, word):
    """The word right of `word` on its line (None when there is none)."""
    at = [b for b in bx if b[2] == word]
    if not at:
        return None
    x, y = at[0][0], at[0][1]
    right = sorted((b for b in bx if abs(b[1] - y) < 2 and b[0] > x), key=lambda b: b[0])
    return right[0][2] if right else None


FIG = ["--size", "8.6cmx8cm", "--set", "view.pendulum=false", *PRINT]
if still("order.pdf", "chaotic.ini", *FIG, "--set", "view.panels=poincare,phase",
         "--set", "view.panel_labels=a"):
    bx = boxes(p("order.pdf"))
    ws = [b[2] for b in bx]
    ok(after(bx, "(a)") == "Poincaré" and after(bx, "(b)") in ("r,", "Phase") and "(c)" in ws,
       f"panels = poincare, phase with panel_labels = a: (a) Poincaré, then (b), (c) the phase "
       f"portraits: (a) {after(bx, '(a)')}, (b) {after(bx, '(b)')}")
    a = [b for b in bx if b[2] == "(a)"]
    b = [b for b in bx if b[2] == "(b)"]
    ok(a and b and (a[0][1] < b[0][1] - 2 or (abs(a[0][1] - b[0][1]) < 2 and a[0][0] < b[0][0])),
       "(a) comes first in reading order (above, or left on the same row)")
    ok("(rad/s)" in ws and not any("°/s" in w for w in ws),
       f"the phase portrait's θ̇ is in rad/s, as data's and sweep's CSVs: "
       f"{[w for w in ws if '/s' in w]}")
    ok("now" not in ws and "latest" not in ws,
       "a still leaves out the video's 'now' and 'latest' (view.cursor = auto)")
    # the labelled two-panel figure at a journal column: its page, its text, its font
    w, h = page_size(p("order.pdf"))
    sizes = text_sizes(p("order.pdf"))
    f = fonts(p("order.pdf"))
    ok(abs(w - 8.6 * CM) < 0.01 and sizes and all(7.9 <= s <= 10.1 for s in sizes) and
       f and all(e for _, e in f) and all("DejaVuSans" in n for n, _ in f),
       f"the labelled still is 8.6 cm wide ({w / CM:.3f} cm), its words and labels 8-10 pt "
       f"({sorted(set(round(s, 2) for s in sizes))}), DejaVu Sans embedded ({f})")
else:
    ok(False, "still -o order.pdf")
if still("order_rev.pdf", "chaotic.ini", *FIG, "--set", "view.panels=phase,poincare",
         "--set", "view.panel_labels=A"):
    bx = boxes(p("order_rev.pdf"))
    ok(after(bx, "(C)") == "Poincaré", f"panels = phase, poincare: (C) is the Poincaré section "
       f"({after(bx, '(C)')})")
if still("cursor.pdf", "chaotic.ini", *FIG, "--set", "view.panels=poincare,phase",
         "--set", "view.cursor=true"):
    ws = words(p("cursor.pdf"))
    ok("now" in ws and "latest" in ws, "view.cursor = true keeps 'now' and 'latest' in a still")
if still("plain.pdf", "chaotic.ini", *FIG, "--set", "view.panels=poincare,r",
         "--set", "view.panel_titles=false", "--set", "view.legend=none",
         "--set", "view.xlabel=Px | Rt", "--set", "view.ylabel=Py"):
    ws = words(p("plain.pdf"))
    ok(not any(w in ws for w in ("Poincaré", "Spring", "crossings")),
       f"panel_titles = false, legend = none: no titles, no legend: {ws}")
    ok(ws.count("Px") == 1 and ws.count("Rt") == 1 and ws.count("Py") == 2 and "(m/s)" not in ws,
       "xlabel 'Px | Rt' names each panel's x axis in panels' order, ylabel 'Py' both y axes")
# the order round-trips through the scene the PNG records
if still("order.png", "chaotic.ini", "--size", "640x480", "--set", "view.pendulum=false",
         "--set", "view.panels=poincare,energy,phase"):
    r = run("scene", p("order.png"))
    ok(r.returncode == 0 and "panels = poincare, energy, phase" in r.stdout,
       f"springpend scene prints the panels in their order: "
       f"{[l for l in r.stdout.splitlines() if l.startswith('panels')]}")
# a label per panel, or one for all: anything else is refused with its line
bad = p("labels.ini")
open(bad, "w").write("[view]\npanels = poincare, r\nxlabel = \"a | b | c\"\n")
r = run("still", bad, "-o", p("labels.png"), "-q")
ok(r.returncode == 2 and f"{bad}:3: view.xlabel" in r.stderr and "3 entries for 2 plots" in r.stderr
   and not os.path.exists(p("labels.png")), f"xlabel with 3 entries for 2 plots: {r.stderr.strip()}")

# ---- sweep figures at a printed size ----
MAP = ["--vary", "initial.angle=10:170:8", "--vary", "initial.length=0.8:1.6:6",
       "--measure", "lyapunov", "--time", "2"]
POINC = ["--vary", "initial.length=0.7:1.5:6", "--set", "initial.angle=0", "--measure",
         "poincare", "--time", "30"]
ORBIT = ["--vary", "pivot.amplitude=0.05:0.2:12", "--measure", "orbit", "--transient", "10",
         "--time", "10"]


def sweep(name, sc, grid, *args):
    r = run("sweep", scene(sc), *grid, "-o", p(name), "-q", *args)
    if r.returncode:
        print(f"# {name}: {r.stderr.strip()}")
    return r.returncode == 0


for name, sc, grid in (("map.pdf", "chaotic.ini", MAP), ("mosaic.pdf", "chaotic.ini", POINC),
                       ("orbit.pdf", "parametric.ini", ORBIT)):
    if not sweep(name, sc, grid, "--size", "8.6cm", "--csv", p(name + ".csv")):
        ok(False, f"sweep --size 8.6cm -o {name}")
        continue
    w, h = page_size(p(name))
    ok(abs(w - 8.6 * CM) < 0.01 and abs(h - 8.6 * CM * 2 / 3) < 0.01,
       f"sweep {name}: 8.6 cm wide, 2/3 as high: {w} x {h} pt")
    sizes = text_sizes(p(name))
    body = [s for s in sizes if s < 11]
    ok(sizes and all(8 <= s <= 10.1 for s in body) and all(11.5 <= s <= 12.5 for s in sizes if s >= 11),
       f"sweep {name}: ticks and labels in 8-10 pt, the title 12: "
       f"{sorted(set(round(s, 2) for s in sizes))}")
    f = fonts(p(name))
    ok(f and all(e for _, e in f) and all("DejaVuSans" in n for n, _ in f),
       f"sweep {name}: DejaVu Sans embedded: {f}")
    # the numbers do not depend on the figure's size
    r = run("sweep", scene(sc), *grid, "-o", p("plain_" + name), "-q", "--csv", p("plain.csv"))
    ok(r.returncode == 0 and open(p(name + ".csv"), "rb").read() == open(p("plain.csv"), "rb").read(),
       f"sweep {name}: the CSV's bytes are the same with and without --size")

# One notation per quantity: a rate is dotted (θ̇) in every figure and
# message, the basins' legend and attractor lines too (they said θ').
r = run("sweep", scene("parametric.ini"), "--set", "pivot.amplitude=0.01", "--vary",
        "initial.angle=-180:180:6", "--vary", "initial.angle_rate=-10:10:6", "--measure", "basins",
        "--transient", "20", "--time", "200", "-o", p("basins.pdf"))
t = subprocess.run(["pdftotext", "-raw", p("basins.pdf"), "-"], capture_output=True,
                   text=True).stdout if r.returncode == 0 else ""
said = r.stdout + r.stderr
ok(r.returncode == 0 and "θ\u0307 4.13 rad/s" in t and "θ'" not in t and "θ\u0307 4.13 rad/s" in said
   and "θ'" not in said,
   f"the basins' legend and attractor lines write θ̇, never θ': "
   f"{[l for l in t.splitlines() if 'rad/s' in l]} {[l for l in said.splitlines() if 'attractor' in l]}")

# The fonts asked for are the ones a sweep figure embeds, as a still's.
if sweep("map_noto.pdf", "chaotic.ini", MAP, "--size", "8.6cm", "--set", "view.font=Noto Sans"):
    f = fonts(p("map_noto.pdf"))
    ok(f and all(e for _, e in f) and any("NotoSans" in n for n, _ in f),
       f"view.font = Noto Sans: the 8.6 cm Lyapunov map embeds Noto Sans: {f}")
else:
    ok(False, "sweep --size 8.6cm --set view.font=Noto Sans -o map_noto.pdf")


def creator(pdf):
    out = subprocess.run(["pdfinfo", pdf], capture_output=True, text=True).stdout
    m = re.search(r"^Creator:\s*(.*)$", out, re.M)
    return m.group(1).strip() if m else ""


# One figure model: a sweep figure is a draw list drawn by the still
# figures' cairo backend (draw_cairo.c), which signs its documents; the
# sweep's own cairo code left cairo's default Creator in its PDFs.
ok(creator(p("map.pdf")).startswith("springpend ") and creator(p("map.pdf")) == creator(p("poincare.pdf")),
   f"the sweep figure's PDF and the still's come from one backend: Creator "
   f"{creator(p('map.pdf'))!r} and {creator(p('poincare.pdf'))!r}")

# every style key changes the sweep figure and the still alike: rendered
# with pdftoppm (150 dpi) against the figure without the key
def raster(pdf):
    r = subprocess.run(["pdftoppm", "-r", "150", "-png", "-singlefile", pdf, pdf[:-4]],
                       capture_output=True)
    return open(pdf[:-4] + ".png", "rb").read() if r.returncode == 0 else b""


# A key a map has nothing for (a legend, series colours, markers) is tried
# on the sweep figure that has it: a Lyapunov line (one key), the mosaic.
LINE = ["--vary", "initial.angle=10:170:12", "--measure", "lyapunov", "--time", "2"]
KEYS = [("view.theme", "dark", MAP), ("view.colormap", "inferno", MAP),
        ("view.colormap", "magma", MAP), ("view.colormap", "cividis", MAP),
        ("view.colormap", "gray", MAP), ("view.font", "Noto Sans", MAP),
        ("view.font_size", "8", MAP), ("view.title", "Sweep A", MAP),
        ("view.background", "#ffe0c0", MAP), ("view.xlabel", "X axis", MAP),
        ("view.ylabel", "Y axis", MAP), ("view.colorbar_label", "Z colours", MAP),
        ("view.panel_titles", "false", MAP), ("view.panel_labels", "a", MAP),
        ("view.legend", "none", LINE), ("view.palette", "okabe_ito", LINE),
        ("view.marker_size", "6", POINC)]
if shutil.which("pdftoppm"):
    # the still has the trail's colour bar, so that colorbar_label has a bar to name
    STILL_KEYS = [*PRINT, "--set", "view.panels=poincare", "--set", "view.colorbar=true"]
    base_sweep = {}
    for grid in (MAP, LINE, POINC):
        base_sweep[id(grid)] = sweep("key_base.pdf", "chaotic.ini", grid, "--size", "8.6cm",
                                     "--set", "view.theme=light") and raster(p("key_base.pdf"))
    base_still = still("key_base_still.pdf", "chaotic.ini", "--size", "8.6cm",
                       *STILL_KEYS) and raster(p("key_base_still.pdf"))
    for key, val, grid in KEYS:
        a = sweep("key_sweep.pdf", "chaotic.ini", grid, "--size", "8.6cm", "--set", "view.theme=light",
                  "--set", f"{key}={val}") and raster(p("key_sweep.pdf"))
        b = still("key_still.pdf", "chaotic.ini", "--size", "8.6cm", *STILL_KEYS,
                  "--set", f"{key}={val}") and raster(p("key_still.pdf"))
        ok(a and b and a != base_sweep[id(grid)] and b != base_still,
           f"{key} = {val} changes the sweep figure and the still")
    # viridis is chaotic.ini's own colormap: tried against inferno
    va = sweep("key_sweep.pdf", "chaotic.ini", MAP, "--size", "8.6cm", "--set", "view.theme=light",
               "--set", "view.colormap=viridis") and raster(p("key_sweep.pdf"))
    vb = still("key_still.pdf", "chaotic.ini", "--size", "8.6cm", *STILL_KEYS,
               "--set", "view.colormap=viridis") and raster(p("key_still.pdf"))
    ia = sweep("key_sweep.pdf", "chaotic.ini", MAP, "--size", "8.6cm", "--set", "view.theme=light",
               "--set", "view.colormap=inferno") and raster(p("key_sweep.pdf"))
    ib = still("key_still.pdf", "chaotic.ini", "--size", "8.6cm", *STILL_KEYS,
               "--set", "view.colormap=inferno") and raster(p("key_still.pdf"))
    ok(va and vb and ia and ib and va != ia and vb != ib,
       "view.colormap = viridis (against inferno) changes the sweep figure and the still")
    t = words(p("key_sweep.pdf"))
    if sweep("notitle.pdf", "chaotic.ini", MAP, "--size", "8.6cm", "--set", "view.title="):
        ok("Lyapunov" not in words(p("notitle.pdf")) and "Lyapunov" in words(p("map.pdf")),
           "sweep --set view.title= removes the title")

# ---- the README's page of figures: each at its printed size, with its command ----
# Each picture is an 8.6 cm PDF rasterised at 300 dpi (1016 px wide; 8.6 x 8
# cm: 1016 x 945) and shown 325 CSS px wide (8.6 cm at 96 px per inch), with
# the command that made it, at that size, after it.
figs = re.findall(r'<img src="(?:doc/)?(pictures/paper/(\w+)\.png)" width="(\d+)"[^>]*>\s*```sh\n(.*?)```',
                  manual(root), re.S)
ok(len(figs) >= 5, f"the page of figures shows {len(figs)} figures, each followed by its command")
for path, name, width, cmd in figs:
    w, h, ppm = png_info(os.path.join(root, "doc", path))
    size = re.search(r"--size (\S+)", cmd)
    cm = [float(x) for x in re.findall(r"([\d.]+)cm", size.group(1))] if size else []
    want_w = round(cm[0] / 2.54 * 300) if cm else -1
    want_h = round(cm[1] / 2.54 * 300) if len(cm) > 1 else None
    ok(int(width) == round(8.6 / 2.54 * 96) and cm and cm[0] == 8.6 and abs(w - want_w) <= 1 and
       (want_h is None or abs(h - want_h) <= 1) and f"-o {name}.pdf" in cmd,
       f"doc/pictures/paper/{name}.png: {w}x{h} px = {size.group(1) if size else '?'} at 300 dpi "
       f"(expected {want_w} wide), shown {width} px (8.6 cm), made by a command writing {name}.pdf")

# ---- refused: exit 2, the option named, nothing written ----
BAD = [
    (["--size", "8.6furlong"], "--size 8.6furlong"),
    (["--size", "8.6"], "--size 8.6"),
    (["--size", "0.5cm"], "--size 0.5cm"),
    (["--size", "8.6cmx"], "--size 8.6cmx"),
    (["--size", "8.6cmx6"], "--size 8.6cmx6"),
    (["--size", "abccm"], "--size abccm"),
    (["--size", "1e9in"], "--size 1e9in"),
    (["--dpi", "300"], "--dpi"),
    (["--size", "8.6cm", "--dpi", "0"], "--dpi 0"),
    (["--size", "8.6cm", "--dpi", "9000"], "--dpi 9000"),
    (["--size", "60in", "--dpi", "600"], "--size"),
]
for args, said in BAD:
    out = p("bad.png")
    r = run("still", scene("default.ini"), "-o", out, "-q", *args)
    ok(r.returncode == 2 and said in r.stderr and not os.path.exists(out),
       f"still {' '.join(args)}: exit {r.returncode}, names '{said}', no file: {r.stderr.strip()}")
r = run("still", scene("default.ini"), "-o", p("bad.pdf"), "-q", "--size", "8.6cm", "--dpi", "300")
ok(r.returncode == 2 and "--dpi" in r.stderr and not os.path.exists(p("bad.pdf")),
   f"--dpi with a PDF is refused: {r.stderr.strip()}")
r = run("render", scene("default.ini"), "-o", p("bad.mp4"), "-q", "--size", "8.6cm")
ok(r.returncode == 2 and "--size" in r.stderr and not os.path.exists(p("bad.mp4")),
   f"render --size 8.6cm is refused: {r.stderr.strip()}")

SWEEP_BAD = [
    (["--set", "view.panels=r"], "view.panels"),
    (["--set", "view.cursor=true"], "view.cursor"),
    (["--set", "view.xlabel=a|b"], "view.xlabel"),
    (["--set", "view.hud=false"], "view.hud"),
    (["--set", "video.fps=30"], "video.fps"),
    (["--set", "ensemble.count=3"], "ensemble.count"),
    (["--size", "8.6"], "--size 8.6"),
    (["--size", "8.6furlong"], "--size 8.6furlong"),
    (["--size", "8.6cm", "--dpi", "300"], "--dpi"),
    (["--dpi", "300"], "--dpi"),
]
for args, said in SWEEP_BAD:
    out = p("bad_sweep.pdf")
    r = run("sweep", scene("chaotic.ini"), *MAP, "-o", out, "-q", *args)
    ok(r.returncode == 2 and said in r.stderr and not os.path.exists(out),
       f"sweep {' '.join(args)}: exit {r.returncode}, names '{said}', no file: {r.stderr.strip()}")

# ---- one axis layout: a sweep figure and a still's chart of the same
# physical size and font_size (axis.h) ----
def axis_marks(svg):
    """(line widths, tick lengths), pt, of what an SVG draws in the light
    theme's axis colour: a stroke's width (cairo's user unit is the pt here),
    a filled axis-aligned rectangle's short side and, when short, its long
    side (a tick)."""
    widths, ticks = [], []
    for style, d in re.findall(r'<path style="([^"]*)" d="([^"]*)"', open(svg).read()):
        if "34.999999%,38%,41.999999%" not in style:
            continue
        nums = [float(v) for v in re.findall(r"-?[\d.]+", d)]
        xs, ys = nums[0::2], nums[1::2]
        m = re.search(r"stroke-width:([\d.]+)", style)
        if m and "stroke:rgb(34.999999%" in style:
            widths.append(float(m.group(1)))
            if len(xs) == 2:
                ticks.append(math.hypot(xs[1] - xs[0], ys[1] - ys[0]))
        elif "fill:rgb(34.999999%" in style and len(xs) in (4, 5):
            w, h = max(xs) - min(xs), max(ys) - min(ys)
            widths.append(min(w, h))
            if max(w, h) < 6:
                ticks.append(max(w, h))
    mode = lambda v: max(set(round(x, 2) for x in v), key=lambda x: sum(round(y, 2) == x for y in v)) if v else None
    return mode(widths), mode(ticks)


def tick_label_pt(pdf):
    """The tick labels' sizes, pt: the words that are numbers."""
    data = open(pdf, "rb").read()
    asc = [int(v) for v in re.findall(rb"/Ascent (-?\d+)", data)]
    desc = [int(v) for v in re.findall(rb"/Descent (-?\d+)", data)]
    em = (asc[0] - desc[0]) / 1000 if asc and desc else 1
    out = subprocess.run(["pdftotext", "-bbox", pdf, "-"], capture_output=True, text=True).stdout
    return sorted({round((float(y1) - float(y0)) / em, 3) for y0, y1, w in re.findall(
        r'<word xMin="[^"]+" yMin="([^"]+)" xMax="[^"]+" yMax="([^"]+)">([^<]*)<', out)
        if re.fullmatch(r"\u2212?[\d.]+", html.unescape(w))})


for fs in ("10", "9", "12"):
    made = all([still(f"ax{fs}.{e}", "chaotic.ini", "--size", "8.6cm", "--set", "view.panels=theta",
                      "--set", "view.pendulum=false", "--set", f"view.font_size={fs}", *PRINT)
                and sweep(f"axsw{fs}.{e}", "chaotic.ini", MAP, "--size", "8.6cm", "--set",
                          f"view.font_size={fs}", "--set", "view.theme=light")
                for e in ("svg", "pdf")])
    st_pt, sw_pt = (tick_label_pt(p(f"{n}.pdf")) if made else [] for n in (f"ax{fs}", f"axsw{fs}"))
    st_m, sw_m = (axis_marks(p(f"{n}.svg")) if made else (None, None) for n in (f"ax{fs}", f"axsw{fs}"))
    want = round(0.85 * float(fs) * 4) / 4  # axis.h: 0.85 of the body, in the still's quarter points
    ok(len(st_pt) == 1 and len(sw_pt) == 1 and abs(st_pt[0] - want) < 0.03 and
       abs(sw_pt[0] - st_pt[0]) < 0.02,
       f"font_size {fs}, 8.6 cm: the still's chart and the sweep figure set their tick labels at one size "
       f"({want} pt): still {st_pt}, sweep {sw_pt} pt")
    ok(st_m[0] == sw_m[0] == 0.8 and st_m[1] == sw_m[1] == 3.5,
       f"font_size {fs}, 8.6 cm: axis lines 0.8 pt and ticks 3.5 pt in both SVGs (still {st_m}, sweep {sw_m})")

done()
