#!/usr/bin/env python3
"""springpend tests (issue 28): the nineteenth attacker's pass
(doc/notes/2026-11-28/attack19.md), finding 5: output names the folder
can hold (up to NAME_MAX, 255 bytes) but NAME.XXXXXX.part cannot (244 to
255 bytes) were never written: "cannot create NAME.XXXXXX.part: File name
too long", exit 1, for still, data, render and compare's --diff, --report
and --summary. Such a target is now written through
FOLDER/springpend-XXXXXX.part (O_EXCL, in the same folder, removed on a
signal); a name the folder cannot hold, or a CSV whose NAME-metadata.json
partner it cannot (data, sweep --csv), is refused before any work: what is
wrong, what is allowed, exit 2, nothing written. (Finding 6, the guides'
folder holding only `copyright`, is checked in test_install.py.)
The lengths come from os.pathconf of the test's folder, the files' kinds
from their own first bytes, never from springpend's words.
usage: test_attack19_names.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import os
import signal
import struct
import subprocess
import threading
import time
import zlib

import sptest
from sptest import done, err, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack19-names")
scene = os.path.join(scenes, "default.ini")
MAX = os.pathconf(work, "PC_NAME_MAX")
META = "-metadata.json"


def name(n, ext, fill="a"):
    """A name of exactly n bytes ending in ext."""
    return fill * (n - len(ext)) + ext


def fresh(sub):
    """A fresh empty folder under the test's, and a runner there."""
    d = path(sub)
    os.makedirs(d)
    return d, sptest.runner_bytes(exe, d)


def left(d, *expected):
    """What d holds beyond the names expected (sorted)."""
    return sorted(set(os.listdir(d)) - set(expected))


def png_size(p):
    """(width, height) from a PNG's IHDR, or None when it is not a PNG (or not there)."""
    try:
        with open(p, "rb") as f:
            head = f.read(24)
    except OSError:
        return None
    return struct.unpack(">II", head[16:24]) if head[:8] == b"\x89PNG\r\n\x1a\n" else None


