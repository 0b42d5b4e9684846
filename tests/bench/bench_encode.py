#!/usr/bin/env python3
"""springpend benchmark: a scene to MP4 against ffmpeg's own encode of the
same frames (issue 25's floor). For each scene and size: springpend renders
the frames once as raw RGBA into memory (/dev/shm); then, alternating,
`springpend render SCENE -o x.mp4` and `ffmpeg -f rawvideo -pix_fmt rgba ...
-c:v libx264 -preset superfast -crf 23 -pix_fmt yuv420p` (ffmpeg's own
colour conversion and thread count), each REPEAT times. Prints a Markdown
table: least wall and CPU time (user + sys of the process and its threads,
the steadier figure on a shared machine), largest peak RSS, and the ratios
springpend / ffmpeg. The x264 threads of both are their own choice.
usage: bench_encode.py SPRINGPEND SCENES_DIR [--repeat=N] [--seconds=S]
                       [--case=SCENE@WxH ...]
  default cases: default.ini and resonance.ini at 1920x1080, default.ini at
  3840x2160; 60 fps, --seconds of video (default 5)."""
import os
import subprocess
import sys
import tempfile
import time

if sys.argv[1:2] in (["-h"], ["--help"]):
    sys.exit(print(__doc__))
if len([a for a in sys.argv[1:] if not a.startswith("--")]) < 2:
    print(__doc__, file=sys.stderr)
    sys.exit(2)
args = [a for a in sys.argv[1:] if not a.startswith("--")]
opt = {a.split("=")[0]: a.split("=", 1)[1] for a in sys.argv[1:] if a.startswith("--") and "=" in a}
exe, scenes = os.path.abspath(args[0]), os.path.abspath(args[1])
REPEAT = int(opt.get("--repeat", 3))
SECONDS = float(opt.get("--seconds", 5))
cases = [a.split("=", 1)[1] for a in sys.argv[1:] if a.startswith("--case=")] or \
    ["default.ini@1920x1080", "resonance.ini@1920x1080", "default.ini@3840x2160"]
work = tempfile.mkdtemp(prefix="springpend-bench-",
                        dir="/dev/shm" if os.path.isdir("/dev/shm") else None)


def run(cmd, stdout=None):
    """(wall s, CPU s, peak RSS MiB) of cmd, which must succeed."""
    t0 = time.monotonic()
    p = subprocess.Popen(cmd, stdout=stdout or subprocess.DEVNULL, stderr=subprocess.PIPE, cwd=work)
    err = p.stderr.read()
    _, status, ru = os.wait4(p.pid, 0)
    if os.waitstatus_to_exitcode(status):
        sys.exit(f"failed: {' '.join(cmd)}: {err.decode()[-400:]}")
    return time.monotonic() - t0, ru.ru_utime + ru.ru_stime, ru.ru_maxrss / 1024


print("| scene, size | springpend wall s | CPU s | RSS MiB | ffmpeg wall s | CPU s | RSS MiB "
      "| wall × | CPU × | RSS × |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for case in cases:
    name, size = case.split("@")
    scene = os.path.join(scenes, name)
    common = [exe, "render", scene, "--size", size, "--fps", "60",
              "--set", f"video.duration={SECONDS:g}", "-q"]
    raw = os.path.join(work, "frames.rgba")
    with open(raw, "wb") as f:
        run(common + ["--format", "raw", "-o", "-"], stdout=f)
    sp = ff = None
    for _ in range(REPEAT):
        a = run(common + ["-o", os.path.join(work, "sp.mp4")])
        b = run(["ffmpeg", "-v", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgba", "-s", size,
                 "-r", "60", "-i", raw, "-c:v", "libx264", "-preset", "superfast", "-crf", "23",
                 "-pix_fmt", "yuv420p", "-colorspace", "bt709", "-movflags", "+faststart",
                 os.path.join(work, "ff.mp4")])
        sp = a if not sp else (min(sp[0], a[0]), min(sp[1], a[1]), max(sp[2], a[2]))
        ff = b if not ff else (min(ff[0], b[0]), min(ff[1], b[1]), max(ff[2], b[2]))
        print(f"# {case}: springpend {a[0]:.2f} s, CPU {a[1]:.2f} s, {a[2]:.0f} MiB; "
              f"ffmpeg {b[0]:.2f} s, CPU {b[1]:.2f} s, {b[2]:.0f} MiB", file=sys.stderr, flush=True)
    os.remove(raw)
    print(f"| {name} {size} | {sp[0]:.2f} | {sp[1]:.2f} | {sp[2]:.0f} | {ff[0]:.2f} | {ff[1]:.2f} "
          f"| {ff[2]:.0f} | {sp[0] / ff[0]:.2f} | {sp[1] / ff[1]:.2f} | {sp[2] / ff[2]:.2f} |",
          flush=True)
for f in os.listdir(work):
    os.remove(os.path.join(work, f))
os.rmdir(work)
