#!/usr/bin/env python3
"""springpend tests: every output kind, reopened with ffprobe/ffmpeg; frame
ranges and shards joined equal the whole video; signals keep a playable file;
a full disk and a read-only folder give a clear error and leave no file.
usage: test_output.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)
Exits 77 (skip) without ffprobe/ffmpeg. The full-disk and read-only checks
mount a tmpfs and are skipped where mounting is not permitted."""
import glob
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

from sptest import done, ok, skip

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "output"))
scene = os.path.join(src, "..", "scenes", "default.ini")
if not shutil.which("ffprobe") or not shutil.which("ffmpeg"):
    print("1..0 # SKIP ffprobe/ffmpeg not installed")
    sys.exit(77)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
W, H, FPS, DUR = 160, 120, 30, 2.0  # small and short: 60 frames
N = int(FPS * DUR)
SMALL = ["--size", f"{W}x{H}", "--fps", str(FPS), "--set", f"video.duration={DUR}", "-q"]


def run(*args, **kw):
    return subprocess.run([exe, *args], capture_output=True, cwd=work, **kw)


def path(name):
    return os.path.join(work, name)


def probe(f):
    """codec, pix_fmt, decoded frame count, duration (s) of the first stream."""
    r = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-show_entries",
                        "stream=codec_name,pix_fmt,nb_read_frames:format=duration",
                        "-of", "json", f], capture_output=True, text=True)
    if r.returncode:
        return None
    j = json.loads(r.stdout)
    st = j["streams"][0]
    return (st.get("codec_name"), st.get("pix_fmt"), int(st.get("nb_read_frames", 0)),
            float(j["format"].get("duration", 0)))


def decode(f, pre=(), post=()):
    """Decoded RGBA bytes of every frame of f."""
    r = subprocess.run(["ffmpeg", "-v", "error", *pre, "-i", f, *post, "-f", "rawvideo",
                        "-pix_fmt", "rgba", "-"], capture_output=True)
    return r.stdout if r.returncode == 0 else None


def leftovers(folder):
    return [n for n in os.listdir(folder) if n.endswith(".part")]


# ---- every format, reopened ----
for name, fmt_args, codec, pix in [
        ("all.mp4", [], "h264", "yuv420p"),
        ("all.webm", [], "vp9", "yuv420p"),
        ("all.mkv", ["--format", "webm"], "vp9", "yuv420p")]:
    r = run("render", scene, *SMALL, *fmt_args, "-o", name)
    p = probe(path(name)) if r.returncode == 0 else None
    ok(p and p[0] == codec and p[1] == pix and p[2] == N and abs(p[3] - DUR) < 0.05
       and not leftovers(work),
       f"{name}: {codec} {pix}, {N} frames, {DUR} s, no .part (got {p}, "
       f"rc {r.returncode} {r.stderr.decode()[-200:]!r})")

# [video] crf and preset reach x264 (it writes its settings into the stream).
data = open(path("all.mp4"), "rb").read()
r = run("render", scene, *SMALL, "--set", "video.crf=40", "--set", "video.preset=ultrafast",
        "-o", "crf40.mp4")
data40 = open(path("crf40.mp4"), "rb").read() if r.returncode == 0 else b""
ok(b"crf=23.0" in data and b"cabac=1" in data and b"crf=40.0" in data40 and b"cabac=0" in data40,
   "defaults reach x264 as crf=23 (CABAC on); video.crf=40, preset=ultrafast as crf=40, CABAC off")

# [video] png_level: 9 writes smaller files than 1, with the same pixels.
sizes = {}
for lvl in (1, 9):
    run("render", scene, *SMALL, "--set", f"video.png_level={lvl}", "--frames", "50:51",
        "-o", f"lvl{lvl}/%03d.png")
    f = path(f"lvl{lvl}/050.png")
    sizes[lvl] = os.path.getsize(f) if os.path.exists(f) else 0
ok(0 < sizes[9] < sizes[1] and decode(path("lvl1/050.png")) == decode(path("lvl9/050.png")),
   f"png_level 9 is smaller than 1 ({sizes[9]} < {sizes[1]} bytes), same pixels")

# --quality presets, and --size still overrides them.
def size_fps(f):
    r = subprocess.run(["ffprobe", "-v", "error", "-show_entries", "stream=width,height,r_frame_rate",
                        "-of", "csv=p=0", f], capture_output=True, text=True)
    return r.stdout.strip()


r = run("render", scene, "--quality", "low", "--set", "video.duration=0.5", "-q", "-o", "low.mp4")
r2 = run("render", scene, "--quality", "low", "--size", "320x240", "--set", "video.duration=0.5",
         "-q", "-o", "low2.mp4")
