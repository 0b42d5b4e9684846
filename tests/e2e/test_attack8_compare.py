#!/usr/bin/env python3
"""springpend tests (issue 28): the attacker's eighth pass
(doc/notes/2026-11-27/attack8.md) on compare --jobs, each check run as the
attacker ran it (smaller and fewer files):
- finding 8: with --jobs above 1 every unreadable video was opened twice and
  its error said twice (the retry alone, meant for out of memory, took every
  failure): a file the container level refuses is read once, said once;
- finding 7: the memory pre-pass opened every pair's header before the first
  comparison and ignored SIGTERM meanwhile: it stops on the cancel flag
  (exit 143, "interrupted", nothing written);
- finding 6: one forged PNG header (1000000x1000000, 59 bytes) put the
  whole compare --jobs on one thread: an image the reader refuses unread
  is not counted in the cap. The same for videos (fix28): a header claiming
  16000x16000 (a size FFmpeg decodes; 6 GB a thread at 24 B/px) is refused
  unread (beyond SP_VIDEO_MAX_PIXELS, 8192x4352), and one claiming the
  largest size read costs one thread's share, not every thread's (the n
  threads hold the n largest pairs at once).
usage: test_attack8_compare.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import signal
import struct
import subprocess
import time
import zlib

import sptest
from sptest import done, err, ok

exe, src, work, _ = sptest.setup("attack8_compare", [])
run = sptest.runner_bytes(exe, work)
default = os.path.join(src, "..", "scenes", "default.ini")


def path(*names):
    return os.path.join(work, *names)


def write(p, data):
    os.makedirs(os.path.dirname(p) or ".", exist_ok=True)
    with open(p, "wb") as f:
        f.write(data)


def link(a, b):
    """b as a hard link to a (cheap: thousands of pairs)."""
    os.makedirs(os.path.dirname(b), exist_ok=True)
    os.link(a, b)


def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


r = run("render", default, "--size", "160x90", "--fps", "10", "--set", "video.duration=0.3",
        "-q", "-o", "v.mp4", timeout=120)
assert r.returncode == 0, err(r)
r = run("still", default, "--size", "64x36", "-q", "-o", "a.png")
assert r.returncode == 0, err(r)
video, still = path("v.mp4"), path("a.png")

# ---- finding 8: an unreadable video is read once and said once -------------------------
for i in range(3):  # readable pairs beside it, so that the pool runs several threads
    link(video, path("fv", "e", f"ok{i}.mp4"))
    link(video, path("fv", "a", f"ok{i}.mp4"))
write(path("fv", "e", "y.mp4"), b"garbage")
link(video, path("fv", "a", "y.mp4"))
for j in ("1", "4"):
    r = run("compare", "fv/e", "fv/a", "--jobs", j)
    said = err(r).count("y.mp4: cannot read a video from it")
    # main: said 1 time with --jobs 1, 2 times with --jobs 4
    ok(r.returncode == 2 and said == 1,
       f"--jobs {j}: a garbage .mp4 beside a video is refused, its error said once "
       f"(rc {r.returncode}, said {said} times: {err(r)[:400]})")

# a video cut at 90 %: its header reads, its last frame does not decode. A
# decoder's error may be memory (FFmpeg says some failed allocations so), so
# the pool's try is compared again alone: said once all the same, FFmpeg's
# own lines too (main: both twice)
import re  # noqa: E402
with open(video, "rb") as f:
    data = f.read()
write(path("dc", "e", "t.mp4"), data[:len(data) * 9 // 10])
link(video, path("dc", "a", "t.mp4"))
for i in range(3):
    link(video, path("dc", "e", f"ok{i}.mp4"))
    link(video, path("dc", "a", f"ok{i}.mp4"))
said = {}
for j in ("1", "4"):
    r = run("compare", "dc/e", "dc/a", "--jobs", j)
    said[j] = (r.returncode, sorted(re.sub(r"@ 0x[0-9a-f]+", "@", line)
                                    for line in err(r).splitlines()))
n = sum("springpend: dc/e/t.mp4: cannot" in line for line in said["4"][1])
ok(said["4"][0] == 2 and n == 1 and said["4"] == said["1"],
   f"--jobs 4, a video cut at 90 %: its decoder's error said once, FFmpeg's lines as with "
   f"--jobs 1 (rc {said['4'][0]}, said {n} times; --jobs 4: {said['4'][1][:8]}; --jobs 1: "
   f"{said['1'][1][:8]})")

# FFmpeg's own lines ("[mov @ 0x...] stream 0, offset 0xe14: partial file")
# are whole lines: never a springpend line in the middle of one (main: about
# one run in two of these had one)
with open(video, "rb") as f:
    cut = f.read()[:3000]
for i in range(8):
    write(path("fl", "e", f"x{i}.mp4"), cut)
    write(path("fl", "e", f"y{i}.mp4"), b"garbage")
    link(video, path("fl", "a", f"x{i}.mp4"))
    link(video, path("fl", "a", f"y{i}.mp4"))
mixed = []
for _ in range(10):
    r = run("compare", "fl/e", "fl/a", "--jobs", "4")
    mixed += [line for line in err(r).splitlines() if "] springpend:" in line]
ok(not mixed, f"--jobs 4, 8 cut and 8 garbage videos, 10 runs: FFmpeg's lines and "
   f"springpend's never share a line ({mixed[:2]})")

os.makedirs(path("ff", "e"))
os.makedirs(path("ff", "a"))
for i in range(3):
    link(video, path("ff", "e", f"ok{i}.mp4"))
    link(video, path("ff", "a", f"ok{i}.mp4"))
os.mkfifo(path("ff", "e", "3.mp4"))
os.mkfifo(path("ff", "a", "3.mp4"))
r = sptest.hangs(run, "compare", "ff/e", "ff/a", "--jobs", "4", timeout=60)
said = r[1].count("3.mp4: is a FIFO")
# main: "ff/e/3.mp4: is a FIFO ..." twice
ok(r[0] == 2 and said == 1,
   f"--jobs 4: a FIFO named .mp4 is refused and said once (rc {r[0]}, said {said} times: "
   f"{r[1][:400]})")

# ---- finding 7: SIGTERM during the memory pre-pass -------------------------------------
# 20000 pairs of two different videos (hard links): the pre-pass opens 40000
# headers, about 0.3 ms each (12 s here, longer on a loaded machine), before
# the first comparison; the signal comes 1 s in. main ran the pass to its
# end first (answering 10 s and more late); the cancel flag stops it at once,
# and no pair is compared, no diff image written.
r = run("render", default, "--size", "160x90", "--fps", "10", "--set", "video.duration=0.3",
        "--set", "initial.angle=12", "-q", "-o", "v2.mp4", timeout=120)
assert r.returncode == 0, err(r)
PAIRS = 20000
for i in range(PAIRS):
    link(video, path("pv", "e", f"{i}.mp4"))
    link(path("v2.mp4"), path("pv", "a", f"{i}.mp4"))
with open(path("term.out"), "wb") as out, open(path("term.err"), "wb") as e:
    p = subprocess.Popen([exe, "compare", "pv/e", "pv/a", "--jobs", "2", "--diff", "dd"],
                         cwd=work, stdout=out, stderr=e)
    time.sleep(1)
    p.send_signal(signal.SIGTERM)
    sent = time.monotonic()
    try:
        rc = p.wait(timeout=240)
    except subprocess.TimeoutExpired:
        p.kill()
        rc = "hung"
    late = time.monotonic() - sent
with open(path("term.out"), "rb") as f, open(path("term.err"), "rb") as g:
    said = (f.read() + g.read()).decode(errors="replace")
diffs = [n for _, _, ns in os.walk(path("dd")) for n in ns]
# late: the rest of the run after the signal (listing the 20000 records not
# compared: 0.3 s here, 2.2 s under ASan); main's rest of the pre-pass was
# 17 s here
sanitized = b"__asan_init" in open(exe, "rb").read()
ok(rc == 143 and late < (12 if sanitized else 6) and "INTERRUPTED: 0 compared" in said and not diffs,
   f"compare --jobs 2 of {PAIRS} video pairs, SIGTERM 1 s in (in the memory pre-pass): "
   f"exit 143 {late:.1f} s after it, nothing compared, no diff written "
   f"(rc {rc}, {len(diffs)} diffs, {said[-300:]})")

# ---- finding 6: a forged PNG header does not make the run serial -----------------------
write(path("huge.png"), b"\x89PNG\r\n\x1a\n"
      + chunk(b"IHDR", struct.pack(">IIBBBBB", 1000000, 1000000, 8, 6, 0, 0, 0))
      + chunk(b"IDAT", zlib.compress(b"\0" * 10)) + chunk(b"IEND", b""))
for i in range(40):
    link(still, path("pb", "e", f"{i}.png"))
    link(still, path("pb", "a", f"{i}.png"))
link(path("huge.png"), path("pb", "a", "zz.png"))
link(still, path("pb", "e", "zz.png"))
r = run("compare", "pb/e", "pb/a", "--jobs", "4")
# main: "--jobs 4: each thread holds up to 12000000 MB for the largest image
# (1000000.0 Mpx) ... comparing on 1 thread"
ok(r.returncode == 2 and "each thread holds" not in err(r)
   and "beyond the 100000000-pixel limit" in r.stdout.decode(errors="replace") + err(r),
   f"--jobs 4 with a forged 1000000x1000000 header among 40 pairs: no thread cap, the "
   f"image refused (rc {r.returncode}: {err(r)[:400]})")

# ---- finding 6 for videos (fix28): a forged frame size in a video's header --------------
def forged_video(w, h):
    """v.mp4 with its avc1 sample entry's size set to w x h (FFmpeg's mov
    demuxer gives that as the stream's size; the H.264 stream is unchanged)."""
    data = bytearray(open(video, "rb").read())
    at = data.index(b"avc1", data.index(b"stsd")) + 28  # VisualSampleEntry's width, height
    data[at:at + 4] = struct.pack(">HH", w, h)
    # the track header's display size too (16.16), as a muxer writes it: else the demuxer
    # reads the two sizes' ratio as non-square pixels, which compare refuses (attack11 #8)
    tkhd = data.index(b"tkhd") - 4
    at = tkhd + (84 if data[tkhd + 8] == 0 else 96)
    data[at:at + 8] = struct.pack(">II", w << 16, h << 16)
    return bytes(data)


