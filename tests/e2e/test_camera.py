#!/usr/bin/env python3
"""springpend tests: [view] camera, the perspective of a 3-D scene (issue 26).
The bob is found in the picture by its colour (the middle of its box of
reddish pixels) and must lie, to a pixel, where a pinhole camera computed
here puts scipy's position of the bob (DOP853 on the 3-D equations): the eye
at target + D (sin az cos el, sin el, cos az cos el) from the scene's angles
(auto: 35 and 25 degrees), looking at the target, no roll; the fitted focal
length, image centre, target and distance come from the PNG's
springpend.overlay text. The bob's size follows 1/depth (two cameras, 4%).
Its shadow darkens the floor straight below it. SVG (rsvg-convert), PDF
(pdftoppm) and raw video frames (GL) put the bob where the PNG does. The
HUD's precession per exchange is info's. Refused with exit 2 and no output:
a Poincare panel or data --poincare of a 3-D scene, vectors in perspective,
an eye inside the motion, malformed cameras (an ensemble with a camera is drawn
in perspective: test ensemble).
usage: test_camera.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import math
import os
import subprocess

from sptest import diag, done, ffmpeg_rgb, need_scipy, ok, png_overlay, setup

exe, src, work, run = setup("camera", ["ffmpeg"])
need_scipy()
import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

L0, K, M, G = 0.75, 39.24, 1.0, 9.81
R0, TH0, PHD = 1.05, 12.0, 1.5
W, H = 960, 540
BODY = (f"[pendulum]\nnatural_length = {L0}\nstiffness = {K}\nmass = {M}\ngravity = {G}\n"
        f"[initial]\nlength = {R0}\nangle = {TH0}\nazimuth_rate = {PHD}\n"
        "[integrator]\nmethod = dop853\ntolerance = 1e-11\n"
        "[video]\nduration = 12\nfps = 30\n")


def scene(name, view="", extra=""):
    path = os.path.join(work, name + ".ini")
    with open(path, "w") as fp:
        fp.write(BODY + extra + "[view]\ntrail = 0\n" + view)
    return path


def bob_at(t):
    """scipy: the bob (x, y, z), m, at time t."""
    th = math.radians(TH0)
    x, y = R0 * math.sin(th), -R0 * math.cos(th)
    u0 = [x, y, 0.0, 0.0, 0.0, PHD * x]

    def rhs(_, u):
        x, y, z, vx, vy, vz = u
        c = K / M * (1 - L0 / math.sqrt(x * x + y * y + z * z))
        return [vx, vy, vz, -c * x, -c * y - G, -c * z]
    return solve_ivp(rhs, (0, t), u0, method="DOP853", rtol=1e-12, atol=1e-14).y[:3, -1]


def pixels(path, w=W, h=H):
    return ffmpeg_rgb(path, w, h)


def bob_box(img):
    """Middle and half width (px) of the box of the bob's reddish pixels."""
    r, g, b = img[..., 0], img[..., 1], img[..., 2]
    ys, xs = np.nonzero((r > g + 40) & (r > b + 40))
    if len(xs) == 0:
        return None, 0
    return (np.array([xs.min() + xs.max() + 1, ys.min() + ys.max() + 1]) / 2,
            (xs.max() - xs.min() + 1) / 2)


def pinhole(o, az_deg, el_deg, p):
    """p (m) in px, the eye from the scene's angles; the fit from overlay o."""
    az, el = math.radians(az_deg), math.radians(el_deg)
    target = np.array([float(v) for v in o["camera.target_m"].split(",")])
    dist = float(o["camera.distance_m"])
    back = np.array([math.sin(az) * math.cos(el), math.sin(el), math.cos(az) * math.cos(el)])
    eye = target + dist * back
    fwd = -back
    right = np.cross(fwd, [0, 1, 0])
    right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    q = np.asarray(p) - eye
    d = q @ fwd
    f = float(o["camera.focal_px"])
    cx, cy = (float(v) for v in o["camera.centre_px"].split(","))
    return np.array([cx + f * (q @ right) / d, cy - f * (q @ up) / d]), d


T = 7.3
bob = bob_at(T)
ok(abs(bob[2]) > 0.05, f"the bob is out of the starting plane at t = {T} s (z = {bob[2]:.3f} m)")
sizes = {}
for name, cam, (az, el) in [("auto", None, (35, 25)), ("side", "-60 12", (-60, 12)),
                            ("high", "140 50 6", (140, 50)), ("front0", "0 0", (0, 0))]:
    path = scene(name, f"camera = {cam}\n" if cam else "")
    out = os.path.join(work, name + ".png")
    r = run("still", path, "--at", str(T), "--size", f"{W}x{H}", "-q", "-o", out)
    if not ok(r.returncode == 0, f"still with camera = {cam or 'auto'}"):
        diag(r.stderr)
        continue
    o = png_overlay(out)
    if not ok("camera.focal_px" in o, f"camera = {cam or 'auto'}: the overlay states the pinhole"):
        continue
    want, depth = pinhole(o, az, el, bob)
    got, half = bob_box(pixels(out))
    err = np.hypot(*(got - want)) if got is not None else math.inf
    ok(err <= 1.0, f"camera = {cam or 'auto'}: the bob at {np.round(got, 1) if got is not None else None} px, "
       f"the pinhole puts it at {np.round(want, 1)} ({err:.2f} px off)")
    sizes[name] = (half, float(o["camera.distance_m"]) / depth)
    if name == "auto":
        img = pixels(out)
        fy = float(o["camera.floor_y_m"])
        sh, _ = pinhole(o, az, el, [bob[0], fy, bob[2]])
        lum = img.mean(axis=2)
        yy, xx = np.mgrid[0:H, 0:W]
        dist = np.hypot(xx + 0.5 - sh[0], 2 * (yy + 0.5 - sh[1]))  # the floor seen at a slant
        under, floor = lum[dist < 6].mean(), lum[(dist > 40) & (dist < 60)].mean()
        ok(under < 0.7 * floor, f"the shadow below the bob at {np.round(sh, 1)} px darkens the floor "
           f"(mean luminance {under:.1f} there, {floor:.1f} around it)")
