#!/usr/bin/env python3
"""springpend benchmark: the default scene, 1080p60, 10 s of video (600
frames), side by side with the encoder floor, ffmpeg's PNG writer and the
matplotlib peer. Prints a Markdown table: wall time, fps, CPU time (user +
sys, the process and the children it waited for) and peak memory (maximum
RSS, from wait4). On a busy machine the wall times swell; CPU times much less.
Then the scenes users render (default.ini as shipped, resonance.ini with
all panels), each against the encoder floor for its own frames, and their
--verbose stage times: the GL draw per frame with panels against the
pendulum alone, with the static cache and without (SPRINGPEND_DRAW_CACHE=0).
usage: bench_render.py SPRINGPEND SCENE [WORK_DIR] [--quick] [--repeat=N]
                       [--scenes-only] [--size=WxH] [--scene-seconds=S]
  --quick: 2 s of video instead of 10 (and 12 s instead of 60 for memory).
  --repeat=N: run each comparison N times (default 3) and keep the best.
  --scenes-only: only the scenes' part; --size: its frame size (default
  1920x1080, 60 fps); --scene-seconds: its video length (default 5).
Raw frames for the floor are kept in WORK_DIR (default: /dev/shm when it
has room, so that ffmpeg reads them from memory)."""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

args = [a for a in sys.argv[1:] if not a.startswith("--")]
quick = "--quick" in sys.argv
REPEAT = int(next((a.split("=")[1] for a in sys.argv if a.startswith("--repeat=")), 3))
if "-h" in sys.argv or "--help" in sys.argv:
    print(__doc__)
    sys.exit(0)
if len(args) < 2:
    sys.exit(__doc__.split("usage: ")[1].split("\n")[0].join(("usage: ", "")))
exe, scene = os.path.abspath(args[0]), os.path.abspath(args[1])
SCENES_ONLY = "--scenes-only" in sys.argv
SW, SH = map(int, next((a.split("=")[1] for a in sys.argv if a.startswith("--size=")),
                       "1920x1080").split("x"))
SCENE_S = float(next((a.split("=")[1] for a in sys.argv if a.startswith("--scene-seconds=")),
                     2 if quick else 5))
W, H, FPS = 1920, 1080, 60
SECONDS = 2 if quick else 10
N = SECONDS * FPS
PEER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "shared",
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


def measure(label, cmd, stdout_path=None, out_dir=None, repeat=None, env=None, frames=None):
    """Runs cmd `repeat` times (default REPEAT); records a row with the least
    wall and CPU time (the runs the machine disturbed least) and the largest
    peak RSS, and returns (wall s, peak RSS MiB, CPU s). stdout goes to
    stdout_path (else nowhere); out_dir is made empty before each run, and
    the size of what the last run left there joins the label."""
    best = None
    for _ in range(repeat or REPEAT):
        if out_dir:
            shutil.rmtree(os.path.join(work, out_dir), ignore_errors=True)
            os.makedirs(os.path.join(work, out_dir))
        with open(stdout_path or os.devnull, "wb") as out:
            t0 = time.monotonic()
            p = subprocess.Popen(cmd, stdout=out, stderr=subprocess.PIPE, cwd=work,
                                 env=dict(os.environ, **(env or {})))
            err = p.stderr.read().decode()
            _, status, ru = os.wait4(p.pid, 0)
            wall = time.monotonic() - t0
        if os.waitstatus_to_exitcode(status) != 0:
            print(f"# {label} failed: {err.strip()[-300:]}", file=sys.stderr)
            rows.append((label, None, None, None, None))
            return None
        run = (wall, ru.ru_maxrss / 1024, ru.ru_utime + ru.ru_stime)
        best = run if not best else (min(best[0], run[0]), max(best[1], run[1]),
                                     min(best[2], run[2]))
    if out_dir:
        d = os.path.join(work, out_dir)
        label += f", {sum(os.path.getsize(os.path.join(d, f)) for f in os.listdir(d)) / 1e6:.0f} MB"
        shutil.rmtree(d)
    wall, mib, cpu = best
    rows.append((label, wall, (frames or N) / wall, mib, cpu))
    print(f"# {label}: {wall:.2f} s, CPU {cpu:.2f} s, {mib:.0f} MiB", file=sys.stderr,
          flush=True)
    return best