write(path("big.mp4"), forged_video(16000, 16000))  # 256 Mpx: FFmpeg decodes such a size
write(path("lim.mp4"), forged_video(8192, 4352))    # the most compare reads
for folder, forged in (("vb", "big.mp4"), ("vl", "lim.mp4")):
    for i in range(40):
        link(video, path(folder, "e", f"{i}.mp4"))
        link(video, path(folder, "a", f"{i}.mp4"))
    link(video, path(folder, "e", "zz.mp4"))
    link(path(forged), path(folder, "a", "zz.mp4"))
# main: "--jobs 41: each thread holds up to 6148 MB for the largest image (256.0 Mpx) ...
# 2 of them fit in 12663 MB, half of physical memory: comparing on 2 threads"
r = run("compare", "vb/e", "vb/a", "--jobs", "41", timeout=120)
out = r.stdout.decode(errors="replace")
ok(r.returncode == 2 and "each thread holds" not in err(r)
   and "vb/a/zz.mp4: its header says 16000x16000, 256000000 pixels a frame; compare reads "
       "videos of at most 35651584 pixels a frame" in err(r)
   and "40 compared, 40 passed, 0 failed, 1 missing or unreadable" in out
   and "Picture size" not in err(r),
   f"--jobs 41 with a video header forged to 16000x16000 among 40 pairs: no thread cap, "
   f"the video refused unread, said once without FFmpeg's line (rc {r.returncode}: "
   f"{err(r)[:400]} | {out[-120:]})")
# main: "... up to 860 MB for the largest image (35.7 Mpx) ... comparing on 14 threads"
r = run("compare", "vl/e", "vl/a", "--jobs", "41", timeout=120)
out = r.stdout.decode(errors="replace")
ok(r.returncode == 0 and "each thread holds" not in err(r)
   and "41 compared, 41 passed" in out,
   f"--jobs 41 with one video header forged to 8192x4352 (860 MB a thread) among 40 "
   f"small pairs: counted once, not on every thread: no thread cap (rc {r.returncode}: "
   f"{err(r)[:400]} | {out[-120:]})")

done()