def write_png(p, level):
    """A 20 x 20 grey PNG at one level."""
    rows = b"".join(b"\0" + bytes([level] * 60) for _ in range(20))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    os.makedirs(os.path.dirname(p), exist_ok=True)
    with open(p, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 20, 20, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


# ---- names of MAX - 1 bytes are written whole, nothing left beside them ----
d, r_ = fresh("still")
png = name(MAX - 1, ".png")
r = r_("still", scene, "--at", "1", "--size", "160x90", "-o", png, "-q")
ok(r.returncode == 0 and png_size(os.path.join(d, png)) == (160, 90) and not left(d, png),
   f"5: still -o a {len(png)}-byte name: a 160x90 PNG written, nothing else left "
   f"(exit {r.returncode}: {err(r)[-160:]}; left {left(d, png)})")

d, r_ = fresh("render")
mp4 = name(MAX - 1, ".mp4")
r = r_("render", scene, "--size", "160x90", "--set", "video.duration=0.5", "-o", mp4, "-q")
head = open(os.path.join(d, mp4), "rb").read(12) if os.path.exists(os.path.join(d, mp4)) else b""
ok(r.returncode == 0 and head[4:8] == b"ftyp" and not left(d, mp4),
   f"5: render -o a {len(mp4)}-byte name: an MP4 written, nothing else left "
   f"(exit {r.returncode}: {err(r)[-160:]}; left {left(d, mp4)})")

# data: the CSV's metadata must fit too, so the longest CSV name is MAX - 14
d, r_ = fresh("data")
csv = name(MAX - len(META), ".csv")
r = r_("data", scene, "--set", "video.duration=1", "-o", csv, "-q")
rows = open(os.path.join(d, csv)).read().splitlines() if os.path.exists(os.path.join(d, csv)) else []
try:
    meta = json.load(open(os.path.join(d, csv + META)))
except (OSError, ValueError):
    meta = None
ok(r.returncode == 0 and len(rows) > 2 and rows[0].startswith("t,") and meta is not None
   and len(csv + META) == MAX and not left(d, csv, csv + META),
   f"5: data -o a {len(csv)}-byte CSV: the rows and its {len(csv + META)}-byte metadata (JSON) "
   f"written, nothing else left (exit {r.returncode}: {err(r)[-160:]}; {len(rows)} lines; "
   f"left {left(d, csv, csv + META)})")

d, r_ = fresh("compare")
write_png(os.path.join(d, "e", "x.png"), 100)
write_png(os.path.join(d, "a", "x.png"), 200)
diff, report, summary = name(MAX - 1, ".png", "d"), name(MAX, ".html", "r"), name(MAX - 2, ".md", "s")
r = r_("compare", "e/x.png", "a/x.png", "--diff", diff)
ok(r.returncode == 1 and png_size(os.path.join(d, diff)) == (20, 20) and not left(d, "e", "a", diff),
   f"5: compare --diff a {len(diff)}-byte name: the diff image written (the pair differs: exit 1), "
   f"nothing else left (exit {r.returncode}: {err(r)[-160:]}; left {left(d, 'e', 'a', diff)})")
if os.path.exists(os.path.join(d, diff)):
    os.unlink(os.path.join(d, diff))
r = r_("compare", "e", "a", "--report", report, "--summary", summary)
html = open(os.path.join(d, report), "rb").read() if os.path.exists(os.path.join(d, report)) else b""
md = open(os.path.join(d, summary), "rb").read() if os.path.exists(os.path.join(d, summary)) else b""
ok(r.returncode == 1 and html.rstrip().endswith(b"</html>") and b"x.png" in md
   and not left(d, "e", "a", report, summary),
   f"5: compare --report ({len(report)} bytes) and --summary ({len(summary)} bytes): both written "
   f"whole, nothing else left (exit {r.returncode}: {err(r)[-160:]}; "
   f"left {left(d, 'e', 'a', report, summary)})")

# ---- refused up front: exit 2, what is wrong and what is allowed, nothing written ----
d, r_ = fresh("refused")
long_csv = name(MAX - 1, ".csv")
r = r_("data", scene, "-o", long_csv, "-q")
ok(r.returncode == 2 and f"at most {MAX - len(META)} bytes" in err(r) and "metadata" in err(r)
   and not os.listdir(d),
   f"5: data -o a {len(long_csv)}-byte CSV, whose metadata cannot be named beside it: refused, "
   f"exit 2, the longest name allowed said, nothing written (exit {r.returncode}: "
   f"{err(r)[-200:]}; left {os.listdir(d)})")
shard = name(MAX - len(META) + 1, ".csv")
r = r_("sweep", os.path.join(scenes, "chaotic.ini"), "--vary", "initial.angle=30:31:2", "--measure",
       "lyapunov", "--time", "2", "--csv", shard, "--shard", "1/2", "-q")
ok(r.returncode == 2 and f"at most {MAX - len(META)} bytes" in err(r) and not os.listdir(d),
   f"5: a sweep shard's --csv of {len(shard)} bytes (its -metadata.json would be {len(shard + META)}): "
   f"refused, exit 2, nothing written (exit {r.returncode}: {err(r)[-200:]}; left {os.listdir(d)})")
shard = name(MAX - len(META), ".csv")
r = r_("sweep", os.path.join(scenes, "chaotic.ini"), "--vary", "initial.angle=30:31:2", "--measure",
       "lyapunov", "--time", "2", "--csv", shard, "--shard", "1/2", "-q")
ok(r.returncode == 0 and not left(d, shard, shard + META),
   f"5: a sweep shard's --csv of {len(shard)} bytes: the rows and the metadata written, nothing "
   f"else left (exit {r.returncode}: {err(r)[-200:]}; left {left(d, shard, shard + META)})")
for f in os.listdir(d):
    os.unlink(os.path.join(d, f))
over = name(MAX + 1, ".png")
r = r_("still", scene, "--at", "1", "--size", "160x90", "-o", over, "-q")
ok(r.returncode == 2 and f"the name is {MAX + 1} bytes" in err(r) and f"at most {MAX}" in err(r)
   and not os.listdir(d),
   f"5: still -o a {len(over)}-byte name the folder cannot hold: refused, exit 2, the limit said, "
   f"nothing written (exit {r.returncode}: {err(r)[-200:]}; left {os.listdir(d)})")

# ---- the short .part keeps the guarantees: two runs at once, a signal ----
d, r_ = fresh("twice")
results = [None, None]


def still_at(i):
    results[i] = r_("still", scene, "--at", str(1 + i), "--size", "160x90", "-o", png, "-q")


threads = [threading.Thread(target=still_at, args=(i,)) for i in range(2)]
for t in threads:
    t.start()
for t in threads:
    t.join()
ok(all(x.returncode == 0 for x in results) and png_size(os.path.join(d, png)) == (160, 90)
   and not left(d, png),
   f"5: two stills at once to one {len(png)}-byte name: both finish, one whole PNG, no .part left "
   f"({[(x.returncode, err(x)[-80:]) for x in results]}; left {left(d, png)})")

d, _ = fresh("signal")
p = subprocess.Popen([exe, "render", scene, "--size", "160x90", "--set", "video.duration=600", "-o", mp4, "-q"],
                     cwd=d, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
sptest.wait_caught(p, signal.SIGTERM)
end = time.time() + 30
while time.time() < end and p.poll() is None and not sptest.part_files(d):
    time.sleep(0.05)
seen = sptest.part_files(d)
p.send_signal(signal.SIGTERM)
time.sleep(0.3)
if p.poll() is None:
    p.send_signal(signal.SIGTERM)
try:
    _, said = p.communicate(timeout=30)
except subprocess.TimeoutExpired:
    p.kill()
    _, said = p.communicate()
ok(p.returncode == 128 + signal.SIGTERM and seen and all(len(s) < 40 for s in seen)
   and not sptest.part_files(d),
   f"5: render to a {len(mp4)}-byte name stopped by SIGTERM: its short .part ({seen}) is gone, exit 143 "
   f"(exit {p.returncode}: {said.decode(errors='replace').strip()[-160:]}; left {os.listdir(d)})")
done()
