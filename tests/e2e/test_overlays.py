#!/usr/bin/env python3
"""springpend tests: [view] vectors and the energy_bars panel (issue 22).
Arrows from the bob against
the forces computed here with numpy from the state `data` writes (gravity
-m g, spring -k (r - L0) along the spring, damping -b v_air, the drive's
inertial force -m a_pivot, net their sum; velocity; acceleration net / m),
each alone in a 1920x1080 still: the arrow's tip, found by its colour, lies
where the scale stated in the PNG's springpend.overlay text puts it, to a
pixel (direction and length; the tip is where the arrow's coverage reaches
farthest along its axis). An unknown vector name is refused
with FILE:LINE and exit 2; a scene without vectors has no overlay text.
Side by side (2 to 4 scenes): in every cell the bob's centre, found by its
colour, lies r * px_per_m from the pivot, one px_per_m for all cells, with r
from data; the charts' tick labels sit at the same heights in every cell
(PDF text positions), the cells' labels name the differing key and a shorter
scene says it ended; data writes each scene's rows with a scene column; 5
scenes and a missing file are refused with exit 2 and no output.
Energy bars: each bar's height in the PNG against the energies computed
here from data's states (kinetic, spring, gravity from the lowest point of
the run, total, start, the drive's work, the loss to damping integrated
here by the trapezoid rule, bounce, swing), to 1.5 px, on one axis at every
time.
usage: test_overlays.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import csv
import io
import math
import os
import shutil
import subprocess

from sptest import done, ffmpeg_rgb, need_scipy, ok, png_overlay, png_text, setup

exe, src, work, run = setup("overlays", ["ffmpeg"])
need_scipy()
import numpy as np  # noqa: E402
from scipy import ndimage  # noqa: E402

L0, K, M, G, B, A, F = 0.5, 2.0, 0.5, 9.81, 0.15, 0.15, 0.9
scene = os.path.join(work, "teach.ini")
with open(scene, "w") as fp:
    fp.write(f"[pendulum]\nnatural_length = {L0}\nstiffness = {K}\nmass = {M}\ngravity = {G}\n"
             f"damping = {B}\n[initial]\nangle = 50\nlength = 2.0\n[pivot]\namplitude = {A}\n"
             f"frequency = {F}\n[view]\ntrail = 0\n")
W, H = 1920, 1080
# the theme's arrow colours (panels.c), by name
COLOURS = {"velocity": (64, 217, 242), "acceleration": (255, 204, 38), "gravity": (102, 140, 255),
           "spring": (89, 230, 102), "damping": (204, 128, 255), "drive": (255, 102, 191),
           "net": (255, 255, 255)}


def pixels(path):
    return ffmpeg_rgb(path, W, H)


overlay = png_overlay


def state_at(t):
    r = run("data", scene, "-o", "-", "--every", str(t), "--set", f"video.duration={t}")
    rows = list(csv.DictReader(io.StringIO(r.stdout)))
    return {k: float(v) for k, v in rows[-1].items()}


def expected(name, s):
    """The vector, SI, y up, computed from the state alone."""
    x, y, vx, vy, t = s["x"], s["y"], s["vx"], s["vy"], s["t"]
    w = 2 * math.pi * F
    vp, ap = A * w * math.cos(w * t), -A * w * w * math.sin(w * t)
    rho = math.hypot(x, y)
    spring = -K * (rho - L0) * np.array([x, y]) / rho
    gravity = np.array([0.0, -M * G])
    damping = -B * np.array([vx, vy + vp])
    drive = np.array([0.0, -M * ap])
    net = spring + gravity + damping + drive
    return {"velocity": np.array([vx, vy]), "acceleration": net / M, "gravity": gravity,
            "spring": spring, "damping": damping, "drive": drive, "net": net}[name]


QUANTITY = {"velocity": "velocity", "acceleration": "acceleration"}
T = 2.1
s = state_at(T)
ok(abs(s["t"] - T) < 1e-9, f"data's row at t = {T}")
worst = 0.0
for name, colour in COLOURS.items():
    out = os.path.join(work, f"{name}.png")
    r = run("still", scene, "--at", str(T), "--size", f"{W}x{H}", "-q", "-o", out,
            "--set", f"view.vectors={name}")
    if not ok(r.returncode == 0, f"still with vectors = {name}"):
        print("# " + r.stderr.strip())
        continue
    o = overlay(out)
    q = QUANTITY.get(name, "force")
    scale = float(o[f"vectors.{q}.px_per_unit"])
    px_m = float(o["camera.px_per_m"])
    ox, oy = map(float, o["camera.origin_px"].split(","))
    yp = s["pivot_y"]
    centre = np.array([ox + px_m * s["x"], oy - px_m * (s["y"] + yp)])
    vec = expected(name, s)
    tip = centre + scale * np.array([vec[0], -vec[1]])
    img = pixels(out)
    mask = (np.abs(img - np.array(colour)).max(axis=2) <= 40)
    labels, n = ndimage.label(mask)
    ys, xs = np.nonzero(mask)
    if not ok(len(xs) > 0, f"{name}: arrow pixels of its colour found"):
        continue
    pc = np.stack([xs + 0.5, ys + 0.5], axis=1)
    near = np.argmin(np.hypot(*(pc - centre).T))
    comp = labels[ys[near], xs[near]]
    # the arrow's pixels with their coverage (0..1, from the blend between
    # the background and the arrow's colour), antialiased edges included
    grown = ndimage.binary_dilation(labels == comp, iterations=2)
    gy, gx = np.nonzero(grown)
    bg = np.median(img[~grown][::97], axis=0)
    col_ = np.array(colour, float)
    cover = np.clip((img[gy, gx] - bg) @ (col_ - bg) / ((col_ - bg) @ (col_ - bg)), 0, 1)
    # only blends of the background and the arrow's colour (not the spring's coil)
    cover[np.hypot.reduce(img[gy, gx] - (bg + cover[:, None] * (col_ - bg)), axis=1) > 24] = 0
    far_mask = np.hypot(gx + 0.5 - centre[0], gy + 0.5 - centre[1]) > 6  # off the bob's centre
    gp = np.stack([gx + 0.5, gy + 0.5], axis=1)[far_mask]
    wgt = cover[far_mask]
    # the axis: the arrow is symmetric about it (shaft and two barbs), so its
    # direction is the coverage-weighted principal direction of the pixels
    # about the bob's centre, and the tip is the farthest coverage reaches
    rel = gp - centre
    mean_dir = (wgt[:, None] * rel).sum(axis=0)
    u = mean_dir / np.hypot(*mean_dir)
    normal = np.array([-u[1], u[0]])
    lateral = (wgt * (rel @ normal)).sum() / wgt.sum()
    along = rel @ u
    on_axis = np.abs(rel @ normal - lateral) < 1.0
    reach = (along + cover[far_mask] - 0.5)[on_axis & (wgt > 0.05)].max()
    far = centre + reach * u + lateral * normal
    err = float(np.hypot(*(far - tip)))
    length = float(np.hypot(*(tip - centre)))
    worst = max(worst, err)
    ang = math.degrees(math.atan2(-(far - centre)[1], (far - centre)[0]) - math.atan2(vec[1], vec[0]))
    ang = (ang + 180) % 360 - 180
    ok(err <= 1.0, f"{name}: tip at ({far[0]:.1f}, {far[1]:.1f}) px, expected ({tip[0]:.1f}, {tip[1]:.1f}) "
       f"for |{name}| = {np.hypot(*vec):.4g} at {scale:.4g} px per unit ({length:.0f} px long): "
       f"{err:.2f} px off, direction {ang:+.2f} degrees off")
    ok(o.get(f"vectors.{q}.key", "").split(" ")[0].replace(".", "").isdigit(),
       f"{name}: the key states a value ({o.get(f'vectors.{q}.key')})")
print(f"# worst tip error {worst:.2f} px")

# one scale for the whole video: the same at two times
a, b = os.path.join(work, "a.png"), os.path.join(work, "b.png")
for path, t in ((a, "0.5"), (b, "6")):
    run("still", scene, "--at", t, "--size", f"{W}x{H}", "-q", "-o", path, "--set", "view.vectors=forces,velocity")
oa, ob = overlay(a), overlay(b)
ok(oa and all(oa[k] == ob[k] for k in oa if k.startswith("vectors.")),
   "the arrow scales are the same at t = 0.5 s and t = 6 s (chosen from the whole run)")

# bad input: FILE:LINE, exit 2, no file
bad = os.path.join(work, "bad.ini")
with open(bad, "w") as fp:
    fp.write("[view]\nvectors = velocity, froce\n")
r = run("still", bad, "-o", os.path.join(work, "bad.png"))
ok(r.returncode == 2 and f"{bad}:2:" in r.stderr and "'froce' is not a vector" in r.stderr
   and not os.path.exists(os.path.join(work, "bad.png")), f"unknown vector: {r.stderr.strip()}")

# without vectors: no overlay chunk, no vectors key in the scene text
plain = os.path.join(work, "plain.png")
run("still", scene, "--at", "1", "--size", "320x180", "-q", "-o", plain)
t = png_text(plain)
ok("springpend.overlay" not in t, "a still without vectors carries no overlay text")

# ---- energy bars ----
r = run("data", scene, "-o", "-", "--every", "0.001")
rows = list(csv.DictReader(io.StringIO(r.stdout)))
d = {k: np.array([float(row[k]) for row in rows]) for k in rows[0]}
y_low = d["y"].min()
Tb = 4.0
i = int(np.argmin(np.abs(d["t"] - Tb)))
ok(abs(d["t"][i] - Tb) < 1e-9, f"data's row at t = {Tb}")
w = 2 * math.pi * F
vy_air = d["vy"] + A * w * np.cos(w * d["t"])
power = B * (d["vx"] ** 2 + vy_air ** 2)
loss = float(np.sum(0.5 * (power[1:i + 1] + power[:i]) * np.diff(d["t"][:i + 1])))


def energies(j, zero_y):
    x, y, vx, vy = d["x"][j], d["y"][j], d["vx"][j], d["vy"][j]
    r_ = math.hypot(x, y)
    ell = L0 + M * G / K
    rdot = (x * vx + y * vy) / r_
    thdot = (x * vy - y * vx) / r_ ** 2
    kin, spr, grav = 0.5 * M * (vx * vx + vy * vy), 0.5 * K * (r_ - L0) ** 2, M * G * (y - zero_y)
    return kin, spr, grav, kin + spr + grav, (0.5 * M * rdot ** 2 + 0.5 * K * (r_ - ell) ** 2,
                                               0.5 * M * r_ * r_ * thdot ** 2 + M * G * (r_ + y))


bars = {}
for t_ in (str(Tb), "7.5"):
    path = os.path.join(work, f"bars{t_}.png")
    r = run("still", scene, "--at", t_, "--size", f"{W}x{H}", "-q", "-o", path,
            "--set", "view.panels=energy_bars")
    ok(r.returncode == 0, f"still with the energy_bars panel at t = {t_}") or print("# " + r.stderr)
    bars[t_] = (path, overlay(path))
path, o = bars[str(Tb)]
ok(all(bars[str(Tb)][1][k] == bars["7.5"][1][k] for k in ("energy_bars.zero_px", "energy_bars.px_per_J")),
   "the bars' axis is the same at t = 4 s and 7.5 s (one axis for the whole video)")
zero_y = float(o["energy_bars.gravity_zero_y_m"])
ok(abs(zero_y - y_low) < 1e-3, f"gravity's zero: the lowest point, y = {zero_y:.5f} m (data every 1 ms: {y_low:.5f})")
kin, spr, grav, tot, (bnc, swg) = energies(i, zero_y)
start = energies(0, zero_y)[3]
work_total = d["work"][i]
expect = {"kinetic": kin, "spring": spr, "gravity": grav, "total": tot, "start": start,
          "drive work": work_total + loss, "damping loss": loss, "bounce": bnc, "swing": swg}
ok(abs(tot - (start + work_total)) < 1e-6 * max(1, abs(tot)), f"data: total = start + work ({tot:.6f} J)")
ok(int(o["energy_bars.count"]) == len(expect), f"{o['energy_bars.count']} bars for a damped, driven scene")
img = pixels(path)
zero, ppj = float(o["energy_bars.zero_px"]), float(o["energy_bars.px_per_J"])
slot, x0 = float(o["energy_bars.slot_px"]), float(o["energy_bars.x0_px"])
panel = np.array([26, 32, 41])
for k, (name, value) in enumerate(expect.items()):
    col = img[:, int(x0 + (k + 0.5) * slot)]
    colour = col[int(round(zero - value * ppj / 2))] if abs(value * ppj) > 4 else None
    want = value * ppj
    if colour is None:
        ok(True, f"{name}: {value:.4f} J is {want:.2f} px, too short to measure")
        continue
    rows_ = np.nonzero(np.abs(col - colour).max(axis=1) <= 12)[0]
    rows_ = rows_[np.abs(rows_ + 0.5 - zero) <= abs(want) + 4]
    got = zero - rows_.min() if value > 0 else rows_.max() + 1 - zero
    got = got if value > 0 else -got
    ok(abs(got - want) <= 1.5, f"{name}: bar {got:.1f} px, expected {want:.1f} px ({value:.4f} J at {ppj:.4g} px/J)")

# the energy chart takes gravity's zero where the bars do (the lowest point of
# the run), stated in both: in an undamped scene the chart's total is a flat
# line at the total bar's value, both data's energy less m g y_low
dflt = os.path.join(src, "..", "scenes", "default.ini")
r = run("data", dflt, "-o", "-", "--every", "0.001")
rows = list(csv.DictReader(io.StringIO(r.stdout)))
dd = {k: np.array([float(row[k]) for row in rows]) for k in ("t", "x", "y", "vx", "vy")}
m_, k_, l0_, g_ = 0.5, 2.0, 0.5, 9.81  # scenes/default.ini
e_tot = (0.5 * m_ * (dd["vx"] ** 2 + dd["vy"] ** 2) + 0.5 * k_ * (np.hypot(dd["x"], dd["y"]) - l0_) ** 2
         + m_ * g_ * (dd["y"] - dd["y"].min()))
path = os.path.join(work, "energy-chart.png")
r = run("still", dflt, "--at", "6", "--size", f"{W}x{H}", "-q", "-o", path,
        "--set", "view.panels=energy,energy_bars", "--set", "view.hud=false")
o = overlay(path)
ok(r.returncode == 0 and "energy.zero_px" in o, "the energy chart states its scale beside the bars'")
if "energy.zero_px" in o:
    ok(o["energy.gravity_zero_y_m"] == o["energy_bars.gravity_zero_y_m"] and
       abs(float(o["energy.gravity_zero_y_m"]) - dd["y"].min()) < 1e-3,
       f"one gravity zero for the chart and the bars: y = {o['energy.gravity_zero_y_m']} m "
       f"(data's lowest y {dd['y'].min():.5f})")
    img = pixels(path)
    zb, pb_ = float(o["energy_bars.zero_px"]), float(o["energy_bars.px_per_J"])
    bx = int(float(o["energy_bars.x0_px"]) + 3.5 * float(o["energy_bars.slot_px"]))
    total_rgb = img[int(zb - 0.5 * e_tot.mean() * pb_), bx]   # the total bar's colour
    zc, pc_ = float(o["energy.zero_px"]), float(o["energy.px_per_J"])
    mask = np.abs(img - total_rgb).max(axis=2) <= 12
    mask[int(zc) + 2:] = False                                   # the chart only, above the bars
    counts = mask.sum(axis=1)
    line = np.nonzero(counts >= 0.5 * counts.max())[0] if counts.max() > 200 else np.array([])
    want = zc - e_tot.mean() * pc_
    got = line.mean() + 0.5 if len(line) else float("nan")
    ok(len(line) and abs(got - want) <= 1.0 and np.ptp(e_tot) < 1e-6,
       f"the chart's total: a flat line at y = {got:.2f} px, expected {want:.2f} px "
       f"({e_tot.mean():.4f} J from the lowest point at {pc_:.4g} px/J)")
    below = int(zc) + 2
    bar_top = zb - below - np.nonzero(np.abs(img[below:, bx] - total_rgb).max(axis=1) <= 12)[0].min()
    ok(abs(bar_top - e_tot.mean() * pb_) <= 1.0, f"the total bar: {bar_top:.1f} px for the same "
       f"{e_tot.mean():.4f} J ({e_tot.mean() * pb_:.1f} px expected)")

# panel_background = none: a transparent still's panels are transparent too
for pb, alpha in (("theme", 255), ("none", 0)):
    path = os.path.join(work, f"pb-{pb}.png")
    r = run("still", scene, "--at", "2", "--size", f"{W}x{H}", "-q", "-o", path, "--set", "view.panels=energy_bars",
            "--set", "view.background=transparent", "--set", f"view.panel_background={pb}")
    o = overlay(path)
    raw = subprocess.run(["ffmpeg", "-v", "error", "-i", path, "-f", "rawvideo", "-pix_fmt", "rgba", "-"],
                         capture_output=True).stdout
    rgba = np.frombuffer(raw, np.uint8).reshape(H, W, 4) if len(raw) == W * H * 4 else None
    # between the first two bars, just above the zero line: the panel itself
    x = int(float(o.get("energy_bars.x0_px", "0")) + float(o.get("energy_bars.slot_px", "0")))
    y = int(float(o.get("energy_bars.zero_px", "0")) - 4)
    got = int(rgba[y, x, 3]) if rgba is not None else -1
    ok(r.returncode == 0 and got == alpha, f"view.panel_background = {pb} on a transparent background: "
       f"the panel's alpha is {got} (expected {alpha})")

# ---- side by side ----
def write(name, text):
    path = os.path.join(work, name)
    with open(path, "w") as fp:
        fp.write(text)
    return path


base = "[initial]\nangle = 30\nlength = 1.2\n[view]\ntrail = 0\n"
sa = write("soft.ini", "[pendulum]\nstiffness = 2\n" + base)
sb = write("stiff.ini", "[pendulum]\nstiffness = 6\n" + base)
sc = write("short.ini", "[pendulum]\nstiffness = 12\n[video]\nduration = 3\n" + base)
Ts = 4.0
out = os.path.join(work, "sbs.png")
r = run("still", sa, sb, sc, "--at", str(Ts), "--size", f"{W}x{H}", "-q", "-o", out)
ok(r.returncode == 0, f"still with three scenes side by side {r.stderr.strip()}")
o = overlay(out)
scales = [float(o.get(f"cell{i}.camera.px_per_m", "nan")) for i in (1, 2, 3)]
ok(len(set(scales)) == 1 and not math.isnan(scales[0]), f"one camera scale in every cell: {scales} px/m")
img = pixels(out)
# the bob (palette.bob, a shaded ball from a dark rim to a light highlight):
# red-dominated pixels; its centre is the middle of their extent
reddish = (img[..., 0] > 60) & (img[..., 0] > 1.6 * img[..., 1]) & (img[..., 0] > 1.6 * img[..., 2])
for i, (path, t_cell) in enumerate(((sa, Ts), (sb, Ts), (sc, 3.0 - 1 / 60)), start=1):
    rr = run("data", path, "-o", "-", "--every", "0.001")
    rows_ = list(csv.DictReader(io.StringIO(rr.stdout)))
    row = min(rows_, key=lambda q: abs(float(q["t"]) - t_cell))
    rlen = float(row["r"])
    ox, oy = map(float, o[f"cell{i}.camera.origin_px"].split(","))
    x0, x1 = (i - 1) * W // 3, i * W // 3
    ys, xs = np.nonzero(reddish[:, x0:x1])
    centre = (np.array([0.5 * (xs.min() + xs.max()) + x0 + 0.5, 0.5 * (ys.min() + ys.max()) + 0.5])
              if len(xs) else np.array([math.nan] * 2))
    got = float(np.hypot(*(centre - np.array([ox, oy]))))
    want = rlen * scales[0]
    ok(abs(got - want) <= 1.5, f"cell {i}: pivot to bob {got:.1f} px, r = {rlen:.4f} m at "
       f"{scales[0]:.3f} px/m is {want:.1f} px")

# the pendulums keep a sensible share of a side by side frame: with arrows and
# two panels at 1080p, each cell's camera scale is at least half of what the
# scene alone gets in the same frame (before, the arrows' room took the
# whole view and the bob sat on the pivot at 0.19 px/m)
dflt_dir = os.path.join(src, "..", "scenes")
teach = ("--at", "4.2", "--set", "view.panels=r,energy_bars", "--set", "view.vectors=forces",
         "--set", "view.colorbar=false", "--size", f"{W}x{H}", "-q")
alone, pair = os.path.join(work, "alone.png"), os.path.join(work, "pair.png")
run("still", os.path.join(dflt_dir, "default.ini"), *teach, "-o", alone)
r = run("still", os.path.join(dflt_dir, "default.ini"), os.path.join(dflt_dir, "stiff.ini"), *teach, "-o", pair)
s_alone = float(overlay(alone).get("camera.px_per_m", "nan"))
op = overlay(pair)
s_pair = [float(op.get(f"cell{i}.camera.px_per_m", "nan")) for i in (1, 2)]
ok(r.returncode == 0 and min(s_pair) >= 0.5 * s_alone,
   f"side by side at 1080p with arrows and two panels: {s_pair[0]:.1f} px/m in each cell, "
   f"the scene alone {s_alone:.1f} px/m (at least half asked)")
f_pair = [float(op.get(f"cell{i}.vectors.force.px_per_unit", "nan")) for i in (1, 2)]
ok(f_pair[0] == f_pair[1] and f_pair[0] > 0, f"one arrow scale in both cells: {f_pair} px/N")

# labels, ended marker and shared axes: the PDF keeps its text and where it is
pdf = os.path.join(work, "sbs.pdf")
r = run("still", sa, sb, sc, "--at", str(Ts), "--size", f"{W}x{H}", "-q", "-o", pdf,
        "--set", "view.panels=r", "--set", "view.hud=true")
if shutil.which("pdftotext") and ok(r.returncode == 0, "the same side by side as PDF, with a chart"):
    txt = subprocess.run(["pdftotext", pdf, "-"], capture_output=True, text=True).stdout
    ok(all(f"stiffness = {k}" in txt for k in (2, 6, 12)),
       "each cell is labelled with the key in which the scenes differ (stiffness = 2, 6, 12)")
    ok("ended at t = 2.98 s" in txt, "the shorter scene holds its last frame, marked as ended")
    ok(all(f"differs: stiffness = {k}" in txt for k in (2, 6, 12)),
       "each cell's HUD lists the key in which it differs, with its value")
    bbox = subprocess.run(["pdftotext", "-bbox", pdf, "-"], capture_output=True, text=True).stdout
    import re
    # the y tick labels: the largest column of numbers right-aligned at one x
    columns = {1: {}, 2: {}, 3: {}}
    for m_ in re.finditer(r'<word xMin="([\d.]+)" yMin="([\d.]+)" xMax="([\d.]+)" yMax="[\d.]+">([^<]*)</word>', bbox):
        x, y, x1, word = float(m_.group(1)), float(m_.group(2)), float(m_.group(3)), m_.group(4)
        cell = int(x // (W / 3)) + 1
        if re.fullmatch(r"[\d.]+", word):
            columns[cell].setdefault(round(x1 - (cell - 1) * W / 3), set()).add((word, round(y, 1)))
    ticks = {c: max(cols.values(), key=len) if cols else set() for c, cols in columns.items()}
    ok(ticks[1] and ticks[1] == ticks[2] == ticks[3],
       f"the r charts' y axes are the same in every cell: {sorted(ticks[1])}")

# with titles the labels are the titles, and the HUD still says what differs
pdf2 = os.path.join(work, "sbs-titled.pdf")
r = run("still", sa, sb, "--at", "1", "--size", f"{W}x{H}", "-q", "-o", pdf2, "--set", "view.title=Compare",
        "--set", "view.panels=none", "--set", "view.hud=true")
if shutil.which("pdftotext") and ok(r.returncode == 0, "two titled scenes side by side as PDF"):
    txt = subprocess.run(["pdftotext", pdf2, "-"], capture_output=True, text=True).stdout
    ok(txt.count("Compare") == 2 and "differs: stiffness = 2" in txt and "differs: stiffness = 6" in txt,
       "titled cells: the HUD lists the differing key and value in each cell")

# an optional [view] style key set in one scene only (it shifts the lines of
# the scene's canonical text) must not make equal keys look different: the
# cells' lists are matched by key (before, both listed the [ensemble]
# defaults "count = 0, key = initial.angle ..." as differences)
sd = write("stiff-labelled.ini", "[pendulum]\nstiffness = 6\n" + base.replace("[view]\n", "[view]\npanel_labels = a\n"))
pdf3 = os.path.join(work, "sbs-style.pdf")
r = run("still", sa, sd, "--at", "1", "--size", f"{W}x{H}", "-q", "-o", pdf3,
        "--set", "view.panels=none", "--set", "view.hud=true")
if shutil.which("pdftotext") and ok(r.returncode == 0, "two scenes, one with a [view] style key, side by side"):
    txt = subprocess.run(["pdftotext", pdf3, "-"], capture_output=True, text=True).stdout
    ok("differs: stiffness = 2" in txt and "differs: stiffness = 6" in txt and
       "count = 0" not in txt and "key = initial.angle" not in txt,
       "a style key in one scene: the HUD lists only the physics that differs "
       f"({' | '.join(l for l in txt.splitlines() if 'differs' in l)})")

# data: each scene's rows with a scene column
r = run("data", sa, sc, "-o", "-", "--every", "0.5")
lines = r.stdout.splitlines()
one = run("data", sc, "-o", "-", "--every", "0.5").stdout.splitlines()
ok(r.returncode == 0 and lines[0].startswith("scene,t,x,y") and
   [ln for ln in lines if ln.startswith("short,")] == ["short," + ln for ln in one[1:]] and
   sum(ln.startswith("soft,") for ln in lines) == 21,
   "data of two scenes: a scene column, each scene's rows as its own run writes them")

# hostile file names: the scene column is an RFC 4180 field that Python's
# csv module reads back; two files with one name are refused.
odd = os.path.join(work, "odd")
os.makedirs(os.path.join(odd, "x"), exist_ok=True)
os.makedirs(os.path.join(odd, "y"), exist_ok=True)
names = ["we,ird", "new\nline", 'quo"te']
for n in names:
    shutil.copy(sc, os.path.join(odd, n + ".ini"))
r = run("data", *[os.path.join(odd, n + ".ini") for n in names], "-o", "-", "--every", "1")
rows = list(csv.reader(r.stdout.splitlines(keepends=True)))
ok(r.returncode == 0 and len({len(row) for row in rows}) == 1 and
   [row[0] for row in rows[1:]][::len(rows[1:]) // 3] == names,
   f"names with a comma, a line break and a quote stay one field each "
   f"({sorted({len(row) for row in rows})} fields; {r.stderr.strip()[-120:]})")
for d in ("x", "y"):
    shutil.copy(sc, os.path.join(odd, d, "a.ini"))
out = os.path.join(odd, "twice.csv")
r = run("data", os.path.join(odd, "x", "a.ini"), os.path.join(odd, "y", "a.ini"), "-o", out)
ok(r.returncode == 2 and "both give the scene column 'a'" in r.stderr and not os.path.exists(out),
   f"two scene files of one name: {r.stderr.strip()}")

# bad input
five = os.path.join(work, "five.png")
r = run("still", sa, sb, sc, sa, sb, "-o", five)
ok(r.returncode == 2 and "5 SCENE files: at most 4" in r.stderr and not os.path.exists(five),
   f"5 scenes: {r.stderr.strip()}")
r = run("render", sa, os.path.join(work, "missing.ini"), "-o", os.path.join(work, "m.mp4"))
ok(r.returncode == 2 and "missing.ini: cannot open scene" in r.stderr and
   not os.path.exists(os.path.join(work, "m.mp4")), f"a missing scene file: {r.stderr.strip()}")
r = run("still", sa, write("fps.ini", "[video]\nfps = 30\n"), "-o", five)
ok(r.returncode == 2 and "video.fps = 30" in r.stderr and not os.path.exists(five),
   f"scenes that differ in fps: {r.stderr.strip()}")
done()
