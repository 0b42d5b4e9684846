#!/usr/bin/env python3
"""springpend tests (issue 28): the attacker's seventh pass
(doc/notes/2026-11-27/attack7.md) on axes and sweep figures, and issue 20's
leftovers there, each check run as the attacker ran it:
- finding 15: tick labels of large values were printed in full (20 digits)
  and squeezed the plot; now labels have at most SP_AXIS_MAX_DIGITS (6)
  digits before the point, and the axis's name carries the power of ten
  ("E (×10¹⁹ J)"), in a still and a sweep figure alike; the exponent is
  checked against the scene's spring energy, worked out here;
- finding 21: a printed sweep figure cut its last x tick label at the
  page's edge, and drew its legend over the curves; now every word lies
  on the page, and the legend's box crosses no curve (the curves from the
  CSV, placed on the page through the tick labels' own positions);
- finding 10: a sweep PNG at 11 dpi drew 1-2 px text, exit 0; now refused
  with the least dpi (4 px for the smallest text: 11/14 of font_size);
- finding 5: --vary refused 1e-300:2e-300:3 with a rule ("1e-9 of their
  size") it did not apply; the rule is now relative, and the message says
  the rule applied;
- issue 20's leftovers: sweep legends wrote "-" where tick labels write
  "−" (U+2212), and a sweep figure's axis names were at body size, a
  still's at the tick labels' size (doc/figures.md);
- the eighth pass (doc/notes/2026-11-27/attack8.md), finding 5: a still's
  colour bar at tiny speeds labelled every tick 0.0000000000000000; now
  "2×10⁻¹⁶"; finding 13: a PNG figure too small in pixels was told to
  lower --dpi; now to raise it; and the lead's own find: a round top
  speed put the colour bar's top tick label against its name.
usage: test_attack7_axes.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import csv
import html
import math
import os
import re
import subprocess

import sptest
from sptest import done, err, ok

exe, src, work, _ = sptest.setup("attack7-axes", ["pdftotext"])
run = sptest.runner_bytes(exe, work)
scenes = os.path.join(src, "..", "scenes")
chaotic, default = os.path.join(scenes, "chaotic.ini"), os.path.join(scenes, "default.ini")
SUP = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-")


def path(*names):
    return os.path.join(work, *names)


def words(pdf):
    """[(text, xMin, yMin, xMax, yMax)] of pdftotext -bbox, and the page's
    (width, height), pt."""
    out = subprocess.run(["pdftotext", "-bbox", pdf, "-"], capture_output=True, text=True).stdout
    page = re.search(r'<page width="([^"]+)" height="([^"]+)"', out)
    ws = [(html.unescape(w), float(a), float(b), float(c), float(d)) for a, b, c, d, w in re.findall(
        r'<word xMin="([^"]+)" yMin="([^"]+)" xMax="([^"]+)" yMax="([^"]+)">([^<]*)<', out)]
    return ws, (float(page.group(1)), float(page.group(2))) if page else (0, 0)


def number(w):
    """The value of a tick label ("−0.5", "200000"), or None."""
    return float(w.replace("\u2212", "-")) if re.fullmatch(r"\u2212?\d+(\.\d+)?", w) else None


def power(text):
    """N of the first "×10ᴺ" in text, or None."""
    m = re.search(r"×10([⁻]?[⁰¹²³⁴⁵⁶⁷⁸⁹]+)", text)
    return int(m.group(1).translate(SUP)) if m else None


# ---- finding 15: large values' tick labels -------------------------------------
K, M, R0, L0 = 1e12, 1e6, 10000.0, 0.5  # default.ini's L0; stretched 10 km at 1e12 N/m
big = ["--set", f"pendulum.stiffness={K:g}", "--set", f"pendulum.mass={M:g}", "--set",
       f"initial.length={R0:g}", "--set", "integrator.dt=1e-5", "--set", "video.duration=0.5"]
r = run("still", default, "--at", "0.3", "--size", "640x360", "--set", "view.panels=energy", *big,
        "--set", "view.hud=false", "-o", "big.pdf", "-q")
ws, _ = words(path("big.pdf")) if r.returncode == 0 else ([], (0, 0))
labels = [w for w, *_ in ws if number(w) is not None]
text = " ".join(w for w, *_ in ws)
# the spring's energy at the start, ½ k (r0 − L0)², is the chart's largest
want = math.floor(math.log10(0.5 * K * (R0 - L0) ** 2))
ok(r.returncode == 0 and labels and max(len(w) for w in labels) <= 7 and power(text) == want and
   "E (×10" in text,
   f"still, energy of 5e19 J: tick labels of at most 6 digits ({sorted(set(labels), key=len)[-3:]}), "
   f"the axis named with ×10^{want} (got {power(text)})")

grid = ["--vary", "pendulum.mass=1e5:1e6:4", "--measure", "lyapunov", "--time", "2"]
r = run("sweep", chaotic, *grid, "--size", "3in", "-o", "mass.pdf", "--csv", "mass.csv", "-q")
ws, page = words(path("mass.pdf")) if r.returncode == 0 else ([], (0, 0))
labels = [w for w, *_ in ws if number(w) is not None]
text = " ".join(w for w, *_ in ws)
ok(r.returncode == 0 and labels and max(len(w) for w in labels) <= 7 and power(text) == 6 and
   "pendulum.mass (×10" in text,
   f"sweep over mass 1e5..1e6 kg: x labels short ({labels}), the axis named with ×10^6 "
   f"({power(text)})")


# ---- finding 21: the last x label on the page; the legend clear of the curves --
def on_page(pdf):
    ws, (pw, ph) = words(path(pdf))
    out = [(w, round(x0, 1), round(x1, 1)) for w, x0, _, x1, _ in ws if x0 < 0 or x1 > pw + 0.01]
    return ws, pw, out


for name, g in (("m4.pdf", ["--vary", "pendulum.mass=1e4:4e5:4"]),
                ("mass.pdf", None)):
    if g:
        r = run("sweep", chaotic, *g, "--measure", "lyapunov", "--time", "2", "--size", "3in", "-o",
                name, "--csv", name + ".csv", "-q")
        if r.returncode:
            ok(False, f"sweep {g}: {err(r)}")
            continue
    ws, pw, out = on_page(name)
    ok(ws and not out, f"{name}: every word within the {pw:g} pt page (beyond it: {out})")


def legend_crossings(pdf, csv_name, key, series):
    """Segments of the CSV's curves that pass through the legend's box, the
    curves put on the page through the tick labels' positions (the x labels'
    centres, the y labels' vertical centres)."""
    ws, _ = words(path(pdf))
    nums = [(number(w), (x0 + x1) / 2, (y0 + y1) / 2, x1) for w, x0, y0, x1, y1 in ws
            if number(w) is not None]
    if not nums:
        return None
    base = max(y for _, _, y, _ in nums)  # the x labels: the lowest row of numbers
    xs = [(v, x) for v, x, y, _ in nums if abs(y - base) < 1]
    right = min(x1 for _, _, y, x1 in nums if abs(y - base) >= 1)  # the y labels' column
    ys = [(v, y) for v, x, y, x1 in nums if abs(y - base) >= 1 and abs(x1 - right) < 30]
    text = " ".join(w for w, *_ in ws)
    scale = 10 ** (power(text) or 0)
    if len(xs) < 2 or len(ys) < 2:
        return None
    (xa, pa), (xb, pb) = xs[0], xs[-1]
    (ya, qa), (yb, qb) = ys[0], ys[-1]
    fx = lambda v: pa + (v / scale - xa) * (pb - pa) / (xb - xa)
    fy = lambda v: qa + (v - ya) * (qb - qa) / (yb - ya)
    rows_y = {round(b[2], 1) for b in ws if b[0] == "over"}  # the legend's lines
    legend = [b for b in ws if round(b[2], 1) in rows_y]
    if not legend:
        return None
    box = (min(b[1] for b in legend), min(b[2] for b in legend), max(b[3] for b in legend),
           max(b[4] for b in legend))
    rows = list(csv.DictReader(open(path(csv_name))))
    hits = 0
    for s in series:
        pts = [(fx(float(row[key])), fy(float(row[s]))) for row in rows]
        for (ax, ay), (bx, by) in zip(pts, pts[1:]):
            for k in range(101):  # the segment sampled every 1 %
                x, y = ax + (bx - ax) * k / 100, ay + (by - ay) * k / 100
                hits += box[0] <= x <= box[2] and box[1] <= y <= box[3]
    return hits


