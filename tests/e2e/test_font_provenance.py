#!/usr/bin/env python3
"""springpend tests: the rest of the attacker's fourth pass, finding 6
(doc/notes/2026-11-26d/attack4.md; issue 28):
- compare counts a PNG's unread text chunks once: a forged zTXt that
  inflates past the bound is said once, "1 text chunk not read", as
  `scene` says it (compare read the text once per key and said it each
  time, so one chunk was counted several times);
- the built-in font is named as built in, "DejaVu Sans (embedded in
  springpend)", never by a system path that may not exist, alike in a
  still's and a sweep's PNG (springpend.fonts), a PDF's /Keywords, an MP4's
  tags and the environment's font line, whose SHA-256 is computed here
  from the file the build embedded (meson_options.txt's font).
The font hash of the bytes drawn (not of the path reopened) is
test_font_bytes.c's.
usage: test_font_provenance.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import hashlib
import json
import os
import re
import shutil
import struct
import subprocess
import zlib

import sptest
from sptest import done, err, ok, png_text

exe, src, work, _ = sptest.setup("font_provenance", ["pdfinfo", "ffprobe"])
run = sptest.runner_bytes(exe, work)
scenes = os.path.join(src, "..", "scenes")
default = os.path.join(scenes, "default.ini")
chaotic = os.path.join(scenes, "chaotic.ini")
NAME = "DejaVu Sans (embedded in springpend)"
OLD = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"


def path(*names):
    return os.path.join(work, *names)


def forge_bomb(png, out):
    """png with a zTXt chunk inflating to 4 MiB of zeros before its IDAT."""
    data = open(png, "rb").read()
    body = b"bomb\0\0" + zlib.compress(b"\0" * (4 << 20), 9)
    chunk = struct.pack(">I", len(body)) + b"zTXt" + body + \
        struct.pack(">I", zlib.crc32(b"zTXt" + body) & 0xffffffff)
    i = data.index(b"IDAT") - 4
    open(out, "wb").write(data[:i] + chunk + data[i:])


# 1. compare says a dropped text chunk once
a, bomb = path("a.png"), path("bomb.png")
r = run("still", default, "--at", "1", "--size", "160x90", "-o", a)
forge_bomb(a, bomb)
for args in [("compare", a, bomb), ("scene", bomb)]:
    r = run(*args)
    said = [line for line in err(r).splitlines() if "text chunk" in line]
    ok(len(said) == 1 and "1 text chunk not read" in said[0],
       f"{args[0]} says the forged PNG's dropped text chunk once ({said})")

# 2. the built-in font's name, the same in every output
font_file = None  # meson_options.txt's default for -Dfont (what a plain build embeds)
m = re.search(r"option\('font'[^)]*value\s*:\s*'([^']+)'",
              open(os.path.join(src, "..", "meson_options.txt")).read())
if m:
    font_file = m.group(1)
emb_hash = hashlib.sha256(open(font_file, "rb").read()).hexdigest() \
    if font_file and os.path.exists(font_file) else None
s_png = path("s.png")
r = run("still", default, "--at", "1", "--size", "320x180", "--set", "view.title=Federpendel",
        "-o", s_png)
t = png_text(s_png, compressed=True) if r.returncode == 0 else {}
ok(t.get("springpend.fonts") == NAME,
   f"a still's springpend.fonts names the built-in font as such ({t.get('springpend.fonts')!r})")
envl = [line for line in t.get("springpend.environment", "").splitlines() if line.startswith("font:")]
ok(len(envl) == 1 and envl[0].startswith("font: " + NAME[:-1] + ", ") and OLD not in envl[0]
   and (emb_hash is None or envl[0].endswith("sha256 " + emb_hash)),
   f"the environment's font line names it and its SHA-256 ({envl}; the build's file "
   f"{font_file}: {emb_hash})")
s_pdf = path("s.pdf")
r = run("still", default, "--at", "1", "--size", "320x180", "--set", "view.title=Federpendel",
        "-o", s_pdf)
info = subprocess.run(["pdfinfo", s_pdf], capture_output=True, text=True).stdout
kw = [line for line in info.splitlines() if line.startswith("Keywords:")]
ok(kw and kw[0].split(":", 1)[1].strip() == "fonts: " + NAME,
   f"a still's PDF /Keywords names it alike ({kw})")
w_png = path("w.png")
r = run("sweep", chaotic, "--vary", "initial.angle=1:179:4", "--measure", "lyapunov", "--time", "2",
        "-o", w_png)
t = png_text(w_png, compressed=True) if r.returncode == 0 else {}
ok(t.get("springpend.fonts") == NAME,
   f"a sweep figure's springpend.fonts names it alike ({t.get('springpend.fonts')!r}; {err(r)[-200:]})")
mp4 = path("v.mp4")
r = run("render", default, "--set", "video.duration=0.2", "--size", "320x180", "--set", "view.title=Federpendel",
        "-o", mp4, timeout=120)
tags = {}
if r.returncode == 0:
    probe = subprocess.run(["ffprobe", "-v", "error", "-show_entries", "format_tags", "-of", "json", mp4],
                           capture_output=True, text=True).stdout
    tags = json.loads(probe).get("format", {}).get("tags", {})
ok(tags.get("springpend.fonts") == NAME and OLD not in tags.get("springpend.environment", ""),
   f"an MP4's springpend.fonts tag names it alike ({tags.get('springpend.fonts')!r}; {err(r)[-200:]})")

done()