ok(size_fps(path("low.mp4")) == "854,480,15/1" and size_fps(path("low2.mp4")) == "320,240,15/1",
   f"--quality low is 854x480 at 15 fps; --size overrides its size "
   f"({size_fps(path('low.mp4'))}; {size_fps(path('low2.mp4'))})")
r = run("render", scene, "--quality", "8k", "-o", "q.mp4")
ok(r.returncode == 2 and b"low (854x480@15)" in r.stderr, "--quality 8k: exit 2, lists the presets")

# A transparent background: VP9 with an alpha plane (yuva420p; ffprobe shows
# the main plane and the alpha_mode tag, libvpx decodes the alpha).
r = run("render", scene, *SMALL, "--set", "view.background=transparent", "--set", "view.panels=none",
        "--set", "view.hud=false", "--set", "view.colorbar=false", "-o", "alpha.webm")
tags = subprocess.run(["ffprobe", "-v", "error", "-show_entries", "stream_tags=alpha_mode",
                       "-of", "csv=p=0", path("alpha.webm")], capture_output=True, text=True)
rgba = decode(path("alpha.webm"), pre=["-c:v", "libvpx-vp9"], post=["-frames:v", "1"])
alpha = rgba[3::4] if rgba else b""
clear = sum(a < 8 for a in alpha) / max(len(alpha), 1)
solid = sum(a > 247 for a in alpha)
ok(r.returncode == 0 and tags.stdout.strip() == "1" and clear > 0.9 and solid > 20,
   f"alpha.webm: VP9 with alpha; {clear:.0%} of the first frame clear, {solid} px "
   f"opaque (the pendulum)")
r = run("render", scene, *SMALL, "--set", "view.background=transparent", "-o", "alpha.mp4")
ok(r.returncode == 2 and b"use .webm" in r.stderr and not os.path.exists(path("alpha.mp4")),
   "a transparent background in MP4: exit 2, points to .webm, no file")

# GIF: above 50 fps every other frame is kept; the duration is the same.
r = run("render", scene, *SMALL, "--fps", "60", "-o", "all.gif")
p = probe(path("all.gif")) if r.returncode == 0 else None
ok(p and p[0] == "gif" and p[2] == N and abs(p[3] - DUR) < 0.05,
   f"all.gif at 60 fps: GIF of {N} frames (every other of {2 * N}), {DUR} s (got {p})")
gif = decode(path("all.gif"))
mp4_first = decode(path("all.mp4"), post=["-frames:v", "1"]) if p else None
# The palette is made for the content: the first frame's colours stay close
# to the H.264 video's (mean absolute difference in 0..255 levels).
if gif and mp4_first:
    diff = sum(abs(a - b) for a, b in zip(gif[:W * H * 4], mp4_first)) / (W * H * 4)
    ok(diff < 4, f"GIF's first frame is within {diff:.2f} levels of the MP4's on average")
else:
    ok(False, "GIF and MP4 decode")

# PNG sequence and raw: the same pixels, frame for frame.
r1 = run("render", scene, *SMALL, "-o", "seq/%03d.png")
r2 = run("render", scene, *SMALL, "--format", "raw", "-o", "-")
pngs = sorted(os.listdir(path("seq")))
ok(r1.returncode == 0 and len(pngs) == N and pngs[0] == "000.png" and not leftovers(path("seq")),
   f"PNG sequence: {N} files 000.png.., no .part (got {len(pngs)})")
ok(r2.returncode == 0 and len(r2.stdout) == N * W * H * 4,
   f"raw to stdout: {N} frames of {W}x{H}x4 bytes (got {len(r2.stdout)} bytes)")
seq_rgba = decode(path("seq/%03d.png"), pre=["-f", "image2"]) if r1.returncode == 0 else None
ok(seq_rgba is not None and seq_rgba == r2.stdout,
   "raw frames equal the PNG sequence's pixels, frame for frame")

# A closed pipe is a clear error, not a silent death.
p = subprocess.Popen([exe, "render", scene, *SMALL, "--format", "raw", "-o", "-"],
                     stdout=subprocess.PIPE, stderr=subprocess.PIPE)
p.stdout.read(10)
p.stdout.close()
err = p.stderr.read().decode()
p.wait()
ok(p.returncode == 1 and "closed the pipe" in err,
   f"raw into a closed pipe: exit 1, says so (got {p.returncode}: {err.strip()!r})")

# ---- progress: a bar on a terminal, nothing otherwise ----
import pty
master, slave = pty.openpty()
p = subprocess.Popen([exe, "render", scene, "--size", f"{W}x{H}", "--fps", str(FPS), "--set",
                      f"video.duration={DUR}", "-o", "bar.mp4"], stderr=slave, cwd=work)