for pdf, csvn in (("mass.pdf", "mass.csv"), ("m4.pdf", "m4.pdf.csv")):
    h = legend_crossings(pdf, csvn, "pendulum.mass", ["lyapunov", "lyapunov_half"]) \
        if os.path.exists(path(csvn)) else None
    ok(h == 0, f"{pdf}: the legend's words lie where no curve passes ({h} points of the curves "
       "inside its box)")

# ---- finding 10: a PNG whose text would be 1 px --------------------------------
small = 11 / 14 * 10  # pt: the smallest text (the basins' legend) at font_size 10
least = math.ceil(4 * 72 / small)
g = ["--vary", "initial.angle=1:179:4", "--measure", "lyapunov", "--time", "2", "--size", "8.6cm"]
r = run("sweep", chaotic, *g, "--dpi", "11", "-o", "tiny.png")
ok(r.returncode == 2 and not os.path.exists(path("tiny.png")) and f"--dpi {least} or more" in err(r)
   and "4 px" in err(r),
   f"sweep --size 8.6cm --dpi 11: refused, naming --dpi {least} (exit {r.returncode}: {err(r)})")
# attack8.md finding 5: the still's colour bar at a speed of 5e-16 m/s labelled
# every tick 0.0000000000000000 across the next panel; its ticks (a round
# step under the top speed, v = omega * r) are now written with a power of ten
vmax = 1e-15 * 0.5   # initial.angle_rate (rad/s) times initial.length (m), gravity 0
# two panels: default.ini's four cannot hold their legends at 8.6 cm (refused: attack13 #19)
r = run("still", default, "--at", "3", "--size", "8.6cm", "--set", "view.colorbar=true", "--set", "view.panels=r,theta",
        "--set", "pendulum.gravity=0", "--set", "initial.angle=0", "--set", "initial.angle_rate=1e-15",
        "--set", "initial.length=0.5", "-o", "cbt.pdf", "-q")
