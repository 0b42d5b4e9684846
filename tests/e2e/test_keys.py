#!/usr/bin/env python3
"""springpend tests: every scene key read through the parser, from a scene
file, with a value that is not its default (and not zero), in its unit, and
shown to change what it should. The shipped scenes set some keys to zero and
the C tests set struct fields directly, so a key read in the wrong unit (rad/s
taken as degrees/s, Hz as rad/s, ms as s) or parsed and then ignored passed
the suite. Physics is checked against scipy (sptest.solve), frame times and
counts against k * speed / fps and round(duration * fps / speed), the
encoder's settings against x264's own record of them in the stream, PNG's
level against zlib's header, and each [view] and [ensemble] key against the
frame it draws (raw RGBA: the pixels, not the file's bytes, which carry the
scene's text). A key missing from this test fails the last check.
usage: test_keys.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import math
import os
import re
import shutil
import subprocess
import sys
import zlib

from sptest import diag, done, model, need_scipy, ok, runner, sets, solve, start

need_scipy()
import numpy as np  # noqa: E402

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "keys"))
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
run = runner(exe, work)
covered = set()


def scene(name, keys):
    """Writes a scene file with keys {"section.key": value}; returns its path
    and marks the keys covered."""
    by = {}
    for k, v in keys.items():
        by.setdefault(k.split(".")[0], []).append(f"{k.split('.')[1]} = {v}")
        covered.add(k)
    path = os.path.join(work, name + ".ini")
    with open(path, "w") as f:
        for sec, lines in by.items():
            f.write(f"[{sec}]\n" + "\n".join(lines) + "\n")
    return path


def rows(text):
    lines = text.strip().split("\n")
    head = lines[0].split(",")
    return head, np.array([[float(v) for v in line.split(",")] for line in lines[1:]])


def err(r):
    return r.stderr.strip()[-300:]


# ---- physics: every [pendulum], [initial] and [pivot] key at once ----------
PHYS = {"pendulum.natural_length": 0.7, "pendulum.stiffness": 13, "pendulum.mass": 0.8,
        "pendulum.gravity": 9.5, "pendulum.damping": 0.05,
        "initial.length": 0.9, "initial.angle": 25, "initial.length_rate": 0.3,
        "initial.angle_rate": 0.4, "pivot.amplitude": 0.02, "pivot.frequency": 1.3}
T = 3.0
ts = np.arange(0, T + 1e-9, 0.25)
ref = solve(model(0.7, 13, 0.8, 0.05, 0.02, 1.3, 9.5), start(0.9, 25, 0.3, 0.4), T, ts).y.T
m, k, L0, g = 0.8, 13, 0.7, 9.5
kin = 0.5 * m * (ref[:, 2] ** 2 + ref[:, 3] ** 2)
spr = 0.5 * k * (np.hypot(ref[:, 0], ref[:, 1]) - L0) ** 2
grav = m * g * ref[:, 1]
# fixed steps at dt = 2e-4 s: their errors over 3 s, with margin
bounds = {"dop853": 1e-7, "dopri5": 1e-5, "rk4": 1e-6, "verlet": 1e-3, "yoshida4": 1e-5}
for method, bound in bounds.items():
    path = scene(f"phys-{method}", {**PHYS, "integrator.method": method, "integrator.dt": "2e-4",
                                    "integrator.tolerance": "1e-11", "video.duration": T})
    r = run("data", path, "-o", "-", "--every", "0.25")
    if not ok(r.returncode == 0, f"data with every physics key set ({method}): exit 0 {err(r)}"):
        continue
    head, got = rows(r.stdout)
    col = {h: got[:, i] for i, h in enumerate(head)}
    worst = max(np.max(np.abs(col[c] - ref[:, i])) for i, c in enumerate(("x", "y", "vx", "vy")))
    ok(got.shape[0] == len(ts) and worst < bound,
       f"{method}: x, y, vx, vy against scipy with L0 0.7 m, k 13 N/m, m 0.8 kg, g 9.5, "
       f"b 0.05 N s/m, r0 0.9 m, 25 deg, 0.3 m/s, 0.4 rad/s, A 0.02 m, f 1.3 Hz: "
       f"{worst:.2e} < {bound:.0e}")
    if method == "dop853":
        ok(np.max(np.abs(col["pivot_y"] - 0.02 * np.sin(2 * np.pi * 1.3 * ts))) < 1e-12,
           "pivot_y = A sin(2 pi f t), f in Hz, A in m")
        ok(max(np.max(np.abs(col["kinetic"] - kin)), np.max(np.abs(col["spring"] - spr)),
               np.max(np.abs(col["gravity"] - grav))) < 1e-6,
           "kinetic, spring and gravity energies against 1/2 m v^2, 1/2 k (rho - L0)^2, m g y")
        ok(abs(col["r"][0] - 0.9) < 1e-15 and abs(col["theta"][0] - math.radians(25)) < 1e-15 and
           abs(col["r_dot"][0] - 0.3) < 1e-15 and abs(col["theta_dot"][0] - 0.4) < 1e-15,
           "t = 0: r 0.9 m, theta 25 degrees (in radians), r_dot 0.3 m/s, theta_dot 0.4 rad/s")

# rkn1210 takes a force of the position only: the same scene undamped, pivot at rest
cons = {k: v for k, v in PHYS.items() if k not in ("pendulum.damping", "pivot.amplitude",
                                                   "pivot.frequency")}
path = scene("phys-rkn1210", {**cons, "integrator.method": "rkn1210",
                              "integrator.tolerance": "1e-11", "video.duration": T})
r = run("data", path, "-o", "-", "--every", "0.25")
want = solve(model(0.7, 13, 0.8, 0, 0, 0, 9.5), start(0.9, 25, 0.3, 0.4), T, ts).y.T
got = rows(r.stdout)[1][:, 1:5] if r.returncode == 0 else np.zeros((0, 4))
worst = np.max(np.abs(got - want)) if got.shape == want.shape else math.inf
ok(worst < 1e-7, f"rkn1210: x, y, vx, vy against scipy (no damping, no drive): {worst:.2e} {err(r)}")

# azimuth_rate in rad/s about the vertical: the bob starts at z = 0 with
# vz = phi' r0 sin(theta0), and L_y = z vx - x vz stays put (3-D: test_spatial)
path = scene("phys-azimuth", {**cons, "initial.azimuth_rate": 0.7, "integrator.method": "dop853",
                              "integrator.tolerance": "1e-11", "video.duration": T})
r = run("data", path, "-o", "-", "--every", "0.25")
head, got = rows(r.stdout) if r.returncode == 0 else ([], np.zeros((1, 20)))
col = {h: got[:, i] for i, h in enumerate(head)}
want_vz = 0.7 * 0.9 * math.sin(math.radians(25))
Ly = col["z"] * col["vx"] - col["x"] * col["vz"] if "z" in col else np.array([math.inf])
ok(r.returncode == 0 and col["z"][0] == 0 and abs(col["vz"][0] - want_vz) < 1e-15 and
   np.ptp(col["z"]) > 0.1 and np.ptp(Ly) < 1e-9,
   f"initial.azimuth_rate 0.7 rad/s: vz(0) = 0.7 * 0.9 m * sin 25 deg = {want_vz:.6f} m/s, "
   f"z leaves 0, L_y holds {err(r)}")

# [integrator] dt in seconds: RK4's error falls 16-fold from dt 0.02 to 0.01
errs = []
for dt in (0.02, 0.01):
    path = scene(f"dt-{dt}", {**PHYS, "integrator.method": "rk4", "integrator.dt": dt,
                              "video.duration": T})
    r = run("data", path, "-o", "-", "--every", "0.25")
    head, got = rows(r.stdout) if r.returncode == 0 else ([], np.zeros((len(ts), 5)))
    errs.append(np.max(np.abs(got[:, 1:5] - ref)) if got.shape[0] == len(ts) else math.inf)
ok(1e-7 < errs[0] < 1e-3 and 10 < errs[0] / errs[1] < 24,
   f"integrator.dt in s: rk4 error {errs[0]:.2e} at 0.02, ratio {errs[0] / errs[1]:.1f} (4th order: 16)")
# tolerance: dopri5 at 1e-5 far off, at 1e-10 close
errs = []
for tol in ("1e-5", "1e-10"):
    path = scene(f"tol-{tol}", {**PHYS, "integrator.method": "dopri5", "integrator.tolerance": tol,
                                "video.duration": T})
    r = run("data", path, "-o", "-", "--every", "0.25")
    head, got = rows(r.stdout) if r.returncode == 0 else ([], np.zeros((len(ts), 5)))
    errs.append(np.max(np.abs(got[:, 1:5] - ref)) if got.shape[0] == len(ts) else math.inf)
ok(errs[0] > 1e-7 and errs[1] < 1e-6 and errs[0] > 30 * errs[1],
   f"integrator.tolerance: dopri5 error {errs[0]:.1e} at 1e-5, {errs[1]:.1e} at 1e-10")

# ---- [video]: frames at k * speed / fps, k < round(duration * fps / speed) --
for fps, dur, speed in ((25, 4.6, 1), (24, 5, 2.5), (29.97, 1.1, 0.5)):
    path = scene(f"frames-{fps}", {"video.fps": fps, "video.duration": dur, "video.speed": speed})
    r = run("data", path, "-o", "-")
    n = round(dur * fps / speed)
    head, got = rows(r.stdout) if r.returncode == 0 else ([], np.zeros((0, 1)))
    # t is printed with 10 significant digits
    ok(got.shape[0] == n and np.max(np.abs(got[:, 0] - np.arange(n) * speed / fps)) < 1e-9,
       f"fps {fps}, duration {dur} s, speed {speed}: {got.shape[0]} frame rows (want {n}), "
       f"at k * {speed} / {fps} s")

# width and height in px; png_level through zlib's header (FLEVEL 0 for level
# 1, 3 for 9, RFC 1950); crf and preset through x264's own record in the stream
small = {"video.width": 96, "video.height": 64, "video.duration": 0.2, "video.fps": 10}


def idat_flevel(path):
    d = open(path, "rb").read()
    i = d.index(b"IDAT")
    return d[i + 5] >> 6, int.from_bytes(d[16:20], "big"), int.from_bytes(d[20:24], "big")


for level, want in ((1, 0), (9, 3)):
    path = scene(f"png-{level}", {**small, "video.png_level": level})
    r = run("render", path, "-q", "-o", f"png{level}-%03d.png")
    got = idat_flevel(os.path.join(work, "png%d-000.png" % level)) if r.returncode == 0 else None
    ok(got == (want, 96, 64), f"png_level {level}: zlib FLEVEL {want}, 96x64 px: {got} {err(r)}")
# x264 presets (x264's preset table): subme 0 ultrafast, 1 superfast, 7 medium
for crf, preset, subme in ((31, "ultrafast", 0), (17, "medium", 7)):
    path = scene(f"x264-{crf}", {**small, "video.crf": crf, "video.preset": preset})
    r = run("render", path, "-q", "-o", f"x264-{crf}.mp4")
    sei = open(os.path.join(work, f"x264-{crf}.mp4"), "rb").read() if r.returncode == 0 else b""
    opts = re.search(rb"x264 - core .*? options: ([^\0]*)", sei)
    opts = opts.group(1).decode() if opts else ""
    ok(f"crf={crf}.0" in opts and f"subme={subme} " in opts,
       f"crf {crf}, preset {preset}: x264 options say crf={crf}.0, subme={subme}: {opts[:90]} {err(r)}")

# ---- [view] and [ensemble]: each changes the frame it draws -----------------
W, H = 320, 192  # at least 320x180: smaller frames leave the HUD and panels out
BASE = {"video.width": W, "video.height": H, "video.fps": 20, "video.duration": 2,
        "view.trail": 20, "view.fade": "false", "view.hud": "false"}


def frame(name, keys, at=30, extra=()):
    """Frame `at` of the scene BASE + keys as an H x W x 4 array (None on error)."""
    W, H = int(keys.get("video.width", BASE["video.width"])), int(keys.get("video.height", BASE["video.height"]))
    path = scene(name, {**BASE, **keys})
    r = subprocess.run([exe, "render", path, "--frames", f"{at}:{at + 1}", "--format", "raw",
                        "-o", "-", "-q", *extra], capture_output=True, cwd=work)
    if r.returncode != 0 or len(r.stdout) != W * H * 4:
        diag(f"{name}: exit {r.returncode} {r.stderr.decode(errors='replace')[-300:]}")
        return None
    return np.frombuffer(r.stdout, np.uint8).reshape(H, W, 4).astype(int)


base = frame("view-base", {})


def changed(name, keys, what, check=None, ref_frame=None, extra=()):
    f = frame(name, keys, extra=extra)
    b = base if ref_frame is None else ref_frame
    n = -1 if f is None or b is None else int(np.count_nonzero(np.any(f != b, axis=2)))
    good = n > 0 and (check is None or check(f))
    ok(good, f"{', '.join(f'{k} = {v}' for k, v in keys.items())}: {what} ({n} pixels changed)")
    return f


def lum(f):
    return f[..., :3].mean()


changed("theme", {"view.theme": "light"}, "a lighter frame", lambda f: lum(f) > lum(base) + 50)
changed("bg", {"view.background": "#204060"}, "that colour in the corner",
        lambda f: tuple(f[1, 1]) == (0x20, 0x40, 0x60, 255))
changed("transp", {"view.background": "transparent"}, "alpha 0 in the corner",
        lambda f: f[1, 1, 3] == 0)
changed("trail", {"view.trail": 2}, "a shorter trail: fewer pixels off the background",
        lambda f: np.count_nonzero(np.any(f != f[1, 1], axis=2)) <
        np.count_nonzero(np.any(base != base[1, 1], axis=2)))
# N frames span N - 1 frame intervals; 1 s at 20 fps spans 20 of them
dur = frame("trail-s", {"view.trail": "1s"})
frames21 = frame("trail-21", {"view.trail": 21})
ok(dur is not None and frames21 is not None and np.array_equal(dur, frames21) and
   not np.array_equal(dur, base),
   "view.trail = 1s (simulated s) at 20 fps draws the trail of view.trail = 21 frames")
changed("fade", {"view.fade": "true"}, "the trail fades")
changed("panels", {"view.panels": "r"}, "a panel")
# the vectors' legend needs a larger frame than the base one (a smaller one is refused)
big = {"video.width": 480, "video.height": 288}
changed("vectors", {"view.vectors": "forces, velocity", **big}, "arrows from the bob and their legend",
        ref_frame=frame("view-base-big", big))
with_r = frame("panel-r", {"view.panels": "r"})
changed("panel-bg", {"view.panels": "r", "view.panel_background": "none"}, "the panel on the frame's "
        "background", ref_frame=with_r)
with_panel = frame("panel-vir", {"view.panels": "energy,phase", "view.colormap": "viridis"})
changed("panel-inf", {"view.panels": "energy,phase", "view.colormap": "inferno"},
        "another colour map", ref_frame=with_panel)
changed("colorbar", {"view.panels": "energy,phase", "view.colormap": "viridis",
                     "view.colorbar": "true"}, "a colour bar", ref_frame=with_panel)
changed("hud", {"view.hud": "true"}, "the HUD's text")
hud = frame("hud-1", {"view.hud": "true"})
# (smaller: 320x192 takes no text above its default 12 px, attack11 #14)
changed("font", {"view.hud": "true", "view.font_scale": 0.8}, "other text", ref_frame=hud)
changed("font-family", {"view.hud": "true", "view.font": '"DejaVu Serif"'}, "serif text", ref_frame=hud)

changed("font-size", {"view.hud": "true", "view.font_size": 10}, "smaller text", ref_frame=hud)
changed("strobe", {"view.strobe": 0.2}, "strobe images")
changed("pendulum", {"view.pendulum": "false"}, "no spring and bob: fewer pixels off the background",
        lambda f: np.count_nonzero(np.any(f != f[1, 1], axis=2)) <
        np.count_nonzero(np.any(base != base[1, 1], axis=2)))
changed("title", {"view.title": "Run 3"}, "a title")
# a planar scene in perspective: the floor grid's lines below the pendulum
changed("camera", {"view.camera": "30 25"}, "the pendulum in perspective over a floor grid")
changed("caption", {"view.caption": "k = 2 N/m"}, "a caption")
# (the bob's trail off: an ensemble draws its members, and refuses a trail
# given with it, test attack13-lead)
ens = frame("ens", {"ensemble.count": 5, "ensemble.spread": 40, "view.trail": 0})
ok(ens is not None and np.count_nonzero(np.any(ens != base, axis=2)) > 0,
   "ensemble.count 5, spread 40 degrees: more pendulums")
changed("ens-key", {"ensemble.count": 5, "ensemble.spread": 0.4, "ensemble.key": "initial.length",
                   "view.trail": 0},
        "the members differ in r0", ref_frame=ens)
changed("ens-trails", {"ensemble.count": 5, "ensemble.spread": 40, "ensemble.trails": "true",
                      "view.trail": 0},
        "the members' trails", ref_frame=ens)
# ensemble.key and spread in the key's file units: members evenly over the range
path = scene("ens-data", {"ensemble.count": 5, "ensemble.spread": 0.4,
                          "ensemble.key": "pendulum.stiffness", "pendulum.stiffness": 3,
                          "video.duration": 0.1})
# a figure's style keys (stills and sweep figures: tests/e2e/test_paper.py)
for cmap in ("magma", "cividis", "gray"):
    changed(f"cmap-{cmap}", {"view.panels": "energy,phase", "view.colormap": cmap},
            f"the {cmap} colour map", ref_frame=with_panel)
with_bar = frame("panel-bar", {"view.panels": "energy,phase", "view.colormap": "viridis",
                               "view.colorbar": "true"})
changed("colorbar-label", {"view.panels": "energy,phase", "view.colormap": "viridis",
                           "view.colorbar": "true", "view.colorbar_label": '"speed"'},
        "the colour bar's own name", ref_frame=with_bar)
changed("cursor", {"view.panels": "r", "view.cursor": "false"}, "no time cursor", ref_frame=with_r)
changed("panel-titles", {"view.panels": "r", "view.panel_titles": "false"}, "no panel title",
        ref_frame=with_r)
changed("panel-labels", {"view.panels": "r", "view.panel_labels": "a"}, "(a) before the title",
        ref_frame=with_r)
changed("palette", {"view.panels": "r", "view.palette": "okabe_ito"}, "Okabe-Ito's blue",
        ref_frame=with_r)
changed("xlabel", {"view.panels": "r", "view.xlabel": '"time"'}, "the x axis's own name",
        ref_frame=with_r)
changed("ylabel", {"view.panels": "r", "view.ylabel": '"length"'}, "the y axis's own name",
        ref_frame=with_r)
with_energy = frame("panel-energy", {"view.panels": "energy"})
changed("legend", {"view.panels": "energy", "view.legend": "none"}, "no legend",
        ref_frame=with_energy)
with_phase = frame("panel-phase", {"view.panels": "phase"})
changed("marker-size", {"view.panels": "phase", "view.marker_size": 8}, "a larger dot at now",
        ref_frame=with_phase)
r = run("data", path, "-o", "-")
lines = r.stdout.split("\n")
vals = [float(line.split(",")[2]) for line in lines[1:6]] if r.returncode == 0 else []
ok(lines[0].startswith("t,member,pendulum.stiffness,") and
   np.allclose(vals, [2.8, 2.9, 3.0, 3.1, 3.2], rtol=0, atol=1e-12),
   f"ensemble.key pendulum.stiffness, spread 0.4 N/m around 3: members at {vals}")

# ---- every key the program knows was read above --------------------------
r = run("keys")
known, section = set(), ""
for line in r.stdout.split("\n"):
    if re.match(r"^\s*\[\w+\]$", line):
        section = line.strip()[1:-1]
    elif section and re.match(r"^\s{4}\w+\s", line):
        known.add(f"{section}.{line.split()[0]}")
missing = sorted(known - covered)
ok(known and not missing, f"every key of 'springpend keys' ({len(known)}) set from a scene "
   f"file here: missing {missing}")
done()