os.close(slave)
tty = b""
while True:
    try:
        chunk = os.read(master, 4096)
    except OSError:
        break
    if not chunk:
        break
    tty += chunk
p.wait()
os.close(master)
r = run("render", scene, "--size", f"{W}x{H}", "--fps", str(FPS), "--set",
        f"video.duration={DUR}", "-o", "nobar.mp4")
ok(p.returncode == 0 and f"frame {N}/{N}".encode() in tty and b"fps" in tty and b"ETA" in tty
   and b"frame " not in r.stderr and b"ETA" not in r.stderr and b"wrote nobar.mp4" in r.stderr,
   f"progress bar (frames, fps, ETA) on a terminal, none into a pipe (got {tty[-90:]!r}, "
   f"{r.stderr[-60:]!r})")

# ---- frame ranges and shards ----
parts = [run("render", scene, *SMALL, "--format", "raw", "--shard", f"{i}/3", "-o", "-")
         for i in (1, 2, 3)]
ok(all(x.returncode == 0 for x in parts) and b"".join(x.stdout for x in parts) == r2.stdout,
   "raw shards 1/3, 2/3, 3/3 joined equal the whole video byte for byte")
r = run("render", scene, *SMALL, "--frames", "17:40", "-o", "part/%03d.png")
names = sorted(os.listdir(path("part"))) if r.returncode == 0 else []
same = names and all(open(path("part/" + n), "rb").read() == open(path("seq/" + n), "rb").read()
                     for n in names)
ok(names == [f"{k:03d}.png" for k in range(17, 40)] and same,
   "--frames 17:40 writes 017.png..039.png, identical to the whole run's files")

# MP4 shards joined without re-encoding (concat demuxer, -c copy).
lst = path("shards.txt")
with open(lst, "w") as f:
    for i in (1, 2, 3):
        run("render", scene, *SMALL, "--shard", f"{i}/3", "-o", f"shard{i}.mp4")
        f.write(f"file 'shard{i}.mp4'\n")
j = subprocess.run(["ffmpeg", "-v", "error", "-y", "-f", "concat", "-safe", "0", "-i", lst,
                    "-c", "copy", path("joined.mp4")], capture_output=True, cwd=work)
p = probe(path("joined.mp4")) if j.returncode == 0 else None
ok(p and p[0] == "h264" and p[2] == N and abs(p[3] - DUR) < 0.05,
   f"MP4 shards joined with -c copy: {N} frames, {DUR} s (got {p})")
whole, joined = decode(path("all.mp4")), decode(path("joined.mp4")) if p else None
if whole and joined and len(whole) == len(joined):
    mad = max(sum(abs(a - b) for a, b in zip(whole[k:k + W * H * 4:7], joined[k:k + W * H * 4:7]))
              / len(whole[k:k + W * H * 4:7]) for k in range(0, len(whole), W * H * 4))
    ok(mad < 2, f"joined frames match the whole video's, frame for frame (worst frame's "
       f"mean difference {mad:.2f} levels; H.264 is lossy)")
else:
    ok(False, "joined and whole video decode to the same number of frames")

# The joined frames sit at k / fps, within compare's 0.5 ms: the movie
# header kept each piece's duration in milliseconds (20 frames at 60 fps:
# 0.334 s), and the concat demuxer starts the next piece there. 60 fps and a
# fractional rate (29.97), 7 pieces whose lengths are not whole milliseconds.
for fps, dur in ((60, 1.0), (29.97, 2.0)):
    frames = int(round(fps * dur))
    lst = path(f"exact{fps}.txt")
    with open(lst, "w") as f:
        for i in range(1, 8):
            run("render", scene, "--size", f"{W}x{H}", "--fps", str(fps), "--set",
                f"video.duration={dur}", "-q", "--shard", f"{i}/7", "-o", f"exact{fps}_{i}.mp4")
            f.write(f"file 'exact{fps}_{i}.mp4'\n")
    j = subprocess.run(["ffmpeg", "-v", "error", "-y", "-f", "concat", "-safe", "0", "-i", lst,
                        "-c", "copy", path(f"exact{fps}.mp4")], capture_output=True, cwd=work)
    t = subprocess.run(["ffprobe", "-v", "error", "-select_streams", "v", "-show_entries",
                        "packet=pts_time", "-of", "csv=p=0", path(f"exact{fps}.mp4")],
                       capture_output=True, text=True).stdout.split()
    t = sorted(float(x) for x in t if x.strip() not in ("", "N/A"))
    worst = max((abs(x - k / fps) for k, x in enumerate(t)), default=float("inf"))
    ok(j.returncode == 0 and len(t) == frames and worst < 5e-4,
       f"{fps} fps MP4 shards joined with the concat demuxer: every frame at k / fps within "
       f"0.5 ms ({len(t)} of {frames} frames, worst {worst * 1e3:.4f} ms)")

