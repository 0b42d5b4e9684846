#!/usr/bin/env python3
"""springpend tests (issue 28): attack13 #23 (doc/notes/2026-11-27/attack13.md).
A folder compare screens each *.png for a link out of its folder once, when
it walks the folders; every later open (the memory plan, the pair's reader,
the HTML report's embedding, --update's and --candidates' copies) followed
a link wherever it pointed. A process that keeps swapping an actual image
with a link to a PNG outside both folders (renameat2 RENAME_EXCHANGE in a
loop) got compare to judge that PNG, embed it in the report and install it
as a baseline with --update=missing (the old build: several runs of each
kind out of 30; fix18's note gives the counts). Now every open of a path
under a compared folder is resolved beneath that folder (infile.h,
sp_infile_confine): a run may refuse the image ("changed after the folder
was listed ... not read") or compare the real one, never the outside file.
Expected values come from the outside PNG's own bytes: its pixels' SHA-256
as compare defines it (the RGBA rows, then "WxH"), a piece of its base64.
Links within a folder are still followed: a relative one, one through
"../FOLDER/", an absolute one (which openat2 RESOLVE_BENEATH refuses and the
opener then checks by where the file lies).
usage: test_attack13_links.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import base64
import hashlib
import json
import os
import shutil
import struct
import subprocess
import sys
import zlib

import sptest
from sptest import done, err, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack13-links")
RUNS = 30

# A flipper: swaps two names (RENAME_EXCHANGE) until it is killed.
FLIPPER = r"""
import ctypes, os, sys
libc = ctypes.CDLL(None, use_errno=True)
ex = libc.renameat2
ex.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
a, b = os.fsencode(sys.argv[1]), os.fsencode(sys.argv[2])
sys.stdout.write("go\n"); sys.stdout.flush()
while True:
    ex(-100, a, -100, b, 2)
