#!/usr/bin/env python3
"""springpend tests: the renderer's YUV pass. Frames written as raw YUV 4:2:0
(--format yuv420p, what MP4 and WebM get from the GPU) against a numpy
reference computed here from the same frames in RGBA (--format raw): the
BT.709 limited-range matrix, chroma sited left ([1, 2, 1]/4 across, two rows
averaged), within one level; sizes whose half width is no multiple of 4;
the MP4's colour tags (ffprobe); the same bytes on every run.
usage: test_yuv.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)
Skips without numpy (needs ffprobe for the tags)."""
import os
import re
import shutil
import subprocess
import sys

from sptest import done, need_scipy, ok, runner, skip

need_scipy()
import numpy as np  # noqa: E402

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "yuv"))
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
run = runner(exe, work)
scenes = os.path.join(src, "..", "scenes")


def reference(rgba):
    """Y, Cb, Cr planes (float levels) of frames (n, H, W, 4) uint8."""
    c = rgba[..., :3].astype(np.float64) / 255
    k = np.array([0.2126, 0.7152, 0.0722])
    y = 16 + 219 * (c @ k)
    p = np.pad(c, ((0, 0), (0, 0), (1, 0), (0, 0)), mode="edge")  # column -1 = column 0
    h = (p[:, :, 0:-1:2] + 2 * p[:, :, 1::2] + p[:, :, 2::2]) / 4  # columns 2i-1, 2i, 2i+1
    v = (h[:, 0::2] + h[:, 1::2]) / 2
    yv = v @ k
    return y, 128 + 224 * (v[..., 2] - yv) / 1.8556, 128 + 224 * (v[..., 0] - yv) / 1.5748


def planes(data, n, w, h):
    """I420 bytes (Y, then Cb, then Cr) as three arrays of n frames."""
    f = np.frombuffer(data, np.uint8).reshape(n, w * h * 3 // 2)
    q = w * h // 4
    return (f[:, :w * h].reshape(n, h, w), f[:, w * h:w * h + q].reshape(n, h // 2, w // 2),
            f[:, w * h + q:].reshape(n, h // 2, w // 2))


CASES = [("default.ini", 160, 120, []),
         ("resonance.ini", 322, 180, ["--set", "view.panels=all"]),
         ("chaotic.ini", 854, 480, ["--set", "view.trail=all"])]
for name, w, h, extra in CASES:
    args = ["render", os.path.join(scenes, name), "--size", f"{w}x{h}", "--fps", "10",
            "--set", "video.duration=1.5", "-q", *extra]
    a = run(*args, "--format", "raw", "-o", "f.rgba")
    b = run(*args, "-o", "f.yuv")
    if a.returncode or b.returncode:
        ok(False, f"{name} {w}x{h}: raw and yuv420p render ({a.stderr[-200:]} {b.stderr[-200:]})")
        continue
    rgba = np.fromfile(os.path.join(work, "f.rgba"), np.uint8)
    n = rgba.size // (w * h * 4)
    data = open(os.path.join(work, "f.yuv"), "rb").read()
    ok(n == 15 and len(data) == n * w * h * 3 // 2,
       f"{name} {w}x{h}: {n} frames, {len(data)} bytes of YUV = 1.5 a pixel")
    if len(data) != n * w * h * 3 // 2:
        continue
    got = planes(data, n, w, h)
    ref = reference(rgba.reshape(n, h, w, 4))
    for what, g, r in zip(("Y", "Cb", "Cr"), got, ref):
        d = np.abs(g.astype(np.float64) - r)
        ok(d.max() <= 1.0 and np.mean(g != np.round(r)) < 1e-3,
           f"{name} {w}x{h}: {what} within one level of the BT.709 reference "
           f"(largest {d.max():.3f}; {np.mean(g != np.round(r)):.2e} not the nearest level)")
    # the picture is really there: not a constant plane
    ok(got[0].std() > 1 and got[1].std() > 0.1,
       f"{name} {w}x{h}: the planes show the picture (Y spread {got[0].std():.1f})")

# MP4: tagged BT.709, limited (tv) range, chroma sited left; same bytes twice.
args = ["render", os.path.join(scenes, "default.ini"), "--size", "320x180", "--fps", "15",
        "--set", "video.duration=1", "-q"]
r1, r2 = run(*args, "-o", "a.mp4"), run(*args, "-o", "b.mp4")
if shutil.which("ffprobe") and not r1.returncode:
    p = subprocess.run(["ffprobe", "-v", "error", "-show_entries",
                        "stream=pix_fmt,color_range,color_space,color_transfer,color_primaries,"
                        "chroma_location", "-of", "default=nw=1", os.path.join(work, "a.mp4")],
                       capture_output=True, text=True).stdout.split()
    tags = dict(kv.split("=") for kv in p)
    ok(tags == {"pix_fmt": "yuv420p", "color_range": "tv", "color_space": "bt709",
                "color_transfer": "bt709", "color_primaries": "bt709", "chroma_location": "left"},
       f"MP4 colour tags: {tags}")
else:
    skip("MP4 colour tags", "no ffprobe" if r1.returncode == 0 else r1.stderr[-200:])
mp4 = open(os.path.join(work, "a.mp4"), "rb").read() if r1.returncode == 0 else b""
ok(r2.returncode == 0 and mp4 == open(os.path.join(work, "b.mp4"), "rb").read(),
   "MP4 from the YUV pass: the same bytes on two runs")
# x264 as doc/performance.md says: four slices of each frame at once, whatever the
# core count (x264 writes its settings into the stream; it takes fewer for
# a frame of few macroblock rows: 3 at 180 px)
m = re.search(rb"threads=(\d+) lookahead_threads=\d+ sliced_threads=(\d)", mp4)
ok(m and 1 <= int(m.group(1)) <= 4 and m.group(2) == b"1",
   f"x264 encodes with up to 4 sliced threads ({m.group(0).decode() if m else 'no settings'})")

# Odd sizes and alpha are refused before any file appears.
r = run("render", os.path.join(scenes, "default.ini"), "--size", "161x120", "-q", "-o", "odd.yuv")
ok(r.returncode == 2 and "even width and height" in r.stderr
   and not os.path.exists(os.path.join(work, "odd.yuv")),
   f"yuv420p at 161x120: exit 2, says even, no file ({r.returncode}: {r.stderr.strip()[-120:]})")
r = run("render", os.path.join(scenes, "default.ini"), "--size", "160x120", "-q",
        "--set", "view.background=transparent", "-o", "alpha.yuv")
ok(r.returncode == 2 and "no alpha" in r.stderr
   and not os.path.exists(os.path.join(work, "alpha.yuv")),
   f"yuv420p with a transparent background: exit 2, no file ({r.stderr.strip()[-120:]})")
done()
