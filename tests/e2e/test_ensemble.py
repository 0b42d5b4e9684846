#!/usr/bin/env python3
"""springpend tests: [ensemble]. Every member equals its own single run (data
with --set KEY=VALUE) for the fixed-step methods; the ensemble's spread grows
at about the Lyapunov exponent that scipy's DOP853 gives for chaotic.ini and
stays small for resonance.ini; bad [ensemble] input is FILE:LINE, exit 2,
no file; a member that blows up stops the run (exit 3, no file); the stills
(PNG, SVG, PDF) and videos draw N distinct colours.
usage: test_ensemble.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import colorsys
import csv
import io
import math
import os
import shutil
import subprocess
import sys
import zlib

from sptest import done, ok, png_overlay, runner

try:
    import scipy  # noqa: F401
except ImportError:
    if os.path.exists("/usr/bin/python3") and os.path.realpath(sys.executable) != os.path.realpath("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3", *sys.argv])

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "ensemble"))
scenes = os.path.join(src, "..", "scenes")
chaotic, resonance = os.path.join(scenes, "chaotic.ini"), os.path.join(scenes, "resonance.ini")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


run = runner(exe, work)


def table(text):
    return list(csv.DictReader(io.StringIO(text)))


# ---- every member is its own single run ----
for method, dt in (("rk4", "0.0005"), ("verlet", "0.0005"), ("yoshida4", "0.001")):
    sets = ["--set", f"integrator.method={method}", "--set", f"integrator.dt={dt}",
            "--set", "video.duration=6", "--set", "video.fps=10"]
    r = run("data", chaotic, *sets, "--set", "ensemble.count=7", "--set", "ensemble.spread=0.5", "-o", "-")
    rows = table(r.stdout)
    same = r.returncode == 0 and len(rows) == 7 * 60
    for member in (0, 3, 6):
        mine = [x for x in rows if int(x["member"]) == member]
        value = mine[0]["initial.angle"] if mine else "0"
        single = table(run("data", chaotic, *sets, "--set", f"initial.angle={value}", "-o", "-").stdout)
        same = same and len(single) == len(mine) and all(
            a[c] == b[c] for a, b in zip(mine, single) for c in ("x", "y", "vx", "vy"))
    # the members differ: the ends of 0.5 degrees apart
    ends = [x for x in rows if x["t"] == rows[-1]["t"] and x["member"] in ("0", "6")]
    ok(same and len(ends) == 2 and ends[0]["x"] != ends[1]["x"],
       f"{method}: members 0, 3, 6 of 7 print the same x, y, vx, vy (15 digits) as their single runs")

# ---- the spread grows at lambda (scipy) for chaotic.ini, stays small for resonance.ini ----
try:
    import numpy as np
    from scipy.integrate import solve_ivp
except ImportError:
    np = None


def lyapunov_scipy(theta0_deg, r0, k, m, L0, g, T):
    """Benettin with scipy's DOP853 on the state and one tangent vector,
    renormalised every second."""
    km = k / m

    def f(t, s):
        x, y, vx, vy, dx, dy, dvx, dvy = s
        rho = math.hypot(x, y)
        c = km * (1 - L0 / rho)
        a = km * L0 / rho ** 3
        jxx, jxy, jyy = -c - a * x * x, -a * x * y, -c - a * y * y
        return [vx, vy, -c * x, -c * y - g, dvx, dvy, jxx * dx + jxy * dy, jxy * dx + jyy * dy]

    th = math.radians(theta0_deg)
    s = np.array([r0 * math.sin(th), -r0 * math.cos(th), 0, 0, 1, 0, 0, 0], float)
    total = 0.0
    for k1 in range(1, int(T) + 1):
        s = solve_ivp(f, (k1 - 1, k1), s, method="DOP853", rtol=1e-10, atol=1e-12).y[:, -1]
        n = math.sqrt(sum(s[4:] ** 2))
        total += math.log(n)
        s[4:] /= n
    return total / T


def log_spread(rows, omega):
    """ln of the RMS distance from the mean in (x, y, vx/omega, vy/omega), per time."""
    by_t = {}
    for x in rows:
        by_t.setdefault(float(x["t"]), []).append(
            [float(x["x"]), float(x["y"]), float(x["vx"]) / omega, float(x["vy"]) / omega])
    out = []
    for t in sorted(by_t):
        p = np.array(by_t[t])
        out.append((t, 0.5 * math.log(((p - p.mean(axis=0)) ** 2).sum(axis=1).mean())))
    return out


if np is None:
    ok(True, "# SKIP scipy is missing: no independent growth check")
    ok(True, "# SKIP scipy is missing")
else:
    T = 30
    # chaotic.ini: k 39.24, m 1, L0 0.75, r0 1.2, theta0 85.94 degrees
    lam_c = lyapunov_scipy(85.94, 1.2, 39.24, 1.0, 0.75, 9.81, T)
    r = run("data", chaotic, "--set", "ensemble.count=20", "--set", "ensemble.spread=1e-6",
            "--set", f"video.duration={T}", "--every", "0.25", "-o", "-")
    ls = log_spread(table(r.stdout), math.sqrt(39.24))
    # least-squares slope of ln spread over the run (the start's transient left out)
    pts = [(t, v) for t, v in ls if t >= 2]
    slope = np.polyfit([t for t, _ in pts], [v for _, v in pts], 1)[0]
    ok(r.returncode == 0 and abs(slope - lam_c) <= 0.3 * lam_c and ls[-1][1] - ls[0][1] > 8,
       f"chaotic.ini: 20 members' spread grows at {slope:.3f}/s (scipy's lambda over {T} s: "
       f"{lam_c:.3f}/s), by e^{ls[-1][1] - ls[0][1]:.1f}")
    # resonance.ini: k 29.43, m 1, L0 1, r0 1.4333, theta0 1 degree
    lam_r = lyapunov_scipy(1.0, 1.4333, 29.43, 1.0, 1.0, 9.81, T)
    r = run("data", resonance, "--set", "ensemble.count=20", "--set", "ensemble.spread=1e-6",
            "--set", f"video.duration={T}", "--every", "0.25", "-o", "-")
    ls = log_spread(table(r.stdout), math.sqrt(29.43))
    grown = max(v for _, v in ls) - ls[0][1]
    ok(r.returncode == 0 and lam_r < 0.2 * lam_c and grown < 4 and grown < 0.5 * lam_c * T,
       f"resonance.ini: the spread grows by e^{grown:.1f} at most over {T} s (scipy's lambda "
       f"{lam_r:.3f}/s; chaotic.ini's e^{lam_c * T:.0f})")

# ---- bad input: FILE:LINE, exit 2, nothing written ----
bad = {
    "count.ini": ("[ensemble]\ncount = -3\n", 2, "ensemble.count"),
    "key.ini": ("[ensemble]\ncount = 4\nkey = video.fps\n", 3, "ensemble.key"),
    "nokey.ini": ("[ensemble]\ncount = 4\nkey = initial.nope\n", 3, "ensemble.key"),
    "spread.ini": ("[ensemble]\ncount = 4\nspread = 0\n", 3, "ensemble.spread"),
    "range.ini": ("[pendulum]\nmass = 0.5\n[ensemble]\ncount = 4\nkey = pendulum.mass\n"
                  "spread = 2\n", 6, "pendulum.mass = -0.5"),
}
for name, (text, line, word) in bad.items():
    with open(os.path.join(work, name), "w") as f:
        f.write(text)
    r = run("still", name, "-o", "bad.png")
    ok(r.returncode == 2 and f"{name}:{line}: " in r.stderr and word in r.stderr
       and not os.path.exists(os.path.join(work, "bad.png")),
       f"{name}: exit 2 with '{name}:{line}: ... {word} ...'")

r = run("data", chaotic, "--set", "ensemble.count=10000", "--set", "video.duration=1000", "-o", "big.csv")
ok(r.returncode == 2 and "ensemble members" in r.stderr and not os.path.exists(os.path.join(work, "big.csv")),
   "data: members times rows past 1e7 refused up front (exit 2, no file)")

# ---- a member that blows up stops the run: exit 3, no file ----
r = run("still", os.path.join(scenes, "default.ini"), "--set", "pendulum.stiffness=6e6",
        "--set", "pendulum.mass=1", "--set", "initial.length=0.5", "--set", "ensemble.count=5",
        "--set", "ensemble.key=pendulum.stiffness", "--set", "ensemble.spread=8e6", "--at", "1",
        "-o", "blow.png")
ok(r.returncode == 3 and "ensemble member 5 of 5" in r.stderr
   and not os.path.exists(os.path.join(work, "blow.png")),
   "a member past rk4's stability limit: exit 3, named, no file")


# ---- N distinct colours in the pictures ----
def member_hue(i, n):
    """sp_ensemble_color's hue (the formula of src/ensemble.c, written again)."""
    h = 0.83 * i / (n - 1)
    rgb = [0.15 + 0.8 * min(max(abs((h * 6 + 4 - 2 * k + 6) % 6 - 3) - 1, 0), 1) for k in range(3)]
    return colorsys.rgb_to_hsv(*rgb)[0]