"""


def exchange(a, b):
    import ctypes
    libc = ctypes.CDLL(None, use_errno=True)
    return libc.renameat2(-100, os.fsencode(a), -100, os.fsencode(b), 2) == 0


def still(scene, at, out, *more):
    r = run("still", os.path.join(scenes, scene), "--at", at, "--size", "160x90", "-o", out,
            "-q", *more)
    assert r.returncode == 0, err(r)


def rgba_sha256(png):
    """compare's pixel hash computed here: the SHA-256 of the RGBA rows
    (8-bit RGB or RGBA, not interlaced, filters undone), then b"WxH"."""
    data = open(png, "rb").read()
    w, h = struct.unpack(">II", data[16:24])
    ctype, idat, i = data[25], b"", 8
    while i < len(data):
        n, kind = struct.unpack(">I4s", data[i:i + 8])
        idat += data[i + 8:i + 8 + n] if kind == b"IDAT" else b""
        i += 12 + n
    bpp = {2: 3, 6: 4}[ctype]
    raw, stride, prev, out = zlib.decompress(idat), w * bpp, bytearray(w * bpp), bytearray()
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b, c = prev[x], prev[x - bpp] if x >= bpp else 0
            p = a + b - c
            pred = (0, a, b, (a + b) // 2, a if abs(p - a) <= abs(p - b) and abs(p - a) <= abs(p - c)
                    else b if abs(p - b) <= abs(p - c) else c)[f]
            line[x] = (line[x] + pred) & 255
        for x in range(0, stride, bpp):
            out += line[x:x + 3] + (line[x + 3:x + 4] if bpp == 4 else b"\xff")
        prev = line
    return hashlib.sha256(bytes(out) + f"{w}x{h}".encode()).hexdigest()


def folders(e, a, with_x_baseline=True):
    """e and a with 30 equal images each (so that the runs take a while),
    a/x.png (stiff) and, with_x_baseline, e/x.png (default)."""
    for d in (e, a):
        os.makedirs(d)
    if with_x_baseline:
        still("default.ini", "0", os.path.join(e, "x.png"))
    still("stiff.ini", "0", os.path.join(a, "x.png"))
    still("default.ini", "1", path("z.png"))
    for k in range(30):
        shutil.copy(path("z.png"), os.path.join(e, f"z{k}.png"))
        shutil.copy(path("z.png"), os.path.join(a, f"z{k}.png"))


def raced(name, spare, args, check):
    """RUNS runs of compare ARGS while a flipper swaps name and spare (a
    link out of both folders); check(run, k) after each, with name a
    regular file again. The runs whose stderr said a file changed."""
    said = 0
    for k in range(RUNS):
        flip = subprocess.Popen([sys.executable, "-c", FLIPPER, name, spare],
                                stdout=subprocess.PIPE, text=True)
        flip.stdout.readline()                      # it is swapping
        r = run(*[a.replace("{k}", str(k)) for a in args])
        flip.kill()
        flip.wait()
        if os.path.islink(name):
            exchange(name, spare)
        said += b"changed after the folder was listed" in r.stderr
        check(r, k)
    return said


# ---- the outside PNG and a link to it -----------------------------------------------------
still("chaotic.ini", "5", path("private.png"), "--set", "view.title=PRIVATE")
private = open(path("private.png"), "rb").read()
private_hash = rgba_sha256(path("private.png"))
private_b64 = base64.b64encode(private).decode()[200:260]
os.symlink(path("private.png"), path("spare"))
os.symlink(path("private.png"), path("spare2"))

# ---- compare --json --report --candidates: judged, embedded, copied ------------------------
folders(path("e"), path("a"))
r = run("compare", path("private.png"), path("private.png"), "--json")
ok(r.returncode == 0 and json.loads(r.stdout)["results"][0]["measured"]["actual_pixels_sha256"]
   == private_hash, "the pixel hash computed here is compare's (private.png against itself)")
judged, embedded, copied = [], [], []


def judge(r, k):
    j = r.stdout.decode(errors="replace")
    if private_hash in j:
        judged.append(k)
    if private_b64 in open(path(f"q{k}.html"), errors="replace").read():
        embedded.append(k)
    cand = path(f"c{k}", "x.png")
    if os.path.exists(cand) and open(cand, "rb").read() == private:
        copied.append(k)


said = raced(path("a", "x.png"), path("spare"),
             ["compare", path("e"), path("a"), "--json", "--jobs", "2",
              "--report", path("q{k}.html"), "--candidates", path("c{k}")], judge)
ok(not judged, f"{RUNS} folder compares while a/x.png flips with a link to a PNG outside: none "
   f"judged that PNG (its pixel hash in --json): runs {judged}")
ok(not embedded, f"... none embedded it in the HTML report (its base64): runs {embedded}")
ok(not copied, f"... none copied it as the candidate c/x.png: runs {copied}")
print(f"# {said} of {RUNS} runs refused a/x.png as changed after the folder was listed")

# ---- compare --update=missing: never installs the outside file -----------------------------
folders(path("e2"), path("a2"), with_x_baseline=False)
installed, added = [], []


real_a2 = open(path("a2", "x.png"), "rb").read()


def installs(r, k):
    x = path("e2", "x.png")
    if os.path.lexists(x):
        if os.path.islink(x) or open(x, "rb").read() != real_a2:
            installed.append(k)
        else:
            added.append(k)
        os.unlink(x)


said2 = raced(path("a2", "x.png"), path("spare2"),
              ["compare", path("e2"), path("a2"), "--update=missing", "--jobs", "2", "-q"],
              installs)
ok(not installed, f"{RUNS} runs of --update=missing while a2/x.png flips: none installed "
   f"anything but a2/x.png's bytes as the baseline e2/x.png (the outside PNG, a link): runs "
   f"{installed}")
print(f"# {said2} of {RUNS} runs refused a2/x.png; {len(added)} added the real one")
ok(said + said2 > 0, f"the race was run: {said + said2} runs of {2 * RUNS} met the image as a "
   f"link out after the walk and said so")
r = run("compare", path("e2"), path("a2"), "--update=missing", "-q")
ok(r.returncode == 0 and open(path("e2", "x.png"), "rb").read() == real_a2,
   f"unraced, --update=missing adds a2/x.png's bytes (exit {r.returncode}: {err(r)[-200:]!r})")

# ---- links within a folder are still followed -----------------------------------------------
for d in ("le", "la"):
    os.makedirs(path(d, "sub"))
    still("default.ini", "0", path(d, "sub", "real.png"))
    for n in ("x", "rel", "up", "abs"):
        if d == "le" or n == "x":
            shutil.copy(path(d, "sub", "real.png"), path(d, f"{n}.png"))
os.symlink("sub/real.png", path("la", "rel.png"))
os.symlink("../la/sub/real.png", path("la", "up.png"))
os.symlink(path("la", "sub", "real.png"), path("la", "abs.png"))
r = run("compare", path("le"), path("la"), "--json", "--report", path("l.html"))
res = {x["name"]: x for x in json.loads(r.stdout)["results"]} if r.stdout else {}
want = rgba_sha256(path("le", "x.png"))
ok(r.returncode == 0 and all(res.get(f"{n}.png", {}).get("verdict") == "pass" and
                             res[f"{n}.png"]["measured"]["actual_pixels_sha256"] == want
                             for n in ("rel", "up", "abs")),
   f"links within the actual folder (sub/real.png, ../la/sub/real.png, an absolute one) are "
   f"compared (exit {r.returncode}: {[(k, v.get('verdict')) for k, v in res.items()]}; "
   f"{err(r)[-300:]!r})")
done()