if "auto" in sizes and "high" in sizes:
    (h1, s1), (h2, s2) = sizes["auto"], sizes["high"]
    ratio, want = h1 / h2, s1 / s2
    ok(abs(ratio / want - 1) < 0.04, f"the bob's size follows 1/depth: radius ratio {ratio:.3f}, "
       f"depths give {want:.3f}")

# ---- SVG, PDF and video frames put the bob where the PNG does ----------------
path = scene("vec", "hud = true\n")
png = os.path.join(work, "vec.png")
run("still", path, "--at", str(T), "--size", f"{W}x{H}", "-q", "-o", png)
ref, _ = bob_box(pixels(png))
for ext in ("svg", "pdf"):
    out = os.path.join(work, "vec." + ext)
    r = run("still", path, "--at", str(T), "--size", f"{W}x{H}", "-q", "-o", out)
    ras = os.path.join(work, f"vec-{ext}.png")
    if ext == "svg":
        subprocess.run(["rsvg-convert", out, "-o", ras], check=True)
    else:
        subprocess.run(["pdftoppm", "-png", "-r", "72", "-singlefile", out, ras[:-4]], check=True)
    got, _ = bob_box(pixels(ras))
    err = np.hypot(*(got - ref)) if got is not None and ref is not None else math.inf
    ok(r.returncode == 0 and err <= 1.5, f"{ext.upper()}: the bob {err:.2f} px from the PNG's")
    if ext == "pdf":
        text = subprocess.run(["pdftotext", out, "-"], capture_output=True, text=True).stdout
        info = json.loads(run("info", path, "--json").stdout)
        want = math.degrees(info["precession_per_exchange"])
        line = next((ln for ln in text.splitlines() if "precession per exchange" in ln), "")
        shown = line.split("≈")[-1].split("°")[0].strip().replace("\u2212", "-") if line else "nan"
        ok(line and abs(float(shown) - want) < 0.051,
           f"the HUD's precession per exchange '{line.strip()}' is info's {want:.2f}°")
fps, k = 30, 219  # frame 219 at 30 fps: t = 7.3 s
raw = subprocess.run([exe, "render", path, "--size", f"{W}x{H}", "--frames", f"{k}:{k + 1}", "--format",
                      "raw", "-o", "-", "-q"], capture_output=True, cwd=work)
if ok(raw.returncode == 0 and len(raw.stdout) == W * H * 4, "render of one raw frame (GL)"):
    got, _ = bob_box(np.frombuffer(raw.stdout, np.uint8).reshape(H, W, 4)[..., :3].astype(int))
    err = np.hypot(*(got - ref)) if got is not None and ref is not None else math.inf
    ok(err <= 1.0, f"the video frame at t = {T} s: the bob {err:.2f} px from the still's")

# ---- refused: FILE:LINE, exit 2, no output -----------------------------------
for name, view, extra, args, words in [
        ("poincare", "panels = r, poincare\n", "", ("still",), ":18: the poincare panel"),
        ("vectors", "vectors = velocity\n", "", ("still",), ":18: view.vectors"),
        ("inside", "camera = 30 20 0.4\n", "", ("still",), "view.camera: from 0.4 m the eye is inside"),
        ("elev", "camera = 30 90\n", "", ("still",), ":18: view.camera = '30 90' is out of range"),
        ("words", "camera = left\n", "", ("still",), ":18: view.camera: the azimuth 'left'"),
        ("dpoinc", "", "", ("data", "--poincare"), "--poincare writes the planar section")]:
    path = scene("bad-" + name, view, extra)
    out = os.path.join(work, f"bad-{name}.{'csv' if args[0] == 'data' else 'png'}")
    r = run(args[0], path, *args[1:], "-o", out, "-q")
    ok(r.returncode == 2 and words in r.stderr and not os.path.exists(out),
       f"refused ({name}): exit {r.returncode}, '{r.stderr.strip()[:160]}'")

# a planar scene: camera = front and auto draw the same frame (today's front view)
planar = os.path.join(work, "planar.ini")
frames = []
for cam in ("auto", "front"):
    with open(planar, "w") as fp:
        fp.write(f"[view]\ncamera = {cam}\n[video]\nwidth = 320\nheight = 180\n")
    frames.append(subprocess.run([exe, "render", planar, "--frames", "40:41", "--format", "raw", "-o", "-",
                                  "-q"], capture_output=True).stdout)
ok(len(frames[0]) == 320 * 180 * 4 and frames[0] == frames[1],
   "a planar scene: camera = auto draws the front view, as camera = front")
done()
