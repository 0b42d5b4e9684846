#!/usr/bin/env python3
"""springpend tests (issue 28): the seventeenth attacker's pass
(doc/notes/2026-11-27/attack17.md), finding 7: WebM pieces (--shard,
--frames) joined with ffmpeg's concat demuxer and -c copy, as
doc/outputs.md shows, had frames 1 ms off the one-piece render's (each piece
rounded its own times to Matroska's 1 ms), and compare failed the join. Now
every frame of the join is at T(k) = k / fps rounded once to the
millisecond, as in the whole video; the expected times are computed here
from the frame rate (springpend's rational: 29.97 is 2997/100), and ffprobe
reads the packets' times.
usage: test_attack17_shards.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import math
import os
import subprocess
from fractions import Fraction

import sptest
from sptest import done, err, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack17-shards")
default = os.path.join(scenes, "default.ini")


def T(k, fps):
    """k / fps in ms, rounded half away from zero (av_rescale_q's rounding)"""
    x = Fraction(k) * 1000 / fps
    return int(x + Fraction(1, 2)) if x >= 0 else -int(-x + Fraction(1, 2))


def frame_ms(video):
    r = subprocess.run(["ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries", "packet=pts",
                        "-of", "csv=p=0", video], capture_output=True, text=True)
    return sorted(int(x) for x in r.stdout.split()) if r.returncode == 0 else [f"ffprobe: {r.stderr[-200:]}"]


def join(parts, name):
    listing = path(name + ".txt")
    with open(listing, "w") as f:
        f.writelines(f"file '{p}'\n" for p in parts)
    r = subprocess.run(["ffmpeg", "-v", "error", "-y", "-f", "concat", "-safe", "0", "-i", listing, "-c", "copy",
                        path(name + ".webm")], capture_output=True, text=True)
    return r.returncode == 0, r.stderr[-200:]


common = ["--set", "video.duration=2", "--size", "160x90", "-q"]
for fps_text, fps in (("60", Fraction(60)), ("29.97", Fraction(2997, 100)), ("7", Fraction(7))):
    whole = path(f"whole{fps_text}.webm")
    r = run("render", default, *common, "--fps", fps_text, "-o", whole)
    n = math.ceil(2 * fps)  # frames of 2 s: every k / fps < 2 s (59.94 frames make 60)
    want = [T(k, fps) for k in range(n)]
    got = frame_ms(whole) if r.returncode == 0 else [err(r)]
    ok(got == want, f"{fps_text} fps: the one-piece WebM's {n} frames at k / fps rounded to the ms "
       f"({[(k, g, w) for k, (g, w) in enumerate(zip(got, want)) if g != w][:3]} {len(got)} frames)")
    parts = []
    for i in range(1, 8):
        parts.append(path(f"s{fps_text}-{i}.webm"))
        r = run("render", default, *common, "--fps", fps_text, "--shard", f"{i}/7", "-o", parts[-1])
    joined, said = join(parts, f"joined{fps_text}")
    got = frame_ms(path(f"joined{fps_text}.webm")) if joined else [said]
    ok(got == want, f"{fps_text} fps: 7 shards joined with -c copy: every frame where the whole has it "
       f"({[(k, g, w) for k, (g, w) in enumerate(zip(got, want)) if g != w][:3]} {len(got)} frames)")
    c = run("compare", whole, path(f"joined{fps_text}.webm"))
    ok(c.returncode == 0, f"{fps_text} fps: compare whole.webm joined.webm passes ({c.stdout.strip()[:200]})")

# uneven --frames pieces at 60 fps
parts = []
for a, b in ((0, 17), (17, 50), (50, 51), (51, 120)):
    parts.append(path(f"f{a}.webm"))
    run("render", default, *common, "--fps", "60", "--frames", f"{a}:{b}", "-o", parts[-1])
joined, said = join(parts, "joinedframes")
got = frame_ms(path("joinedframes.webm")) if joined else [said]
want = [T(k, Fraction(60)) for k in range(120)]
ok(got == want, f"--frames 0:17, 17:50, 50:51, 51:120 joined: every frame at k / 60 s rounded to the ms "
   f"({[(k, g, w) for k, (g, w) in enumerate(zip(got, want)) if g != w][:3]} {len(got)} frames)")

done()
