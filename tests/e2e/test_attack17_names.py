#!/usr/bin/env python3
"""springpend tests (issue 28): the seventeenth attacker's pass
(doc/notes/2026-11-27/attack17.md), findings 2, 3 and 8: names cut or left
out.
- #2: libinih keeps the first 49 bytes of a `[section]` name (its
  MAX_SECTION, 50 in Debian's build) and says nothing: an image's own
  section of 50+ bytes was dropped (with a warning naming a section nobody
  wrote), `[FOLDER/*_clock.png]` widened to all of FOLDER, two sections
  alike in their first 49 bytes were "the same section twice". compare.ini
  reads section names whole now; a scene's over-long [section] or key is
  refused and named whole (FILE:LINE, exit 2);
- #3: compare's record names were cut at 255 bytes, so two images under a
  deep folder were reported under one name (text, JSON, JUnit, Markdown,
  HTML). Names are kept whole;
- #8: folder mode skipped, unsaid, the video names two-file mode reads
  (.m4v, .h264, .264, .hevc, .h265, .265): one table serves both now, and
  doc/ci.md's two lists agree.
Expected verdicts come from the pixels written here (PNGs built in
Python; videos of one flat colour each made by ffmpeg), never from
springpend's output.
usage: test_attack17_names.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import os
import re
import shutil
import struct
import subprocess
import zlib

import sptest
from sptest import done, err, ok, skip

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack17-names")
root = os.path.abspath(os.path.join(src, ".."))
W = H = 20
MOVED = [(x, y) for x in range(5, 15) for y in range(5, 15)]  # 100 of 400 px moved by 100 levels


def write_png(name, moved):
    """A W x H 8-bit grey-as-RGB PNG at level 100, the MOVED pixels at 200
    when moved."""
    def pix(x, y):
        return 200 if moved and (x, y) in MOVED else 100
    rows = b"".join(b"\0" + bytes(c for x in range(W) for c in (pix(x, y),) * 3) for y in range(H))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    os.makedirs(os.path.dirname(name), exist_ok=True)
    with open(name, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def pair(folder, name, differ):
    """FOLDER/e/NAME and FOLDER/a/NAME; the actual one moved when differ."""
    write_png(path(folder, "e", name), False)
    write_png(path(folder, "a", name), differ)


def verdicts(r):
    """{name: 'FAIL' | 'ok' | 'ERROR'} from compare's text lines."""
    out = {}
    for line in r.stdout.decode(errors="replace").splitlines():
        m = re.match(r"^(FAIL|ok  |ERROR) (.*?): ", line)
        if m:
            out[m.group(2)] = m.group(1).strip()
    return out


# Every pair's verdict here, computed from the pixels: 100 of 400 pixels
# moved by 100 levels fail any rule that allows fewer than 100 pixels
# moved by more than 99 levels (the default allows 0.1%: 0 of 400), and
# pass `max_pixels = 100%`; identical pixels pass any rule.

# ---- 2: compare.ini's section names are read whole ------------------------------------------------
LONG = "snapshot-of-the-default-scene-at-one-second-640x360-dark-theme.png"  # 66 bytes
pair("own", LONG, True)
with open(path("own", "e", "compare.ini"), "w") as f:
    f.write(f"[*]\nmax_pixels = 100%\n[{LONG}]\nmax_pixels = 0\n")
r = sptest.runner_bytes(exe, path("own"))("compare", "e", "a")
ok(r.returncode == 1 and verdicts(r).get(LONG) == "FAIL",
   f"2: [{LONG}] (66 bytes) max_pixels = 0 is the image's rule: 100 px moved fail, exit 1 "
   f"(rc {r.returncode}; {verdicts(r)})")
ok("matches no compared image" not in err(r),
   f"2: no warning that the 66-byte section matches nothing ({err(r)[:200]!r})")

D = "screenshots-of-the-lesson-dashboard-widgets-v23"  # 47 bytes: the cut lands after '/*'
pair("wild", f"{D}/energy.png", True)
pair("wild", f"{D}/live_clock.png", False)
with open(path("wild", "e", "compare.ini"), "w") as f:
    f.write(f"[{D}/*_clock.png]\nmax_pixels = 100%\n")
r = sptest.runner_bytes(exe, path("wild"))("compare", "e", "a")
v = verdicts(r)
ok(r.returncode == 1 and v.get(f"{D}/energy.png") == "FAIL" and v.get(f"{D}/live_clock.png") == "ok",
   f"2: [FOLDER/*_clock.png] (60 bytes) does not widen to FOLDER/*: energy.png fails, "
   f"live_clock.png passes, exit 1 (rc {r.returncode}; {v})")