def png_pixels(path):
    """RGB(A) rows of an 8-bit PNG (no interlace), with the filters undone."""
    data = open(path, "rb").read()
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        n = int.from_bytes(data[pos:pos + 4], "big")
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype = int.from_bytes(body[:4], "big"), int.from_bytes(body[4:8], "big"), body[8], body[9]
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    bpp = {2: 3, 6: 4}[ctype]
    raw, stride, prev, out = zlib.decompress(idat), w * bpp, bytearray(w * bpp), []
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b, c = prev[x], prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out.append([tuple(line[x:x + 3]) for x in range(0, stride, bpp)])
        prev = line
    return out


def hues_found(path, n):
    """How many of the n members' hues have at least 15 saturated pixels within 3 degrees."""
    counts = [0] * n
    want = [member_hue(i, n) for i in range(n)]
    for row in png_pixels(path):
        for px in row:
            hh, s, v = colorsys.rgb_to_hsv(*(c / 255 for c in px))
            if s > 0.5 and v > 0.5:
                for i, w in enumerate(want):
                    if min(abs(hh - w), 1 - abs(hh - w)) < 3 / 360:
                        counts[i] += 1
    return sum(c >= 15 for c in counts)


N = 8
look = ["--set", f"ensemble.count={N}", "--set", "ensemble.spread=120", "--set", "view.panels=spread",
        "--set", "view.hud=false", "--set", "view.colorbar=false", "--size", "960x540"]