bar = subprocess.run(["pdftotext", "-layout", path("cbt.pdf"), "-"], capture_output=True,
                     text=True).stdout if r.returncode == 0 else ""
e = math.floor(math.log10(vmax))
sup = str(e).replace("-", "⁻").translate(str.maketrans("0123456789", "⁰¹²³⁴⁵⁶⁷⁸⁹"))
ok(r.returncode == 0 and "0.0000000" not in bar and f"×10{sup}" in bar,
   f"a colour bar up to {vmax:g} m/s: ticks in units of 10^{e} (×10{sup}), no run of zeros "
   f"(exit {r.returncode}: {err(r)}; {[w for w in bar.split() if '10' in w or '0.00' in w][:6]})")

# a round top speed put the colour bar's top tick label against the bar's
# name "|v| (m/s)" (their boxes overlapped by 3.8 pt); a pure bounce from
# the rest length l = L0 + m g / k at speed v tops out at exactly v
for v in (1, 2, 5, 10):
    r = run("still", default, "--at", "8", "--size", "960x540", "--set", "view.colorbar=true",
            "--set", "initial.angle=0", "--set", "initial.length=2.9525",
            "--set", f"initial.length_rate={v}", "-o", "cbround.pdf", "-q")
    ws, _ = words(path("cbround.pdf")) if r.returncode == 0 else ([], None)
    name = next((w for w in ws if w[0] == "(m/s)"), None)
    bar = next((w for w in ws if w[0] == "|v|"), None)  # the name starts at the bar's left
    below = sorted((w for w in ws if name and bar and number(w[0]) is not None and
                    bar[1] <= w[1] <= name[3] and w[2] > name[2]), key=lambda w: w[2])
    top = below[0] if below else None
    ok(top is not None and number(top[0]) == v and top[2] >= name[4] - 1e-3,
       f"colour bar up to {v} m/s: the top tick label {top and top[0]!r} starts at y "
       f"{top and top[2]} pt, below the name's bottom {name and name[4]} pt ({err(r)})")

# attack8.md finding 13: a PNG too small in pixels was told to "lower --dpi"
r = run("sweep", chaotic, "--vary", "initial.angle=1:179:4", "--measure", "lyapunov", "--time", "2",
        "--size", "1in", "--dpi", "11", "-o", "few.png")
