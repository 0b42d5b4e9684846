#!/usr/bin/env python3
"""springpend tests: frame times and counts in the files, read back with
ffprobe. Fractional frame rates (29.97, 23.976 and 30000/1001 fps): the
stream's frame rate is the scene's fps as a fraction, and frame k's time
stamp is k / fps within 0.1 ms (MP4) or 0.5 ms (WebM, whole ms) (a time base rounded to whole fps passed at 30 and 60 fps).
Durations not exact in binary: 4.6 s at 25 fps is 115 frames, in MP4, WebM,
GIF and a PNG sequence (a truncated count gives 114). GIF keeps every frame
up to 50 fps and every other one above (doc/outputs.md's rule).
usage: test_timing.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import os
import shutil
import subprocess
import sys
from fractions import Fraction

from sptest import diag, done, ok, sets

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "timing"))
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
DEFAULT = os.path.join(src, "..", "scenes", "default.ini")
if not shutil.which("ffprobe"):
    print("1..0 # SKIP ffprobe (Debian's ffmpeg) is not installed")
    sys.exit(77)
SMALL = {"video.width": 96, "video.height": 64, "view.panels": "none", "view.hud": "false"}


def probe(name):
    """ffprobe's view of the first video stream and its frames' time stamps."""
    r = subprocess.run(["ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries",
                        "stream=r_frame_rate,avg_frame_rate,time_base,nb_frames:frame=pts_time,"
                        "best_effort_timestamp_time", "-show_frames", "-of", "json",
                        os.path.join(work, name)], capture_output=True, text=True)
    try:
        j = json.loads(r.stdout)
    except ValueError:
        return {}, []
    times = [float(f.get("pts_time", f.get("best_effort_timestamp_time", "nan")))
             for f in j.get("frames", [])]
    return (j.get("streams") or [{}])[0], times


# LeakSanitizer's tracer sometimes dies during a VP9 encode's threads ("fatal
# error", test_safety.py has the same): no leak check for these renders in a
# sanitizer build (leaks are the valgrind test's and the other tests' job).
asan = os.environ.get("ASAN_OPTIONS", "")
env = dict(os.environ, ASAN_OPTIONS=(asan + ":" if asan else "") + "detect_leaks=0")


def render(name, d, *extra):
    r = subprocess.run([exe, "render", DEFAULT, "-q", "-o", name, *sets({**SMALL, **d}), *extra],
                       capture_output=True, text=True, cwd=work, env=env)
    if r.returncode:
        diag(f"{name}: exit {r.returncode}\n{r.stderr[-600:]}")
    return r.returncode == 0


# ---- fractional frame rates ---------------------------------------------------
for fps, want, ext in (("29.97", Fraction(2997, 100), "mp4"), ("23.976", Fraction(2997, 125), "mp4"),
                       ("29.97002997002997", Fraction(30000, 1001), "mp4"),
                       ("29.97", Fraction(2997, 100), "webm")):
    n = 45
    name = f"fps{fps[:6]}.{ext}"
    good = render(name, {"video.fps": fps, "video.duration": float(n / want)})
    st, times = probe(name) if good else ({}, [])
    rate = Fraction(st.get("avg_frame_rate", "0/1"))
    worst = max((abs(t - k / float(want)) for k, t in enumerate(times)), default=1)
    allowed = 0.1e-3 if ext == "mp4" else 0.5e-3 + 1e-9  # Matroska counts whole ms
    ok(good and len(times) == n and abs(rate - want) <= want * Fraction(1, 10 ** 6) and worst < allowed,
       f"{ext} at {fps} fps: {len(times)} of {n} frames, rate {rate} (want {want}), frame k "
       f"at k/fps within {worst * 1e3:.3f} ms ({allowed * 1e3:.1f} ms allowed)")

# ---- durations not exact in binary: 4.6 s at 25 fps = 115 frames -----------
d = {"video.fps": 25, "video.duration": 4.6}
for ext in ("mp4", "webm", "gif"):
    good = render(f"d46.{ext}", d)
    st, times = probe(f"d46.{ext}") if good else ({}, [])
    ok(len(times) == 115, f"4.6 s at 25 fps as {ext}: {len(times)} frames (115)")
good = render("seq/%03d.png", d)
pngs = sorted(os.listdir(os.path.join(work, "seq"))) if good else []
ok(len(pngs) == 115 and pngs[0] == "000.png" and pngs[-1] == "114.png",
   f"4.6 s at 25 fps as PNGs: {len(pngs)} files, 000 to {pngs[-1] if pngs else '-'}")
r = subprocess.run([exe, "render", DEFAULT, "--format", "raw", "-o", "-",
                    *sets({**SMALL, **d})], capture_output=True, cwd=work, env=env)
ok(len(r.stdout) == 115 * 96 * 64 * 4, f"4.6 s at 25 fps raw: {len(r.stdout) // (96 * 64 * 4)} frames")
# 0.7 s at 30 fps (21 frames) and 2.3 s at speed 0.1 at 10 fps (230)
for dur, fps, speed, want in ((0.7, 30, 1, 21), (2.3, 10, 0.1, 230)):
    good = render(f"d{dur}.mp4", {"video.fps": fps, "video.duration": dur, "video.speed": speed})
    st, times = probe(f"d{dur}.mp4") if good else ({}, [])
    ok(len(times) == want, f"{dur} s at {fps} fps, speed {speed}: {len(times)} frames ({want})")

# ---- GIF: every frame up to 50 fps, every other one above --------------------
for fps, n, kept, rate in ((50, 50, 50, 50), (60, 60, 30, 30), (100, 100, 50, 50)):
    good = render(f"g{fps}.gif", {"video.fps": fps, "video.duration": 1})
    st, times = probe(f"g{fps}.gif") if good else ({}, [])
    step = (times[-1] - times[0]) / (len(times) - 1) if len(times) > 1 else 0
    ok(len(times) == kept and abs(step - 1 / rate) < 0.006,
       f"GIF at {fps} fps: {len(times)} of {n} frames kept ({kept}), {step * 1e3:.0f} ms apart "
       f"(GIF's 10 ms steps; want {1e3 / rate:.0f})")
done()