# The pendulum alone, as the matplotlib peer draws it (default.ini also shows
# charts and text, which cost mostly encoder time).
ALONE = ["--set", "view.panels=none", "--set", "view.hud=false", "--set", "view.colorbar=false"]
base = [exe, "render", scene, "--quality", "high", "--set", f"video.duration={SECONDS}", "-q", *ALONE]
SCENES = [os.path.join(os.path.dirname(scene), n) for n in ("default.ini", "resonance.ini")]
scene_rows = []   # (scene, MP4 run, floor run)
stage_rows = []   # (label, compose ms, GL draw ms, per frame)


def stages(label, cmd, env=None, repeat=None):
    """Runs cmd with --verbose `repeat` times; keeps the least compose and
    GL draw ms per frame."""
    best = None
    for _ in range(repeat or REPEAT):
        r = subprocess.run(cmd + ["--verbose"], capture_output=True, text=True, cwd=work,
                           env=dict(os.environ, **(env or {})))
        comp = re.search(r"compose draw list\s+[\d.]+\s+([\d.]+)", r.stderr)
        draw = re.search(r"GL draw \+ readback\s+[\d.]+\s+([\d.]+)", r.stderr)
        if r.returncode or not draw:
            print(f"# {label} failed: {r.stderr.strip()[-300:]}", file=sys.stderr)
            return None
        got = (float(comp.group(1)) if comp else 0.0, float(draw.group(1)))
        best = got if not best else (min(best[0], got[0]), min(best[1], got[1]))
    stage_rows.append((label, *best))
    print(f"# {label}: compose {best[0]:.2f} ms, GL draw {best[1]:.2f} ms per frame",
          file=sys.stderr, flush=True)
    return best


def scenes_part():
    n = int(round(SCENE_S * FPS))
    size = ["--size", f"{SW}x{SH}", "--fps", str(FPS), "--set", f"video.duration={SCENE_S:g}", "-q"]
    for sc in SCENES:
        name = os.path.basename(sc)
        cmd = [exe, "render", sc, *size]
        mp4 = measure(f"{name}: springpend -> MP4 (defaults)", cmd + ["-o", "scene.mp4"], frames=n)
        measure(f"{name}: springpend -> raw RGBA (to /dev/null)",
                cmd + ["--format", "raw", "-o", "-"], frames=n)
        measure(f"{name}: springpend -> raw RGBA, no static cache (to /dev/null)",
                cmd + ["--format", "raw", "-o", "-"], env={"SPRINGPEND_DRAW_CACHE": "0"}, frames=n)
        raw = os.path.join(work, "scene.rgba")
        measure(f"{name}: springpend -> raw RGBA (to a file in memory)",
                cmd + ["--format", "raw", "-o", "-"], stdout_path=raw, repeat=1, frames=n)
        floor = measure(f"{name}: encoder floor, ffmpeg raw -> MP4 (same frames, same x264 settings)",
                        ["ffmpeg", "-v", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgba",
                         "-s", f"{SW}x{SH}", "-r", str(FPS), "-i", raw,
                         "-c:v", "libx264", "-preset", "superfast", "-crf", "23",
                         "-pix_fmt", "yuv420p", "-colorspace", "bt709",
                         "-movflags", "+faststart", "floor.mp4"], frames=n)
        os.remove(raw)
        scene_rows.append((name, mp4, floor))
        raw_cmd = cmd + ["--format", "raw", "-o", os.devnull]
        stages(f"{name}, panels as shipped, static cache", raw_cmd)
        stages(f"{name}, panels as shipped, no static cache", raw_cmd, env={"SPRINGPEND_DRAW_CACHE": "0"})
        stages(f"{name}, pendulum alone", raw_cmd + ALONE)