P = "a-folder-whose-name-alone-runs-past-forty-nine-bytes"  # 52 bytes: sections alike in 49
pair("twin", f"{P}/strict.png", True)
pair("twin", f"{P}/loose.png", True)
with open(path("twin", "e", "compare.ini"), "w") as f:
    f.write(f"[{P}/strict.png]\nmax_pixels = 0\n[{P}/loose.png]\nmax_pixels = 100%\n")
r = sptest.runner_bytes(exe, path("twin"))("compare", "e", "a")
v = verdicts(r)
ok(r.returncode == 1 and v.get(f"{P}/strict.png") == "FAIL" and v.get(f"{P}/loose.png") == "ok",
   f"2: two sections alike in their first 49 bytes are two sections: strict fails, loose passes "
   f"(rc {r.returncode}; {v}; {err(r)[:200]!r})")

# the longest section a line holds (198 bytes): read whole, applied
N190 = "n" * 186 + ".png"  # "[" + 190 + "]" = 192 bytes
pair("line", N190, True)
with open(path("line", "e", "compare.ini"), "w") as f:
    f.write(f"[*]\nmax_pixels = 0\n[{N190}]\nmax_pixels = 100%\n")
r = sptest.runner_bytes(exe, path("line"))("compare", "e", "a")
ok(r.returncode == 0 and verdicts(r).get(N190) == "ok" and "matches no" not in err(r),
   f"2: a 190-byte section is read whole and applied: its image passes, exit 0 "
   f"(rc {r.returncode}; {err(r)[:200]!r})")

# scene files: an over-long [section] or key is refused and named whole
with open(os.path.join(scenes, "default.ini")) as f:
    base = f.read()
for what, text, line_no, word in (
        ("section", "[view" + "x" * 60 + "]\ntitle = x\n", None, "view" + "x" * 60),
        ("key", "[view]\ntitle" + "x" * 60 + " = 3\n", None, "title" + "x" * 60)):
    scene = path(f"long-{what}.ini")
    with open(scene, "w") as f:
        f.write(base.rstrip("\n") + "\n" + text)
    line_no = base.rstrip("\n").count("\n") + 2 + (what == "key")
    out = path(f"long-{what}.png")
    r = run("still", scene, "--at", "0", "--size", "64x36", "-o", out, "-q")
    e = err(r)
    ok(r.returncode == 2 and e.startswith(f"{scene}:{line_no}: ") and f"{word}]" in e.replace("'", "]")
       and not os.path.exists(out),
       f"2: a scene's {len(word)}-byte {what} is refused at its line and named whole, exit 2, "
       f"nothing written (rc {r.returncode}; {e[:300]!r})")

# ---- 3: record names are whole ----------------------------------------------------------------------
DEEP = "".join(f"deep-folder-name-{i:02d}/" for i in range(1, 15))  # 280 bytes of folders
pair("deep", DEEP + "x.png", True)
pair("deep", DEEP + "y.png", False)
r = sptest.runner_bytes(exe, path("deep"))("compare", "e", "a", "--junit", "j.xml", "--summary",
                                           "s.md", "--report", "r.html", "--json")
want = {DEEP + "x.png": False, DEEP + "y.png": True}
try:
    got = {c["name"]: c["pass"] for c in json.loads(r.stdout)["results"]}
except (ValueError, KeyError, TypeError) as ex:
    got = f"unreadable: {ex}: {r.stdout[:200]!r}"
ok(r.returncode == 1 and got == want,
   f"3: JSON names both images whole (x fails, y passes; {len(DEEP) + 5}-byte names): "
   f"rc {r.returncode}, {got if not isinstance(got, dict) else sorted((k[-40:], p) for k, p in got.items())}")
r = sptest.runner_bytes(exe, path("deep"))("compare", "e", "a")
v = verdicts(r)
ok(v == {DEEP + "x.png": "FAIL", DEEP + "y.png": "ok"},
   f"3: text lines name both images whole ({sorted((k[-30:], p) for k, p in v.items())})")
junit = open(path("deep", "j.xml")).read() if os.path.exists(path("deep", "j.xml")) else ""
cases = re.findall(r'<testcase classname="([^"]*)" name="([^"]*)"', junit)
blocks = dict(re.findall(r'<testcase [^>]*? name="([^"]*)"[^>]*>(.*?)</testcase>', junit, re.S))
ok(sorted(n for _, n in cases) == ["x.png", "y.png"] and
   all(c.endswith(DEEP.rstrip("/")) for c, _ in cases) and
   blocks.get("x.png", "").count("<failure") == 1 and "<failure" not in blocks.get("y.png", "<failure"),
   f"3: JUnit: two test cases, x.png (failure) and y.png, in the whole folder's suite "
   f"({[(c[-30:], n) for c, n in cases]})")
md = open(path("deep", "s.md")).read() if os.path.exists(path("deep", "s.md")) else ""
ok(DEEP + "x.png" in md.replace("\\", ""),
   f"3: the Markdown summary names the failing image whole ({len(md)} bytes)")