r = run("still", chaotic, *look, "-o", "members.png")
ok(r.returncode == 0 and hues_found(os.path.join(work, "members.png"), N) == N,
   f"still PNG: {N} members in {N} distinct hues")
r = run("still", chaotic, *look, "-o", "members.svg")
conv = subprocess.run(["rsvg-convert", "-o", "svg.png", "members.svg"], cwd=work, capture_output=True) \
    if shutil.which("rsvg-convert") and r.returncode == 0 else None
ok(conv is not None and conv.returncode == 0 and hues_found(os.path.join(work, "svg.png"), N) == N,
   f"still SVG (rsvg-convert): {N} distinct hues")
r = run("still", chaotic, *look, "-o", "members.pdf")
conv = subprocess.run(["pdftoppm", "-png", "-r", "72", "-singlefile", "members.pdf", "pdf"], cwd=work,
                      capture_output=True) if shutil.which("pdftoppm") and r.returncode == 0 else None
ok(conv is not None and conv.returncode == 0 and hues_found(os.path.join(work, "pdf.png"), N) == N,
   f"still PDF (pdftoppm): {N} distinct hues")
# without [ensemble] the same picture has no member colours
r = run("still", chaotic, *look[4:], "--set", "view.panels=theta", "-o", "single.png")
ok(r.returncode == 0 and hues_found(os.path.join(work, "single.png"), N) <= 2,
   "without [ensemble]: not the members' hues")
# videos: every format renders
for ext in ("mp4", "webm", "gif", "png"):
    out = f"clip.{ext}" if ext != "png" else "seq/frame-%04d.png"
    r = run("render", chaotic, *look, "--set", "video.duration=0.2", "--set", "video.fps=10",
            "--set", "ensemble.trails=true", "-o", out, "-q")
    made = os.path.exists(os.path.join(work, out)) if ext != "png" else \
        os.path.isdir(os.path.join(work, "seq")) and len(os.listdir(os.path.join(work, "seq"))) == 2
    ok(r.returncode == 0 and made, f"render .{ext} with an ensemble and trails" +
       ("" if r.returncode == 0 else ": " + r.stderr.strip()[-200:]))

