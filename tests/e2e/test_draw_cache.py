#!/usr/bin/env python3
"""springpend tests: the GL backend's static cache (draw_gl.c) leaves every
pixel as it was. Each video is rendered twice as raw RGBA frames, with the
cache (the default) and with SPRINGPEND_DRAW_CACHE=0 (every item of every
frame drawn in list order), and the two must be byte-identical; --verbose
must show the cache used, so a broken cache that silently turned itself off
fails too, and the charts' settled curves must be appended to the cache,
not redrawn. Scenes: the default one and resonance.ini (all panels, HUD,
colourbar) at several sizes, the light theme on a transparent background,
a long exposure (trail = all, the accumulated layer under the cache, also
drawn into it) and chaotic.ini's long exposure with a title, a Poincare
section and a phase portrait. Also: frames of a cached video equal stills at the
same times (a still draws one frame, uncached in effect), and the EGL
backend where it works.
usage: test_draw_cache.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import re
import shutil
import subprocess
import sys

from sptest import done, ok

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "draw_cache"))
scenes = os.path.join(src, "..", "scenes")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def raw(scene, size, args, cache, gl=None):
    """Raw frames of a short video (bytes) and its --verbose text."""
    env = dict(os.environ, SPRINGPEND_DRAW_CACHE="1" if cache else "0")
    cmd = [exe, "render", os.path.join(scenes, scene), "--size", size, "--format", "raw",
           "-o", "-", "-q", "--verbose", *args] + (["--gl", gl] if gl else [])
    r = subprocess.run(cmd, capture_output=True, env=env, cwd=work)
    if r.returncode:
        print("# " + r.stderr.decode(errors="replace").strip()[-400:])
        return None, ""
    return r.stdout, r.stderr.decode(errors="replace")


def cached_frames(verbose):
    m = re.search(r"static layer cached in (\d+) frames \(drawn (\d+) time", verbose)
    return (int(m.group(1)), int(m.group(2))) if m else (0, 0)


def appended_frames(verbose):
    m = re.search(r"settled chart curves appended to it in (\d+) frames", verbose)
    return int(m.group(1)) if m else 0


def unchanged_items(verbose):
    m = re.search(r"dynamic items left as the last frame drew them: (\d+)", verbose)
    return int(m.group(1)) if m else 0


def first_difference(a, b, w, h):
    n = w * h * 4
    for f in range(min(len(a), len(b)) // n):
        if a[f * n:(f + 1) * n] != b[f * n:(f + 1) * n]:
            p = next(i for i in range(f * n, (f + 1) * n) if a[i] != b[i]) - f * n
            return f"frame {f}, pixel ({p // 4 % w}, {p // 4 // w})"
    return "lengths differ" if len(a) != len(b) else None


SHORT = ["--set", "video.duration=1.5", "--fps", "8"]
ALONE = ["--set", "view.panels=none", "--set", "view.hud=false", "--set", "view.colorbar=false"]
CASES = [
    ("default.ini", "320x240", []),
    ("default.ini", "1280x720", []),
    ("resonance.ini", "640x360", []),
    ("resonance.ini", "1080x1920", []),
    ("resonance.ini", "854x480", ["--set", "view.theme=light", "--set", "view.background=transparent"]),
    ("resonance.ini", "1024x768", ["--set", "view.trail=all"]),
    ("chaotic.ini", "800x800", ["--set", "view.panels=poincare,phase", "--set", "video.duration=12",
                                "--fps", "2", "--set", "view.title=Chaos"]),
    # 500 frames: more samples than the charts' pixel columns, so their
    # curves are thinned (by fixed time bins) while they are appended
    ("default.ini", "480x270", ["--set", "video.duration=20", "--fps", "25"]),
    # the pendulum alone: no static item, the cache is the background (and
    # the long exposure), restored where the last frame drew
    ("default.ini", "640x360", ALONE),
    ("chaotic.ini", "640x360", ALONE + ["--set", "video.duration=12", "--fps", "4"]),
]
for scene, size, extra in CASES:
    w, h = map(int, size.split("x"))
    args = SHORT + extra if "video.duration=20" not in extra else extra
    a, verbose = raw(scene, size, args, True)
    b, _ = raw(scene, size, args, False)
    what = f"{scene} {size} {' '.join(extra[1::2]) or 'as shipped'}"
    if not ok(a is not None and b is not None, f"{what}: rendered with and without the cache"):
        continue
    diff = first_difference(a, b, w, h)
    if diff:
        print(f"# first difference: {diff}")
    ok(diff is None and len(a) > 0, f"{what}: {len(a) // (w * h * 4)} frames identical to the uncached ones")
    used, drawn = cached_frames(verbose)
    print(f"# cache used in {used} frames, drawn {drawn} times")
    if size != "320x240":  # there the labels sit too close to the data to prove the order
        ok(used > 0, f"{what}: the cache was used")
    frames = len(a) // (w * h * 4)
    if size != "320x240" and "chaotic" not in scene and "view.panels=none" not in extra:
        # the charts' curves, appended
        grown = appended_frames(verbose)
        # drawn once: every frame's growth was appended, never redrawn (a
        # frame with no new time bin appends nothing)
        ok(grown > frames // 2 and drawn == 1,
           f"{what}: the cache drawn once, the charts' settled curves appended to it in {grown} "
           f"of {frames} frames")

# resonance.ini's phase portraits fade in steps of 1/6 s: between steps
# their faded part is left as the last frame drew it, redrawn only where
# something else changed; 30 fps, so most frames fall between steps
w, h = 640, 360
args = ["--set", "video.duration=2", "--fps", "30"]
a, verbose = raw("resonance.ini", f"{w}x{h}", args, True)
b, _ = raw("resonance.ini", f"{w}x{h}", args, False)
kept_items = unchanged_items(verbose)
ok(a is not None and a == b and kept_items > 30,
   f"resonance.ini 640x360 at 30 fps: frames identical to the uncached ones, {kept_items} "
   f"dynamic items left as the last frame drew them")

# a tiny frame whose energy chart is squeezed flat (its legend sits on the
# data): still byte-identical, and still cached (a static legend there
# turned every frame uncached)
w, h = 321, 239
args = ["--set", "view.panels=all", "--set", "video.duration=3", "--fps", "30"]
a, verbose = raw("resonance.ini", f"{w}x{h}", args, True)
b, _ = raw("resonance.ini", f"{w}x{h}", args, False)
used, drawn = cached_frames(verbose)
frames = len(a) // (w * h * 4) if a else 0
ok(a is not None and a == b and used >= frames - 4,
   f"resonance.ini 321x239, all panels: {frames} frames identical to the uncached ones, "
   f"{used} of them cached")

# the small frame: chaotic.ini at 320x180 with every panel, where
# curves, legends, panel edges and the HUD touch each other (a settled curve
# under a static panel under another settled curve; static text on curves).
# Those items are drawn with the dynamic layer and the rest stays cached:
# every frame cached, byte-identical, the curves appended (every frame was
# drawn uncached before, its cost growing with the curves' length).
w, h = 320, 180
args = ["--set", "view.panels=all", "--set", "video.duration=40", "--fps", "10"]
a, verbose = raw("chaotic.ini", f"{w}x{h}", args, True)
b, _ = raw("chaotic.ini", f"{w}x{h}", args, False)
used, drawn = cached_frames(verbose)
frames = len(a) // (w * h * 4) if a else 0
diff = first_difference(a, b, w, h) if a and b else "not rendered"
if diff:
    print(f"# first difference: {diff}")
ok(a is not None and diff is None and frames == 400 and used == frames
   and appended_frames(verbose) > frames // 4,
   f"chaotic.ini 320x180, all panels, 40 s: {frames} frames identical to the uncached ones, "
   f"{used} cached (cache drawn {drawn} times, curves appended in {appended_frames(verbose)})")

# frames of a cached video against stills at the same times (a still with
# the video's marks of now: view.cursor = true)
w, h, fps = 640, 360, 8
a, _ = raw("resonance.ini", f"{w}x{h}", SHORT, True)
if ok(a is not None, "resonance.ini 640x360 video for the stills"):
    for k in (0, 5, 11):
        png = os.path.join(work, f"still{k}.png")
        r = subprocess.run([exe, "still", os.path.join(scenes, "resonance.ini"), "--size", f"{w}x{h}",
                            "--fps", str(fps), "--set", "video.duration=1.5", "--at", str(k / fps),
                            "--set", "view.cursor=true", "-q", "-o", png], capture_output=True, cwd=work)
        frame = a[k * w * h * 4:(k + 1) * w * h * 4]
        got = None
        if r.returncode == 0:
            got = subprocess.run(["ffmpeg", "-v", "error", "-i", png, "-f", "rawvideo", "-pix_fmt",
                                  "rgba", "-"], capture_output=True).stdout \
                if shutil.which("ffmpeg") else None
        if got is None:
            print("# skipped: no ffmpeg to decode the still" if r.returncode == 0 else
                  "# " + r.stderr.decode(errors="replace").strip())
        ok(got is None and r.returncode == 0 or got == frame,
           f"video frame {k} (cached) equals the still at t = {k / fps:g} s")

# the last frame of a long video, its charts thinned, against a still
w, h, fps, n = 480, 270, 25, 500
a, _ = raw("default.ini", f"{w}x{h}", ["--set", "video.duration=20", "--fps", str(fps)], True)
png = os.path.join(work, "still_long.png")
r = subprocess.run([exe, "still", os.path.join(scenes, "default.ini"), "--size", f"{w}x{h}", "--fps",
                    str(fps), "--set", "video.duration=20", "--at", str((n - 1) / fps),
                    "--set", "view.cursor=true", "-q", "-o", png],
                   capture_output=True, cwd=work)
got = subprocess.run(["ffmpeg", "-v", "error", "-i", png, "-f", "rawvideo", "-pix_fmt", "rgba", "-"],
                     capture_output=True).stdout if r.returncode == 0 and shutil.which("ffmpeg") else None
ok(a is not None and (got is None and r.returncode == 0 or got == a[(n - 1) * w * h * 4:n * w * h * 4]),
   f"default.ini 20 s: the last video frame (cached, charts thinned) equals the still at "
   f"t = {(n - 1) / fps:g} s")

# the EGL backend, where it can make a context here
probe = subprocess.run([exe, "still", os.path.join(scenes, "default.ini"), "--gl", "egl", "--size",
                        "64x48", "-q", "-o", os.path.join(work, "egl.png")], capture_output=True)
if probe.returncode == 0:
    a, verbose = raw("resonance.ini", "640x360", SHORT, True, gl="egl")
    b, _ = raw("resonance.ini", "640x360", SHORT, False, gl="egl")
    ok(a is not None and a == b and cached_frames(verbose)[0] > 0,
       "EGL: resonance.ini 640x360 cached frames identical to uncached ones")
else:
    print("# EGL unavailable here: " + probe.stderr.decode(errors="replace").strip()[-200:])
done()
