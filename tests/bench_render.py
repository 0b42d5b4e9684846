#!/usr/bin/env python3
"""springpend benchmark: the default scene, 1080p60, 10 s of video (600
frames), side by side with the encoder floor, ffmpeg's PNG writer and the
matplotlib peer. Prints a Markdown table: wall time, fps, CPU time (user +
sys, the process and the children it waited for) and peak memory (maximum
RSS, from wait4). On a busy machine the wall times swell; CPU times much less.
usage: bench_render.py SPRINGPEND SCENE [WORK_DIR] [--quick]
  --quick: 2 s of video instead of 10 (and 12 s instead of 60 for memory).
Raw frames for the floor are kept in WORK_DIR (default: /dev/shm when it
has room, so that ffmpeg reads them from memory)."""
import os
import shutil
import subprocess
import sys
import tempfile
import time

args = [a for a in sys.argv[1:] if not a.startswith("--")]
quick = "--quick" in sys.argv
exe, scene = os.path.abspath(args[0]), os.path.abspath(args[1])
W, H, FPS = 1920, 1080, 60
SECONDS = 2 if quick else 10
N = SECONDS * FPS
PEER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared",
                    "peers", "mpl_peer.py")
PEER = os.environ.get("SP_MPL_PEER", PEER)


def pick_dir():
    if len(args) > 2:
        return args[2]
    need = N * W * H * 4 * 1.2
    for d in ("/dev/shm", tempfile.gettempdir()):
        try:
            st = os.statvfs(d)
            if st.f_bavail * st.f_frsize > need:
                return d
        except OSError:
            pass
    return tempfile.gettempdir()


work = tempfile.mkdtemp(prefix="springpend-bench-", dir=pick_dir())
rows = []


def measure(label, cmd, stdout=None, stdin=None, size_of=None):
    """Runs cmd once; returns (wall s, peak RSS MiB, CPU s) and records a row."""
    t0 = time.monotonic()
    p = subprocess.Popen(cmd, stdout=stdout or subprocess.DEVNULL, stdin=stdin,
                         stderr=subprocess.PIPE, cwd=work)
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.monotonic() - t0
    err = p.stderr.read().decode()
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        print(f"# {label} failed ({p.returncode}): {err.strip()[-300:]}", file=sys.stderr)
        rows.append((label, None, None, None, None))
        return None
    mib = ru.ru_maxrss / 1024
    cpu = ru.ru_utime + ru.ru_stime
    if size_of:
        d = os.path.join(work, size_of)
        mb = sum(os.path.getsize(os.path.join(d, f)) for f in os.listdir(d)) / 1e6
        label += f", {mb:.0f} MB"
        shutil.rmtree(d)
    rows.append((label, wall, N / wall, mib, cpu))
    print(f"# {label}: {wall:.2f} s, CPU {cpu:.2f} s, {mib:.0f} MiB", file=sys.stderr,
          flush=True)
    return wall, mib, cpu


base = [exe, "render", scene, "--quality", "high", "--set", f"video.duration={SECONDS}", "-q"]
try:
    sp_mp4 = measure("springpend -> MP4 (defaults: CRF 23, preset superfast)",
                     base + ["-o", "sp.mp4"])
    sp_med = measure("springpend -> MP4 (preset medium, as the peer)",
                     base + ["--set", "video.preset=medium", "-o", "sp_medium.mp4"])
    raw = os.path.join(work, "frames.rgba")
    with open(raw, "wb") as f:
        measure("springpend -> raw RGBA (to a file in memory)", base + ["--format", "raw", "-o", "-"],
                stdout=f)
    ff_in = ["ffmpeg", "-v", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgba",
             "-s", f"{W}x{H}", "-r", str(FPS), "-i", raw]
    floor = measure("encoder floor: ffmpeg raw -> MP4, CRF 23 superfast",
                    ff_in + ["-c:v", "libx264", "-preset", "superfast", "-crf", "23",
                             "-pix_fmt", "yuv420p", "-colorspace", "bt709",
                             "-movflags", "+faststart", "floor.mp4"])
    for d in ("sp_png", "ff_png", "ff_png_default"):
        os.makedirs(os.path.join(work, d))
    sp_png = measure("springpend -> PNG sequence (its default: level 5, filter up)",
                     base + ["-o", "sp_png/%04d.png"], size_of="sp_png")
    ff_png = measure("ffmpeg raw -> PNG sequence (zlib 1, filter up)",
                     ff_in + ["-compression_level", "1", "-pred", "up", "ff_png/%04d.png"],
                     size_of="ff_png")
    ff_png_default = measure("ffmpeg raw -> PNG sequence (ffmpeg's defaults)",
                             ff_in + ["ff_png_default/%04d.png"], size_of="ff_png_default")
    os.remove(raw)
    with open(os.devnull, "wb") as f:
        measure("springpend -> raw RGBA (to /dev/null)", base + ["--format", "raw", "-o", "-"],
                stdout=f)
    peer = None
    if subprocess.run(["/usr/bin/python3", "-c", "import matplotlib"],
                      capture_output=True).returncode == 0 and os.path.exists(PEER):
        peer = measure("matplotlib + FFMpegWriter peer (its defaults: preset medium)",
                       ["/usr/bin/python3", PEER, str(SECONDS), str(FPS), str(W), str(H),
                        "peer.mp4"])
    short_s, long_s = (2, 12) if quick else (5, 60)
    mem = []
    for s in (short_s, long_s):
        mem.append(measure(f"springpend -> MP4, {s} s of video (memory)",
                           [exe, "render", scene, "--quality", "high",
                            "--set", f"video.duration={s}", "-q", "-o", f"mem{s}.mp4"]))
    # fps for the memory rows counts their own frames
    for i, s in enumerate((short_s, long_s)):
        lab, wall, _, mib, cpu = rows[-2 + i]
        rows[-2 + i] = (lab, wall, s * FPS / wall if wall else None, mib, cpu)
finally:
    shutil.rmtree(work, ignore_errors=True)

print(f"| run ({W}x{H}@{FPS}, {N} frames unless said) | wall s | fps | CPU s | peak RSS MiB |")
print("|---|---:|---:|---:|---:|")
for label, wall, fps, mib, cpu in rows:
    if wall is None:
        print(f"| {label} | failed | | | |")
    else:
        print(f"| {label} | {wall:.2f} | {fps:.1f} | {cpu:.2f} | {mib:.0f} |")
print()


def ratio(what, a, b, goal):
    if a and b:
        print(f"{what}: {a[0] / b[0]:.2f}x wall, {a[2] / b[2]:.2f}x CPU ({goal})")


ratio("springpend MP4 / encoder floor, equal settings", sp_mp4, floor, "goal <= 1.15x")
ratio("matplotlib peer / springpend defaults", peer, sp_mp4, "goal >= 1.7x")
ratio("ffmpeg PNG / springpend PNG, equal compression", ff_png, sp_png, "goal >= 2x")
ratio("ffmpeg PNG at its defaults / springpend PNG at its defaults", ff_png_default, sp_png,
      "for reference")
if all(mem):
    print(f"peak memory, {long_s} s / {short_s} s of video: {mem[1][1] / mem[0][1]:.3f} "
          f"(goal <= 1.10)")
print(f"machine: {os.cpu_count()} cores, load average before: "
      f"{open('/proc/loadavg').read().split()[0]}")