r = run("render", scene, *SMALL, "--shard", "4/3", "-o", "bad.mp4")
ok(r.returncode == 2 and b"--shard 4/3" in r.stderr and not os.path.exists(path("bad.mp4")),
   "--shard 4/3: exit 2, says why, no file")
r = run("render", scene, *SMALL, "--frames", "50:70", "-o", "bad.mp4")
ok(r.returncode == 2 and b"0 <= A < B <= 60" in r.stderr and not os.path.exists(path("bad.mp4")),
   "--frames past the end: exit 2, says the range, no file")

# ---- signals ----
LONG = ["--size", "640x360", "--set", "video.duration=60", "-q"]


def start_and_wait_for_part(out):
    p = subprocess.Popen([exe, "render", scene, *LONG, "-o", out], cwd=work,
                         stderr=subprocess.PIPE)
    t0 = time.time()
    while not glob.glob(glob.escape(out) + ".*.part") and time.time() - t0 < 20:
        time.sleep(0.05)
    time.sleep(0.5)  # some frames
    return p


for sig, code in ((signal.SIGINT, 130), (signal.SIGTERM, 143)):
    out = path(f"sig{code}.mp4")
    p = start_and_wait_for_part(out)
    p.send_signal(sig)
    err = p.communicate(timeout=60)[1].decode()
    pr = probe(out)
    ok(p.returncode == code and pr and pr[0] == "h264" and 0 < pr[2] < 3600 and
       not glob.glob(glob.escape(out) + ".*.part") and "kept the" in err,
       f"{sig.name}: exit {code}, a playable MP4 of the frames so far, no .part "
       f"(got {p.returncode}, {pr}, {err.strip()[-120:]!r})")

out = path("sig2.mp4")
p = start_and_wait_for_part(out)
p.send_signal(signal.SIGINT)
time.sleep(0.05)
p.send_signal(signal.SIGINT)
p.communicate(timeout=60)
# The first may have finished the file before the second arrives; either
# way no .part is left, and what is at the target plays.
ok(p.returncode == 130 and not glob.glob(glob.escape(out) + ".*.part") and
   (not os.path.exists(out) or probe(out)),
   f"a second SIGINT stops at once and removes the .part (got {p.returncode}, "
   f"file {'kept' if os.path.exists(out) else 'none'})")


# ---- a full disk and a read-only folder ----
def mount_tmpfs(opts):
    d = tempfile.mkdtemp(dir=work)
    r = subprocess.run(["mount", "-t", "tmpfs", "-o", opts, "tmpfs", d], capture_output=True)
    return d if r.returncode == 0 else None


d = mount_tmpfs("size=16k") if os.geteuid() == 0 and shutil.which("mount") else None
if d:
    try:
        for name in ("full.mp4", "full/%03d.png", "full.gif", "full.raw"):
            args = ["--format", "raw"] if name.endswith(".raw") else []
            r = run("render", scene, "--size", "320x240", "--set", "video.duration=4", "-q",
                    *args, "-o", os.path.join(d, name))
            err = r.stderr.decode()
            left = [os.path.join(dp, f) for dp, _, fs in os.walk(d) for f in fs]
            shutil.rmtree(os.path.join(d, "full"), ignore_errors=True)
            ok(r.returncode == 1 and "No space left on device" in err and d in err and not left,
               f"full disk, {name}: exit 1, names the path and the cause, nothing left "
               f"(got {r.returncode}: {err.strip()[-160:]!r}, left {left})")
    finally:
        subprocess.run(["umount", d])
else:
    skip("full disk", "cannot mount a tmpfs here (needs root)")

d = mount_tmpfs("ro,size=64k") if os.geteuid() == 0 and shutil.which("mount") else None
if d:
    try:
        for name in ("ro.mp4", "ro/%03d.png", "ro.webm"):
            r = run("render", scene, *SMALL, "-o", os.path.join(d, name))
            err = r.stderr.decode()
            ok(r.returncode in (1, 2) and "Read-only file system" in err and d in err
               and not os.listdir(d),
               f"read-only folder, {name}: exit 1 or 2, names the path and the cause, nothing "
               f"left (got {r.returncode}: {err.strip()[-160:]!r})")
    finally:
        subprocess.run(["umount", d])
else:
    skip("read-only folder", "cannot mount a tmpfs here (needs root)")

done()
