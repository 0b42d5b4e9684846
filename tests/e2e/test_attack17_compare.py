#!/usr/bin/env python3
"""springpend tests (issue 28): the seventeenth attacker's pass
(doc/notes/2026-11-27/attack17.md), findings 12, 13 and 14, all compare:
- #12: a file on one side and a folder of the same name on the other was
  reported as "no baseline" / "no actual image" with an --update=missing
  hint that then failed; now one error saying what is where ("a/x.png is a
  folder, e/x.png a file: one of them is misplaced"), exit 2, no hint, and
  --update leaves both sides as they were;
- #13: compare.ini's `mask = 0, 0, W, H` made --max-pixels 0 --max-diff 0
  pass any image; under a command-line limit compare.ini's masks may hide at
  most half an image (pixels under several masks counted once), else the
  image is an error naming the masks and the share, in text, JSON, JUnit
  and the Markdown summary; small masks still work, and without a
  command-line limit compare.ini decides alone;
- #14: in folder mode a symbolic link at a diff image's path was replaced
  without a word; it is refused before anything is compared (exit 2, the
  link and its target untouched), as every other output is.
The images are made here, the masked shares computed here from the
rectangles. Links and a FIFO live in this test's own output folder only.
usage: test_attack17_compare.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import os
import shutil
import struct
import subprocess
import xml.etree.ElementTree as ET
import zlib

import sptest
from sptest import done, err, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack17-compare")

W = H = 100
N = W * H
BASE = 128
G = {(x, y) for x in range(20, 24) for y in range(20, 25)}  # 20 px moved by 100 levels


def write_png(name, pix):
    """An 8-bit RGB PNG W x H from pix(x, y) -> grey level."""
    rows = b"".join(b"\0" + bytes(c for x in range(W) for c in (pix(x, y),) * 3) for y in range(H))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    with open(name, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def pair(e, a, name="x.png", moved=True):
    for d in (e, a):
        os.makedirs(d, exist_ok=True)
    write_png(os.path.join(e, name), lambda x, y: BASE)
    write_png(os.path.join(a, name), lambda x, y: BASE + (100 if moved and (x, y) in G else 0))


def union(masks):
    """Pixels of the W x H image under any of masks (x, y, w, h), counted once."""
    return len({(x, y) for (mx, my, mw, mh) in masks
                for x in range(max(mx, 0), min(mx + mw, W)) for y in range(max(my, 0), min(my + mh, H))})


def out(r):
    return r.stdout.decode(errors="replace")


# ---- 13: masks under a command-line limit ------------------------------------------------------
E, A = "e13", "a13"
pair(path(E), path(A))
ini = path(E, "compare.ini")
STRICT = ["--max-pixels", "0", "--max-diff", "0"]


def masked(masks, *args):
    with open(ini, "w") as f:
        f.write("[*]\n" + "".join(f"mask = {m[0]}, {m[1]}, {m[2]}, {m[3]}\n" for m in masks))
    return run("compare", E, A, *args)


whole = [(0, 0, W, H)]
r = masked(whole, *STRICT, "--json", "--junit", "j.xml", "--summary", "s.md")
ok(r.returncode == 2, f"#13: a mask over the whole image under --max-pixels 0 --max-diff 0: exit "
   f"{r.returncode} (2: not judged; was 0, any image passed)")
try:
    rec = json.loads(out(r))["results"][0]
except (ValueError, KeyError, IndexError):
    rec = {}
e = rec.get("error") or ""
ok(rec.get("pass") is False and rec.get("verdict") == "error" and "0, 0, 100, 100" in e and
   f"{union(whole)} of the {N} pixels" in e and "100.0%" in e and "at most half" in e,
   f"#13: the JSON's record is an error naming the mask and the share: {rec.get('verdict')}: {e!r}")
junit = open(path("j.xml"), encoding="utf-8").read() if os.path.exists(path("j.xml")) else ""
try:
    jtext = " ".join(ET.fromstring(junit).itertext()) + " ".join(
        el.get("message", "") for el in ET.fromstring(junit).iter("error"))
except ET.ParseError:
    jtext = ""
ok("<error" in junit and "0, 0, 100, 100" in jtext and "at most half" in jtext,
   "#13: the JUnit has an <error> naming the mask and saying why")
md = open(path("s.md"), encoding="utf-8").read() if os.path.exists(path("s.md")) else ""
ok("0, 0, 100, 100" in md and "at most half" in md and "10000 of the 10000" in md,
   "#13: the Markdown summary names the mask and the share")
r = masked(whole, *STRICT)
ok(r.returncode == 2 and "ERROR x.png" in out(r) and "at most half" in out(r) and
   "ok: 1 compared, 1 passed" not in out(r),
   f"#13: the text says ERROR x.png with the reason: {out(r).splitlines()[:1]}")
for opt in (["--max-pixels", "0"], ["--max-diff", "0"], ["--tol", "0", "--metric", "rms"],
            ["--threshold", "0", "--metric", "pixelmatch"]):
    r = masked(whole, *opt)
    ok(r.returncode == 2 and "at most half" in out(r),
       f"#13: {' '.join(opt)} alone is a command-line limit: the whole-image mask refused "
       f"(exit {r.returncode})")
r = masked(whole)
ok(r.returncode == 0, f"#13: without a command-line limit compare.ini decides, its whole-image "
   f"mask included: exit {r.returncode} (0)")
r = masked(whole, "--metric", "reftest")
ok(r.returncode == 0, f"#13: --metric alone is no limit: exit {r.returncode} (0)")

small = [(20, 20, 4, 5)]  # the moved pixels exactly: a clock
r = masked(small, *STRICT, "--json")
try:
    rec = json.loads(out(r))["results"][0]
except (ValueError, KeyError, IndexError):
    rec = {}
ok(r.returncode == 0 and rec.get("pass") is True and rec.get("measured", {}).get("masked_pixels") == union(small) == 20,
   f"#13: a small mask over what moved still passes under --max-pixels 0 --max-diff 0: exit "
   f"{r.returncode}, masked_pixels {rec.get('measured', {}).get('masked_pixels')} (20)")
r = masked([], *STRICT)
ok(r.returncode == 1, f"#13: without the mask the same pair fails: exit {r.returncode} (1)")
half = [(0, 0, 50, 100)]
r = masked(half, *STRICT)
ok(r.returncode == 0 and union(half) * 2 == N, f"#13: a mask over exactly half passes: exit "
   f"{r.returncode} (0)")
over = [(0, 0, 51, 100)]
r = masked(over, *STRICT)
ok(r.returncode == 2 and f"{union(over)} of the {N} pixels (51.0%)" in out(r),
   f"#13: a mask over 51% is refused with its share: exit {r.returncode}")
# overlapping masks: each under half, their sum over half, their union under it
ovl = [(0, 0, 30, 100), (10, 0, 30, 100)]
r = masked(ovl, *STRICT, "--json")
try:
    rec = json.loads(out(r))["results"][0]
except (ValueError, KeyError, IndexError):
    rec = {}
ok(r.returncode == 0 and rec.get("measured", {}).get("masked_pixels") == union(ovl) == 4000,
   f"#13: two overlapping masks (sum 6000, union {union(ovl)}) are counted once and pass: exit "
   f"{r.returncode}, masked_pixels {rec.get('measured', {}).get('masked_pixels')}")
ovl2 = [(0, 0, 40, 100), (30, 0, 40, 100), (0, 0, 10, 10)]
r = masked(ovl2, *STRICT)
ok(r.returncode == 2 and f"{union(ovl2)} of the {N} pixels (70.0%)" in out(r) and
   "0, 0, 40, 100; 30, 0, 40, 100; 0, 0, 10, 10" in out(r),
   f"#13: three masks over 70% in all (union {union(ovl2)}, not the sum 8100) are refused, each "
   f"named: {out(r).splitlines()[:1]}")
os.unlink(ini)

# ---- 14: a link at a folder-mode diff image's path ---------------------------------------------
E, A, D = "e14", "a14", "d14"
pair(path(E), path(A))
pair(path(E), path(A), "y.png", moved=False)
os.makedirs(path(D))
with open(path("target.txt"), "w") as f:
    f.write("secret\n")
link = path(D, "x.diff.png")


def intact(lnk, to):
    return os.path.islink(lnk) and os.readlink(lnk) == to


def clear(*names):
    """Removes what is at each path (the old build left diff images)."""
    for n in names:
        if os.path.lexists(n):
            os.unlink(n)


os.symlink("../target.txt", link)
r = run("compare", E, A, "--diff", D, "--report", "r14.html", "--summary", "s14.md")
ok(r.returncode == 2 and "is a symbolic link" in err(r) and "x.diff.png" in err(r),
   f"#14: a link at a failing image's diff path refused: exit {r.returncode} (2; was 1, the link "
   f"replaced): {err(r)[:160]!r}")
ok(intact(link, "../target.txt") and open(path("target.txt")).read() == "secret\n",
   "#14: the link and its target stay as they were")
ok("FAIL" not in out(r) and not os.path.exists(path("r14.html")) and
   not os.path.exists(path("s14.md")), "#14: refused before comparing: no result, no report")
clear(link)
os.symlink("nowhere.png", link)
r = run("compare", E, A, "--diff", D)
ok(r.returncode == 2 and intact(link, "nowhere.png"), f"#14: a dangling link refused and left: "
   f"exit {r.returncode}")
clear(link)
ylink = path(D, "y.diff.png")
os.symlink("../target.txt", ylink)
r = run("compare", E, A, "--diff", D)
ok(r.returncode == 2 and intact(ylink, "../target.txt"),
   f"#14: a link at a passing image's diff path refused too (before comparing): exit {r.returncode}")
clear(ylink, link)
os.mkfifo(path("fifo"))
os.symlink("../fifo", link)
try:
    r = run("compare", E, A, "--diff", D, timeout=20)
    rc = r.returncode
except subprocess.TimeoutExpired:
    rc = "hung"
ok(rc == 2 and intact(link, "../fifo"), f"#14: a link to a FIFO refused, not waited on: {rc}")
clear(link)
os.symlink("../sub", link)
os.makedirs(path("sub"))
r = run("compare", E, A, "--diff", D)
ok(r.returncode == 2 and intact(link, "../sub") and os.listdir(path("sub")) == [],
   f"#14: a link to a folder refused, nothing written in it: exit {r.returncode}")
clear(link)
with open(link, "w") as f:
    f.write("stale")
r = run("compare", E, A, "--diff", D)
ok(r.returncode == 1 and not os.path.islink(link) and open(link, "rb").read(8) == b"\x89PNG\r\n\x1a\n",
   f"#14: a stale regular diff is still replaced by the new one: exit {r.returncode} (1)")
cand = path("c14")
clear(link)
os.symlink("../target.txt", link)
r = run("compare", E, A, "--diff", D, "--candidates", "c14")
ok(r.returncode == 2 and not os.path.exists(cand) and intact(link, "../target.txt"),
   f"#14: refused with --candidates: the candidates folder it would have made is not left: exit "
   f"{r.returncode}")

# ---- 12: a file on one side, a folder of the same name on the other ---------------------------
E, A = "e12", "a12"
os.makedirs(path(E))
os.makedirs(path(A, "x.png"))
write_png(path(E, "x.png"), lambda x, y: BASE)
write_png(path(A, "x.png", "inner.png"), lambda x, y: BASE)
os.makedirs(path(E, "y.png"))
write_png(path(E, "y.png", "z.png"), lambda x, y: BASE)
write_png(path(A, "y.png"), lambda x, y: BASE)
pair(path(E), path(A), "ok.png", moved=False)
before = {p: open(path(E, p), "rb").read() for p in ("x.png", "y.png/z.png")}
r = run("compare", E, A)
t = out(r)
ok(r.returncode == 2, f"#12: exit {r.returncode} (2)")
ok("a12/x.png is a folder, e12/x.png a file: one of them is misplaced" in t,
   "#12: the actual folder beside the baseline file is named as such")
ok("e12/y.png is a folder, a12/y.png a file: one of them is misplaced" in t,
   "#12: the baseline folder beside the actual file is named as such")
ok("e12/x.png is a file, a12/x.png a folder" in t and "e12/y.png is a folder" in t and
   "no baseline" not in t and "no actual image" not in t,
   "#12: the images inside the misplaced folders say the same, not 'no baseline' / 'no actual image'")
ok("--update" not in t, "#12: no --update=missing hint offered where it cannot work")
ok("ok.png" in t and "1 passed" in t, "#12: the other images are still compared")
for mode in ("--update=missing", "--update=all"):
    r = run("compare", E, A, mode)
    now = {p: open(path(E, p), "rb").read() if os.path.isfile(path(E, p)) else None for p in before}
    ok(r.returncode == 2 and now == before and "Not a directory" not in err(r) and
       not os.path.exists(path(E, "x.png.part")),
       f"#12: {mode} leaves both sides as they were (exit {r.returncode}; {err(r)[:120]!r})")
r = run("compare", E, A, "--json")
try:
    recs = {x["name"]: x for x in json.loads(out(r))["results"]}
except (ValueError, KeyError):
    recs = {}
ok(all("misplaced" in (recs.get(n, {}).get("error") or "") and not recs[n].get("hint", "").count("--update")
       for n in ("x.png", "x.png/inner.png", "y.png", "y.png/z.png")),
   "#12: the JSON's four records say misplaced, with no --update hint")
done()
