#!/usr/bin/env python3
"""springpend tests: a scene's [timeline] (captions, eased speed changes,
pauses keyed by simulated time). The video's clock is computed here again
from the rule render --help documents, independently (the speed as a
function of video time, integrated by scipy's quad, the cue times found by
brentq), and checked against: the frame count info prints; the simulated
time every rendered frame carries (its PNG's springpend.time); frames inside
a pause identical but for the caption band; the caption in force at given
times (pdftotext of PDF stills); slow-motion frames equal to stills at their
times; --frames pieces joined equal to the whole video's bytes; every bad
input refused with FILE:LINE, exit 2 and no output; data and sweep ignoring
the timeline.
usage: test_timeline.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import glob
import hashlib
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import zlib

from sptest import done, need_scipy, ok, runner, skip

need_scipy()
import numpy as np  # noqa: E402
from scipy.integrate import quad  # noqa: E402
from scipy.optimize import brentq  # noqa: E402

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "timeline"))
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
run = runner(exe, work)
lesson = os.path.join(src, "..", "scenes", "lesson-exchange.ini")
SMALL = ["--size", "320x180", "-q"]

# ---- the documented rule, computed again ----------------------------------
# speed S at simulated T: from the video time u_T where the clock reaches T,
# s(u) = s0 + (S - s0) q((u - u_T) / E), q(x) = 3x^2 - 2x^3, E = 0.5 s of video;
# pause D at T holds the clock for D s of video. Here the cues' eases do not
# overlap, so each is s0 -> S over [u_T, u_T + E] and then S.
E = 0.5
CUES = [(12, "speed", 0.25), (20, "pause", 3.0), (22, "speed", 1.0)]  # lesson-exchange.ini
DURATION, FPS0 = 40.0, 30


def q(x):
    x = min(max(x, 0.0), 1.0)
    return x * x * (3 - 2 * x)


def clock(cues, s0=1.0):
    """Stretches of video (u0, u1, speed as a function of u, t0, kind)."""
    parts, u, t, s = [], 0.0, 0.0, s0
    steady = lambda s_: lambda x: s_  # noqa: E731
    for T, kind, v in cues:
        assert T >= t, "the test's cues would overlap an ease"
        u_T = u + (T - t) / s  # steady at s until the clock reaches T
        parts.append((u, u_T, steady(s), t, "steady"))
        u, t = u_T, T
        if kind == "speed":
            f = (lambda a, b, u0: lambda x: a + (b - a) * q((x - u0) / E))(s, v, u)
            parts.append((u, u + E, f, t, "ease"))
            t += quad(f, u, u + E, epsabs=1e-13, epsrel=1e-13, limit=200)[0]
            u, s = u + E, v
        else:
            parts.append((u, u + v, lambda x: 0.0, t, "hold"))
            u += v
    parts.append((u, u + (DURATION - t) / s, steady(s), t, "steady"))
    return parts


PARTS = clock(CUES)
LENGTH = PARTS[-1][1]


def t_of(u):
    for u0, u1, f, t0, kind in PARTS:
        if u0 <= u <= u1 or (u0, u1) == PARTS[-1][:2]:
            return t0 if kind == "hold" else t0 + quad(f, u0, u, epsabs=1e-13, epsrel=1e-13, limit=200)[0]
    raise AssertionError(u)


def u_first(t):
    """The first video time the clock shows simulated time t."""
    return brentq(lambda u: t_of(u) - t, 0, LENGTH, xtol=1e-13)


print(f"# the rule: {LENGTH:.6f} s of video (12 + 40 + 3 + 18 = 73 without the eases)")

# ---- the video's length and frame count --------------------------------------
r = run("info", lesson, "--json")
j = json.loads(r.stdout) if r.returncode == 0 else {}
frames = round(LENGTH * FPS0)
ok(abs(j.get("video_length", 0) - LENGTH) < 1e-9 and j.get("video_frames") == frames,
   f"info: the video lasts {j.get('video_length')} s, {j.get('video_frames')} frames at 30 fps "
   f"(the rule: {LENGTH:.9f} s, {frames} frames; 12 + 40 + 3 + 18 = 73 s less the eases)")
ok(abs(LENGTH - 73) < 1.5, "the eases change the length by less than 3 eases' worth")
r = run("info", lesson)
ok(re.search(r"video\s+72\.4375 s of video", r.stdout) is not None,
   "info prints the video's length")
r = run("render", lesson, "--set", "video.fps=10", "--frames", f"{round(LENGTH * 10) - 1}:"
        f"{round(LENGTH * 10)}", "--format", "raw", "-o", "last.rgba", *SMALL)
ok(r.returncode == 0, f"the last frame ({round(LENGTH * 10) - 1}) at 10 fps renders")
r = run("render", lesson, "--set", "video.fps=10", "--frames", f"{round(LENGTH * 10)}:"
        f"{round(LENGTH * 10) + 1}", "--format", "raw", "-o", "past.rgba", *SMALL)
ok(r.returncode == 2 and f"B <= {round(LENGTH * 10)}" in r.stderr,
   f"--frames past the timeline's length is refused: {r.stderr.strip()[:160]}")


# ---- every frame's simulated time, from the PNGs' springpend.time ------------
def png_time(path):
    data = open(path, "rb").read()
    i = 8
    while i < len(data):
        n, kind = struct.unpack(">I4s", data[i:i + 8])
        body = data[i + 8:i + 8 + n]
        if kind == b"tEXt" and body.startswith(b"springpend.time\0"):
            return float(body.split(b"\0", 1)[1])
        if kind == b"iTXt" and body.startswith(b"springpend.time\0"):
            return float(body.split(b"\0", 5)[-1])
        if kind == b"zTXt" and body.startswith(b"springpend.time\0"):
            return float(zlib.decompress(body.split(b"\0", 1)[1][1:]))
        i += 12 + n
    return None


FPS = 10
ranges = [(0, 3), (115, 132), (428, 470), (538, 552), (700, round(LENGTH * FPS))]
os.makedirs(os.path.join(work, "frames"))
worst, checked, missing = 0.0, 0, []
for a, b in ranges:
    r = run("render", lesson, "--set", f"video.fps={FPS}", "--frames", f"{a}:{b}",
            "-o", os.path.join("frames", "%05d.png"), "--set", "view.panels=none", *SMALL)
    if r.returncode:
        print("# " + r.stderr.strip())
    for k in range(a, b):
        t = png_time(os.path.join(work, "frames", f"{k:05d}.png")) if r.returncode == 0 else None
        if t is None:
            missing.append(k)
            continue
        worst = max(worst, abs(t - t_of(k / FPS)))
        checked += 1
ok(not missing and worst < 2e-7 * DURATION,
   f"{checked} frames at 10 fps across the eases, the pause and the end show the rule's "
   f"simulated time (worst {worst:.2g} s; the PNG keeps 9 digits){' missing ' + str(missing[:5]) if missing else ''}")

# ---- pdftotext: the caption in force at simulated times ------------------------
def pdf_text(t, extra=()):
    out = os.path.join(work, f"at{t}.pdf")
    r = run("still", lesson, "--at", str(t), "-o", out, "--size", "640x360", "-q", *extra)
    if r.returncode:
        return None, r.stderr
    p = subprocess.run(["pdftotext", out, "-"], capture_output=True, text=True)
    return " ".join(p.stdout.split()), ""


CAPTIONS = {"bounce": "Energy starts in the bounce", "swing": "The swing takes over",
            "note": "All the energy is in the swing", "back": "... and flows back to the bounce"}
EXPECT = [(0, "bounce"), (5, "bounce"), (15.99, "bounce"), (16, "swing"), (19.99, "swing"),
          (20, "note"), (20.01, "swing"), (29.9, "swing"), (30, "back"), (39, "back")]
if shutil.which("pdftotext"):
    for t, key in EXPECT:
        text, err = pdf_text(t)
        others = [c for k, c in CAPTIONS.items() if k != key and c in (text or "")
                  and c not in CAPTIONS[key]]
        ok(text is not None and CAPTIONS[key] in text and not others,
           f"still --at {t}: the PDF says '{CAPTIONS[key]}' and no other caption"
           f"{' (also ' + str(others) + ')' if others else ''} {err.strip()[:200]}")
    text, _ = pdf_text(20)
    ok(text is not None and "paused" in text, "still --at 20 (the pause): the marker says paused")
    text, _ = pdf_text(14)
    ok(text is not None and "speed ×0.25" in text, "still --at 14 (slow motion): speed ×0.25")
    text, _ = pdf_text(5)
    ok(text is not None and "speed ×1" in text, "still --at 5: speed ×1")
else:
    skip("captions in PDF stills", "pdftotext (poppler-utils) is not installed")


# ---- raw frames -----------------------------------------------------------------
W, H = 320, 180


def raw(*args):
    r = subprocess.run([exe, "render", lesson, "--format", "raw", "-o", "-", *SMALL, *args],
                       capture_output=True, cwd=work)
    if r.returncode:
        print("# " + r.stderr.decode(errors="replace").strip())
        return None
    return np.frombuffer(r.stdout, np.uint8).reshape(-1, H, W, 4)


def png_pixels(path):
    r = subprocess.run(["ffmpeg", "-v", "error", "-i", path, "-f", "rawvideo", "-pix_fmt", "rgba",
                        "-"], capture_output=True)
    return np.frombuffer(r.stdout, np.uint8).reshape(H, W, 4) if r.returncode == 0 else None


# The pause at simulated 20 s: from u_first(20) for 3 s of video.
u_p = u_first(20)
first_k, last_k = int(np.ceil(u_p * FPS - 1e-9)), int(np.ceil((u_p + 3) * FPS - 1e-9)) - 1
print(f"# the pause: video {u_p:.6f} .. {u_p + 3:.6f} s, frames {first_k} .. {last_k} at 10 fps")
fr = raw("--set", f"video.fps={FPS}", "--frames", f"{first_k - 1}:{last_k + 2}")
band = None
if shutil.which("pdftotext") and fr is not None:
    # where the caption band's texts are: pdftotext's word boxes of the PDF
    # stills at the pause (the note) and just before it (the caption), px
    boxes = []
    for t in (20, 19.99):
        out = os.path.join(work, f"bbox{t}.pdf")
        run("still", lesson, "--at", str(t), "-o", out, *SMALL)
        html = subprocess.run(["pdftotext", "-bbox", out, "-"], capture_output=True,
                              text=True).stdout
        for m in re.finditer(r'<word xMin="([\d.]+)" yMin="([\d.]+)" xMax="([\d.]+)" '
                             r'yMax="([\d.]+)">([^<]*)</word>', html):
            if m.group(5) in (CAPTIONS["note"] + " " + CAPTIONS["swing"]).split():
                boxes.append([float(m.group(i)) for i in range(1, 5)])
    if boxes and min(b[1] for b in boxes) > H / 2:
        band = (int(min(b[0] for b in boxes)) - 3, int(min(b[1] for b in boxes)) - 3,
                int(max(b[2] for b in boxes)) + 4, int(max(b[3] for b in boxes)) + 4)
if fr is not None and band:
    x0, y0, x1, y1 = band
    held = fr[1:-1]
    mask = np.ones((H, W), bool)
    mask[max(y0, 0):y1, max(x0, 0):x1] = False
    diff_out = max(int(np.abs(held[i].astype(int) - held[0].astype(int))[mask].max())
                   for i in range(len(held)))
    diff_in = max(int(np.abs(held[i].astype(int) - held[0].astype(int)).max())
                  for i in range(len(held)))
    ok(len(held) == 30 and diff_out == 0 and diff_in > 0,
       f"{len(held)} frames inside the pause are identical outside the caption band "
       f"{band} (largest difference outside {diff_out}, inside {diff_in}: the note fades)")
    before = int(np.abs(fr[0].astype(int) - held[0].astype(int))[mask].max())
    after = int(np.abs(fr[-1].astype(int) - held[-1].astype(int))[mask].max())
    ok(before > 0 and after > 0, f"the frames before and after the pause move ({before}, {after})")
    # the middle of the pause, the note at full strength, is the still at 20 s
    still = os.path.join(work, "still20.png")
    run("still", lesson, "--at", "20", "--set", f"video.fps={FPS}", "-o", still, *SMALL)
    px = png_pixels(still)
    ok(px is not None and np.array_equal(px, held[15]),
       "the middle of the pause is byte for byte the still at 20 s (note and 'paused' shown)")
else:
    skip("frames inside a pause", "pdftotext or the raw frames are missing")

# Slow motion: the video's frames are the stills at their simulated times
# (trail, charts and marker follow simulated time through speed changes and
# pauses), away from the captions' fades.
for k in (300, 500, 620):
    t = t_of(k / FPS)
    fr = raw("--set", f"video.fps={FPS}", "--frames", f"{k}:{k + 1}", "--set", "view.panels=all")
    still = os.path.join(work, f"still{k}.png")
    r = run("still", lesson, "--at", repr(t), "--set", f"video.fps={FPS}", "-o", still, *SMALL,
            "--set", "view.panels=all", "--set", "view.cursor=true")  # the video's marks
    px = png_pixels(still) if r.returncode == 0 else None
    ok(fr is not None and px is not None and np.array_equal(px, fr[0]),
       f"frame {k} (simulated {t:.4f} s) equals the still at its time")

# ---- shards join into the whole video's bytes ------------------------------------
SH = ["--set", "video.fps=5", "--set", "view.panels=r,modes"]
whole = raw(*SH)
n5 = round(LENGTH * 5)
cuts = [0, 61, 110, 117, 200, n5]  # inside the first ease, the pause, the second ease
pieces = [raw(*SH, "--frames", f"{a}:{b}") for a, b in zip(cuts, cuts[1:])]
ok(whole is not None and len(whole) == n5 and all(p is not None for p in pieces)
   and np.concatenate(pieces).tobytes() == whole.tobytes(),
   f"five --frames pieces (cut in the eases and the pause) joined are the whole video's "
   f"{n5} frames, byte for byte")
r1 = run("render", lesson, *SH, "-o", "png/whole/%05d.png", "-q")
r2 = [run("render", lesson, *SH, "--shard", f"{i}/3", "-o", "png/shards/%05d.png", "-q")
      for i in (1, 2, 3)]
names = sorted(os.listdir(os.path.join(work, "png", "whole"))) if r1.returncode == 0 else []
same = names and names == sorted(os.listdir(os.path.join(work, "png", "shards"))) and all(
    open(os.path.join(work, "png", "whole", n), "rb").read()
    == open(os.path.join(work, "png", "shards", n), "rb").read() for n in names)
ok(r1.returncode == 0 and all(r.returncode == 0 for r in r2) and len(names) == n5 and same,
   f"--shard 1/3 .. 3/3 PNGs are the whole run's {len(names)} files")

# ---- bad input ---------------------------------------------------------------------
BASE = "[video]\nduration = 40\nfps = 30\n[timeline]\n"
BAD = [
    ("0 = caption: a\n12 = speed 0.25\n10 = caption: b\n", 7, "out of order"),
    ("50 = caption: late\n", 5, "beyond the end of the video"),
    ("40.5 = speed 2\n", 5, "beyond the end of the video"),
    ("3 = zoom 2\n", 5, "'zoom' is not a cue"),
    ("3 = slowmo 0.5\n", 5, "'slowmo' is not a cue"),
    ("3 = speed 0\n", 5, "speed 0: out of range"),
    ("3 = speed -0.5\n", 5, "speed -0.5: out of range"),
    ("3 = speed\n", 5, "speed needs a speed"),
    ("3 = pause\n", 5, "pause needs a duration"),
    ("3 = pause: a note\n", 5, "pause needs a duration"),
    ("3 = pause 0: a note\n", 5, "pause 0: out of range"),
    ("3 = caption without a colon\n", 5, "caption needs a ':'"),
    ("three = caption: x\n", 5, "time 'three' is not a decimal number"),
    ("-1 = caption: x\n", 5, "time '-1' is out of range"),
    ("3 = caption: x\n3 = caption: y\n", 6, "a second caption at 3 s"),
    ("3 = caption: " + " ".join(["words"] * 30) + "\n", 5, "too long for a 320x180 frame"),
    ("3 = pause 2: " + "W" * 60 + "\n", 5, "a word is wider than the frame"),
    # libinih would end the text at ' #' or ' ;': refused unquoted, as title's
    ("3 = caption: Run #3\n", 5, "' #' would start a comment here"),
    ("3 = pause 2: a ;b\n", 5, "' ;' would start a comment here"),
    ('3 = caption: "Run #3" and more\n', 5, "only a '#' or ';' comment may follow"),
]
for i, (cues, line, what) in enumerate(BAD):
    path = os.path.join(work, f"bad{i}.ini")
    with open(path, "w") as f:
        f.write(BASE + cues)
    for cmd in (["render", path, "-o", f"bad{i}.mp4"], ["still", path, "-o", f"bad{i}.png"]):
        r = run(*cmd, "--size", "320x180")
        left = glob.glob(os.path.join(work, f"bad{i}.*[4g]*")) + glob.glob(
            os.path.join(work, f"bad{i}.*.part"))
        ok(r.returncode == 2 and f"bad{i}.ini:{line}: " in r.stderr and what in r.stderr
           and not left, f"{cmd[0]}: {cues.strip()[:40]!r} -> exit {r.returncode}, "
           f"{r.stderr.strip()[:200]!r}{' left ' + str(left) if left else ''}")
# A cue's text has no byte limit (it was 255): what fits the band's lines is
# the rule, so a teacher's several sentences fit a 1280x720 frame.
CUE = ("Now the spring is stiffer. Watch how the bouncing slows and the swing grows; the energy "
       "moves between the two motions. Count the swings between two exchanges, then compare "
       "with the next run, where the stiffness is back at its first value. Which one exchanges "
       "faster, and why?")
with open(os.path.join(work, "longcue.ini"), "w") as f:
    f.write(BASE + f"1 = caption: {CUE}\n")
r = run("still", "longcue.ini", "--at", "2", "--size", "1280x720", "-o", "longcue.png")
back = run("scene", "longcue.png")
ok(len(CUE.encode()) > 255 and r.returncode == 0 and f'caption: "{CUE}"' in back.stdout,
   f"a {len(CUE.encode())}-byte cue caption renders and is recorded whole ({r.stderr.strip()[-200:]})")
r = run("render", lesson, "--set", "timeline.3=speed 2", "-o", "set.mp4", *SMALL)
ok(r.returncode == 2 and "[timeline] is read from the scene file" in r.stderr
   and not os.path.exists(os.path.join(work, "set.mp4")), "--set timeline.* is refused")
# a slow motion too long to render is refused with the timeline's length
path = os.path.join(work, "long.ini")
with open(path, "w") as f:
    f.write(BASE + "1 = speed 0.0001\n")
r = run("render", path, "-o", "long.mp4", "-q")
ok(r.returncode == 2 and "the [timeline]'s speeds and pauses make the video" in r.stderr
   and "at most 1000000 are allowed" in r.stderr and not os.path.exists(os.path.join(work, "long.mp4")),
   f"a timeline whose video would exceed the frame limit is refused: {r.stderr.strip()[:200]}")
# a slow motion of 1e-300: the frame count is a number, not 300 digits
path = os.path.join(work, "tiny.ini")
with open(path, "w") as f:
    f.write(BASE + "0 = speed 1e-300\n")
r = run("render", path, "-o", "tiny.mp4", "-q")
ok(r.returncode == 2 and "tiny.ini:5: [timeline]" in r.stderr
   and "frame times; at most 1000000000" in r.stderr and len(r.stderr) < 400
   and not os.path.exists(os.path.join(work, "tiny.mp4")),
   f"speed 1e-300: refused in one short line ({len(r.stderr)} bytes)")
# a time longer than 64 bytes was cut to its first 64 (0.000...05 read as 0)
path = os.path.join(work, "longtime.ini")
with open(path, "w") as f:
    f.write(BASE + "0.0000000000000000000000000000000000000000000000000000000000000001e7"
            " = caption: x\n")
r = run("still", path, "-o", "longtime.png", "-q")
ok(r.returncode == 2 and "longtime.ini:5: [timeline] time" in r.stderr
   and "at most 64" in r.stderr and not os.path.exists(os.path.join(work, "longtime.png")),
   f"a 68-byte time (1e-64 * 1e7 is beyond the video) is refused, not cut: {r.stderr.strip()[:200]!r}")
# too many cues: said once, not once a line
path = os.path.join(work, "many.ini")
with open(path, "w") as f:
    f.write(BASE + "".join(f"{i * 0.01:.2f} = caption: c{i}\n" for i in range(1500)))
r = run("still", path, "-o", "many.png", "-q")
ok(r.returncode == 2 and r.stderr.count("more than 1000 cues") == 1
   and "many.ini:1005: " in r.stderr and not os.path.exists(os.path.join(work, "many.png")),
   f"1500 cues: one message at line 1005, {r.stderr.count(chr(10))} lines of stderr")
# quoted texts are read whole, and comments may follow any cue
path = os.path.join(work, "quoted.ini")
with open(path, "w") as f:
    f.write(BASE + '0 = caption: "Run #3; all of it"   # a comment\n2 = speed 0.5  ; slower\n'
            '3 = pause 1   # no note\n4 = pause 2: "note #1"  # a comment\n[view]\npanels = none\n')
if shutil.which("pdftotext"):
    texts = []
    for t in (1, 4):
        r = run("still", path, "--at", str(t), "-o", f"quoted{t}.pdf", "--size", "640x360", "-q")
        texts.append(" ".join(subprocess.run(["pdftotext", os.path.join(work, f"quoted{t}.pdf"), "-"],
                                             capture_output=True, text=True).stdout.split())
                     if r.returncode == 0 else r.stderr)
    j = json.loads(run("info", path, "--json").stdout or "{}")
    ok("Run #3; all of it" in texts[0] and "note #1" in texts[1] and "comment" not in " ".join(texts)
       and abs(j.get("video_length", 0) - (2 + 0.5 + (40 - 2 - 0.375) / 0.5 + 3)) < 1e-9,
       f"quoted texts are read whole, comments after cues ignored: {texts}, {j.get('video_length')}")
else:
    skip("quoted texts", "pdftotext is not installed")
# the caption band's check follows the frame: what fits at 1280x720 does not at 320x180
path = os.path.join(work, "fits.ini")
with open(path, "w") as f:
    f.write(BASE + "3 = caption: " + " ".join(["words"] * 30) + "\n")
ok(run("still", path, "--size", "1280x720", "-o", "fits.png", "-q").returncode == 0
   and run("still", path, "--size", "320x180", "-o", "fits2.png", "-q").returncode == 2,
   "a caption that fits at 1280x720 is refused at 320x180")

# ---- data and sweep ignore the timeline -------------------------------------------
plain = os.path.join(work, "plain.ini")
with open(lesson) as f:
    text = f.read()
with open(plain, "w") as f:
    f.write(text[:text.index("\n[timeline]\n") + 1])
d1, d2 = run("data", lesson, "-o", "-"), run("data", plain, "-o", "-")
ok(d1.returncode == 0 and d1.stdout == d2.stdout and len(d1.stdout.splitlines()) == 1201,
   "data writes the same rows with and without the timeline (frame times of [video] speed)")
sw = ["--vary", "initial.angle=1:3:2", "--measure", "lyapunov", "--time", "2", "-q", "--threads", "1"]
s1 = run("sweep", lesson, *sw, "--csv", "s1.csv", "-o", "s1.png")
s2 = run("sweep", plain, *sw, "--csv", "s2.csv", "-o", "s2.png")
rows = [open(os.path.join(work, n)).read().splitlines()[1:] if os.path.exists(os.path.join(work, n))
        else None for n in ("s1.csv", "s2.csv")]
ok(s1.returncode == 0 and s2.returncode == 0 and rows[0] and rows[0] == rows[1],
   "sweep gives the same rows with and without it (the header names the scene)")
ok("ignores" in run("data", "--help").stdout and "ignores it" in run("sweep", "--help").stdout
   and "round(length * fps)" in run("render", "--help").stdout
   and "caption in force" in run("still", "--help").stdout,
   "--help: data and sweep say they ignore the timeline; render says how the length follows")
# A timeline of captions only keeps the video's frames and times.
cap = os.path.join(work, "captions.ini")
with open(cap, "w") as f:
    f.write(text[:text.index("\n[timeline]\n") + 1] + "[timeline]\n0 = caption: a\n5 = caption: b\n")
b = subprocess.run([exe, "render", cap, "--format", "raw", "-o", "-", *SMALL, "--set", "video.fps=5",
                    "--set", "video.duration=8"], capture_output=True, cwd=work)
ok(b.returncode == 0 and len(b.stdout) == 40 * W * H * 4,
   "captions alone keep round(duration * fps / speed) frames")
done()