try:
    if SCENES_ONLY:
        scenes_part()
        raise StopIteration
    sp_mp4 = measure("springpend -> MP4 (defaults: CRF 23, preset superfast)",
                     base + ["-o", "sp.mp4"])
    sp_med = measure("springpend -> MP4 (preset medium, as the peer)",
                     base + ["--set", "video.preset=medium", "-o", "sp_medium.mp4"])
    raw = os.path.join(work, "frames.rgba")
    measure("springpend -> raw RGBA (to a file in memory)", base + ["--format", "raw", "-o", "-"],
            stdout_path=raw, repeat=1)
    ff_in = ["ffmpeg", "-v", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgba",
             "-s", f"{W}x{H}", "-r", str(FPS), "-i", raw]
    floor = measure("encoder floor: ffmpeg raw -> MP4, CRF 23 superfast",
                    ff_in + ["-c:v", "libx264", "-preset", "superfast", "-crf", "23",
                             "-pix_fmt", "yuv420p", "-colorspace", "bt709",
                             "-movflags", "+faststart", "floor.mp4"])
    sp_png = measure("springpend -> PNG sequence (its default: level 1, filter up)",
                     base + ["-o", "sp_png/%04d.png"], out_dir="sp_png")
    ff_png = measure("ffmpeg raw -> PNG sequence (zlib 1, filter up)",
                     ff_in + ["-compression_level", "1", "-pred", "up", "ff_png/%04d.png"],
                     out_dir="ff_png")
    ff_png_default = measure("ffmpeg raw -> PNG sequence (ffmpeg's defaults)",
                             ff_in + ["ff_png_default/%04d.png"], out_dir="ff_png_default")
    os.remove(raw)
    measure("springpend -> raw RGBA (to /dev/null)", base + ["--format", "raw", "-o", "-"])
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
                           [exe, "render", scene, "--quality", "high", *ALONE,
                            "--set", f"video.duration={s}", "-q", "-o", f"mem{s}.mp4"],
                           repeat=1))
    # fps for the memory rows counts their own frames
    for i, s in enumerate((short_s, long_s)):
        lab, wall, _, mib, cpu = rows[-2 + i]
        rows[-2 + i] = (lab, wall, s * FPS / wall if wall else None, mib, cpu)
    scenes_part()
except StopIteration:
    pass
finally:
    shutil.rmtree(work, ignore_errors=True)

print(f"| run ({W}x{H}@{FPS}, {N} frames unless said; scenes {SW}x{SH}@{FPS}, "
      f"{int(round(SCENE_S * FPS))} frames) | wall s | fps | CPU s | peak RSS MiB |")
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


if not SCENES_ONLY:
    ratio("springpend MP4 / encoder floor, equal settings", sp_mp4, floor, "goal <= 1.15x")
    ratio("matplotlib peer / springpend defaults", peer, sp_mp4, "goal >= 1.7x")
    ratio("ffmpeg PNG / springpend PNG, equal compression", ff_png, sp_png, "goal >= 2x")
    ratio("ffmpeg PNG at its defaults / springpend PNG at its defaults", ff_png_default, sp_png,
          "for reference")
for name, mp4, fl in scene_rows:
    ratio(f"{name} ({SW}x{SH}): springpend MP4 / its own encoder floor", mp4, fl, "goal <= 1.15x")
if stage_rows:
    print()
    print("| --verbose stage, ms per frame (least of the runs) | compose | GL draw + readback |")
    print("|---|---:|---:|")
    for label, comp, draw in stage_rows:
        print(f"| {label} | {comp:.2f} | {draw:.2f} |")
    alone = {l.split(",")[0]: d for l, _, d in stage_rows if l.endswith("pendulum alone")}
    for label, _, draw in stage_rows:
        sc = label.split(",")[0]
        if "panels" in label and alone.get(sc):
            print(f"{label}: GL draw {draw / alone[sc]:.2f}x the pendulum alone (goal <= 2x)")
if not SCENES_ONLY and all(mem):
    print(f"peak memory, {long_s} s / {short_s} s of video: {mem[1][1] / mem[0][1]:.3f} "
          f"(goal <= 1.10)")
print(f"machine: {os.cpu_count()} cores, load average before: "
      f"{open('/proc/loadavg').read().split()[0]}")