html = open(path("deep", "r.html")).read() if os.path.exists(path("deep", "r.html")) else ""
ok(DEEP + "x.png" in html and DEEP + "y.png" in html,
   f"3: the HTML report names both images whole ({len(html)} bytes)")

# ---- 8: folder mode takes every video name the reader takes ----------------------------------------
ENDINGS = [".m4v", ".h264", ".264", ".hevc", ".h265", ".265"]
ci = sptest.doc_page(root, "ci")
head = ci[:ci.index("How a pair is judged")]
folder_list = set(re.findall(r"\.[a-z0-9]+", re.search(r"`(\.[^`]*)`\s+are videos", head).group(1))) \
    if re.search(r"`(\.[^`]*)`\s+are videos", head) else set()
said = re.search(r"each as its\s+name says: (.*?)\. A file whose", ci, re.S)
read_list = set(re.findall(r"`(\.[a-z0-9]+)`", said.group(1))) if said else set()
ok(read_list and folder_list == read_list and set(ENDINGS) <= read_list,
   f"8: doc/ci.md's folder list and its reader's list agree "
   f"(folder {sorted(folder_list)}, read {sorted(read_list)})")
help_text = run("compare", "--help").stdout.decode()
ok(all(re.search(re.escape(e) + r"[ )\n]", help_text) for e in sorted(read_list or ENDINGS)),
   "8: compare --help lists every video ending folder mode takes")

ENC = {".m4v": ("libx264", "mp4"), ".h264": ("libx264", "h264"), ".264": ("libx264", "h264"),
       ".hevc": ("libx265", "hevc"), ".h265": ("libx265", "hevc"), ".265": ("libx265", "hevc")}
encoders = subprocess.run(["ffmpeg", "-hide_banner", "-encoders"], capture_output=True,
                          text=True).stdout if shutil.which("ffmpeg") else ""


def video(name, colour):
    """A 64x64 video of one flat colour (10 frames at 10 fps) named name
    under the folder 'vid', by ffmpeg with the ending's encoder."""
    enc, fmt = ENC[os.path.splitext(name)[1]]
    os.makedirs(os.path.dirname(path("vid", name)), exist_ok=True)
    r = subprocess.run(["ffmpeg", "-v", "error", "-y", "-f", "lavfi", "-i",
                        f"color=c={colour}:s=64x64:r=10:d=1", "-c:v", enc, "-pix_fmt", "yuv420p",
                        *(["-x265-params", "log-level=error"] if enc == "libx265" else []),
                        "-f", fmt, path("vid", name)], capture_output=True)
    return r.returncode == 0


expect = {}
for e in ENDINGS:
    enc = ENC[e][0]
    if enc not in encoders:
        skip(f"8: folder mode compares {e}", f"ffmpeg with {enc} missing")
        continue
    # white against black: every pixel moved by 255 levels, a failure; and
    # a pair of one file's copies: identical, a pass
    if video(f"e/diff{e}", "white") and video(f"a/diff{e}", "black") and video(f"e/same{e}", "gray"):
        shutil.copy(path("vid", "e", f"same{e}"), path("vid", "a", f"same{e}"))
        expect[f"diff{e}"], expect[f"same{e}"] = "FAIL", "ok"
    else:
        skip(f"8: folder mode compares {e}", "ffmpeg could not make the videos")
write_png(path("vid", "e", "ok.png"), False)
write_png(path("vid", "a", "ok.png"), False)
expect["ok.png"] = "ok"
r = sptest.runner_bytes(exe, path("vid"))("compare", "e", "a", "--junit", "j.xml")
v = verdicts(r)
for name in sorted(expect):
    if name != "ok.png":
        ok(v.get(name) == expect[name],
           f"8: folder mode compares {name}: {expect[name]} expected, {v.get(name)} got")
ok(r.returncode == (1 if "FAIL" in expect.values() else 0) and set(v) == set(expect),
   f"8: the run names every video and exits {1 if 'FAIL' in expect.values() else 0} "
   f"(rc {r.returncode}; {sorted(v)})")

# compare.ini's environment keys may not be a video ending (NAME.h264 is a video)
for key in ("m4v", "h264", "265"):
    d = path(f"env-{key}")
    write_png(os.path.join(d, "e", "x.png"), False)
    write_png(os.path.join(d, "a", "x.png"), False)
    with open(os.path.join(d, "e", "compare.ini"), "w") as f:
        f.write(f"envs = {key}\n[*]\nmax_pixels = 0\n")
    r = sptest.runner_bytes(exe, d)("compare", "e", "a")
    ok(r.returncode == 2 and "compare.ini:1: envs:" in err(r) and "reserved" in err(r),
       f"8: envs = {key} is refused as a video ending, exit 2 (rc {r.returncode}; {err(r)[:160]!r})")

done()