ok(r.returncode == 2 and b"raise --dpi or the size" in r.stderr and not os.path.exists(path("few.png")),
   f"--size 1in --dpi 11 (11x7 px): refused, saying to raise --dpi or the size (exit {r.returncode}: "
   f"{err(r)})")
r1 = run("sweep", chaotic, *g, "--dpi", str(least), "-o", "least.png", "-q")
r2 = run("sweep", chaotic, *g, "--dpi", str(least - 1), "-o", "below.png", "-q")
ok(r1.returncode == 0 and os.path.exists(path("least.png")) and r2.returncode == 2 and
   not os.path.exists(path("below.png")),
   f"--dpi {least} draws it, --dpi {least - 1} is refused (exit {r1.returncode}, {r2.returncode})")

# ---- finding 5: --vary's rule, relative ---------------------------------------
r = run("sweep", chaotic, "--vary", "initial.angle=1e-300:2e-300:3", "--measure", "lyapunov",
        "--time", "2", "-o", "t300.pdf", "--csv", "t300.csv", "-q")
vals = [float(row["initial.angle"]) for row in csv.DictReader(open(path("t300.csv")))] \
    if r.returncode == 0 else []
ws, _ = words(path("t300.pdf")) if r.returncode == 0 else ([], (0, 0))
text = " ".join(w for w, *_ in ws)
ok(r.returncode == 0 and vals == [1e-300, 1.5e-300, 2e-300] and power(text) == -300,
   f"--vary initial.angle=1e-300:2e-300:3 (50% apart): swept {vals}, the axis in ×10^-300 "
   f"({power(text)}) (exit {r.returncode}: {err(r)[-200:]})")
r = run("sweep", chaotic, "--vary", "initial.angle=1:1.000000001:3", "--measure", "lyapunov",
        "--time", "2", "-o", "close.pdf")
ok(r.returncode == 2 and "1e-9 of the larger of |FROM| and |TO|" in err(r) and
   not os.path.exists(path("close.pdf")),
   f"--vary initial.angle=1:1.000000001:3 (steps of 5e-10 of the value): refused, stating the "
   f"rule applied: {err(r)}")

# ---- issue 20's leftovers: minus signs and the axis names' size ----------------
r = run("sweep", chaotic, "--vary", "initial.angle=120:120:1", "--measure", "spectrum", "--time",
        "20", "-o", "spec.pdf", "-q")
t = subprocess.run(["pdftotext", path("spec.pdf"), "-"], capture_output=True,
                   text=True).stdout if r.returncode == 0 else ""
neg = [ln for ln in t.splitlines() if re.search(r"λ\d = \u2212", ln)]
ok(r.returncode == 0 and len(neg) >= 1 and not re.search(r"(^|[ =(])-\d", t),
   f"the spectrum's legend writes −, never '-' before a number: {[ln for ln in t.splitlines() if 'λ' in ln or 'sum' in ln]}")


def sizes(pdf, name_words):
    """(the tick labels' heights, the axis names' words' heights), pt, of pdftotext -bbox."""
    ws, _ = words(path(pdf))
    ticks = {round(y1 - y0, 2) for w, _, y0, _, y1 in ws if number(w) is not None}
    names = {round(y1 - y0, 2) for w, _, y0, _, y1 in ws if w in name_words}
    return ticks, names


r = run("sweep", chaotic, *g, "-o", "names.pdf", "-q")
st = run("still", chaotic, "--at", "30", "--size", "8.6cm", "--set", "view.panels=theta", "--set",
         "view.pendulum=false", "--set", "view.hud=false", "--set", "view.colorbar=false", "-o",
         "still.pdf", "-q")
sw_t, sw_n = sizes("names.pdf", {"initial.angle"}) if r.returncode == 0 else (set(), set())
st_t, st_n = sizes("still.pdf", {"t"}) if st.returncode == 0 else (set(), set())
same = lambda a, b: len(a) == 1 and len(b) == 1 and abs(min(a) - min(b)) < 0.02
ok(same(sw_t, sw_n) and same(st_t, st_n) and same(sw_t, st_t),
   f"8.6 cm: the sweep figure's axis name at its tick labels' size, as the still's "
   f"(sweep: ticks {sw_t}, name {sw_n}; still: ticks {st_t}, name {st_n})")

done()