# ---- 3-D members (initial.azimuth_rate): each its own single 3-D run ----
swing = os.path.join(scenes, "swinging-spring.ini")
sets3 = ["--set", "integrator.method=rk4", "--set", "integrator.dt=0.001",
         "--set", "video.duration=6", "--set", "video.fps=10", "--set", "video.speed=1"]
ens3 = ["--set", "ensemble.count=5", "--set", "ensemble.key=initial.azimuth_rate",
        "--set", "ensemble.spread=1.6"]
r = run("data", swing, *sets3, *ens3, "-o", "-")
rows = table(r.stdout)
same = r.returncode == 0 and len(rows) == 5 * 60 and "azimuth" in (rows[0] if rows else {})
for member in (0, 2, 4):
    mine = [x for x in rows if int(x["member"]) == member]
    value = mine[0]["initial.azimuth_rate"] if mine else "0"
    single = table(run("data", swing, *sets3, "--set", f"initial.azimuth_rate={value}",
                       "-o", "-").stdout)
    same = same and len(single) == len(mine) and all(
        a[c] == b[c] for a, b in zip(mine, single)
        for c in ("x", "y", "vx", "vy", "z", "vz", "azimuth"))
ends = [x for x in rows if x["t"] == rows[-1]["t"] and x["member"] in ("0", "4")] if rows else []
ok(same and len(ends) == 2 and ends[0]["z"] != ends[1]["z"],
   "3-D (swinging-spring.ini, rk4): members 0, 2, 4 of 5 turning at 0.2 to 1.8 rad/s print the "
   "same x, y, vx, vy, z, vz, azimuth (15 digits) as their single 3-D runs")

# drawn in the 3-D camera's perspective: every member's hue, the camera in the overlay
# (chaotic.ini's physics from 60 degrees, turning at 1.5 rad/s, 8 starts over 80 degrees)
wide = os.path.join(work, "wide3d.ini")
with open(wide, "w") as f:
    f.write("[pendulum]\nnatural_length = 0.75\nstiffness = 39.24\nmass = 1\n[initial]\n"
            "length = 1.2\nangle = 60\nazimuth_rate = 1.5\n[integrator]\nmethod = rk4\n"
            "dt = 0.0005\n")
look3 = ["--set", f"ensemble.count={N}", "--set", "ensemble.key=initial.angle", "--set",
         "ensemble.spread=80", "--set", "ensemble.trails=true", "--set", "view.panels=none",
         "--set", "view.hud=false", "--size", "960x540"]
r = run("still", wide, *look3, "--at", "3", "-o", "members3d.png")
overlay = png_overlay(os.path.join(work, "members3d.png")) if r.returncode == 0 else ""
ok(r.returncode == 0 and hues_found(os.path.join(work, "members3d.png"), N) == N and
   "camera.focal_px" in overlay,
   f"a 3-D ensemble's still: {N} distinct hues, drawn through the perspective camera "
   f"({r.stderr.strip()[:160]})")
r = run("still", wide, *look3, "--at", "3", "-o", "members3d.svg")
conv = subprocess.run(["rsvg-convert", "-o", "svg3d.png", "members3d.svg"], cwd=work,
                      capture_output=True) if shutil.which("rsvg-convert") and r.returncode == 0 \
    else None
ok(conv is not None and conv.returncode == 0 and hues_found(os.path.join(work, "svg3d.png"), N) == N,
   f"the 3-D ensemble as SVG (rsvg-convert): {N} distinct hues")
r = run("render", wide, *look3, "--set", "video.duration=0.4", "--set", "video.fps=10",
        "-o", "clip3d.mp4", "-q")
ok(r.returncode == 0 and os.path.exists(os.path.join(work, "clip3d.mp4")),
   "render .mp4 of a 3-D ensemble with trails" + ("" if r.returncode == 0 else
                                                  ": " + r.stderr.strip()[-200:]))
# a planar ensemble with an explicit camera: in perspective too (was refused)
r = run("still", chaotic, *look, "--set", "view.camera=30 20", "-o", "members-cam.png")
overlay = png_overlay(os.path.join(work, "members-cam.png")) if r.returncode == 0 else ""
ok(r.returncode == 0 and hues_found(os.path.join(work, "members-cam.png"), N) == N and
   "camera.focal_px" in overlay,
   f"a planar ensemble with view.camera = 30 20: {N} hues, in perspective "
   f"({r.stderr.strip()[:160]})")

done()
