#!/usr/bin/env python3
"""springpend tests: compare as CI uses it, and against hostile inputs.
PNGs of every colour type, bit depth and interlacing (written here by hand,
independently of libpng), oversized headers and a decompression bomb, a
missing IEND, a FIFO among the PNGs, retimed video, signals, stdout
failures, exact-then-fuzzy matching, compare.ini, --update, JSON, JUnit.
usage: test_compare_ci.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR (TAP)"""
import json
import os
import resource
import shutil
import signal
import struct
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
import zlib

from sptest import manual, wait_caught

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "compare_ci"))
scenes = os.path.join(src, "..", "scenes")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
count = failed = 0


def ok(cond, what):
    global count, failed
    count += 1
    failed += not cond
    print(f"{'' if cond else 'not '}ok {count} - {what}".replace("\n", " | "), flush=True)
    return cond


def run(*args, **kw):
    return subprocess.run([exe, *args], capture_output=True, text=True, cwd=work,
                          timeout=kw.pop("timeout", 60), **kw)


def W(*parts):
    return os.path.join(work, *parts)


def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png(path, w, h, ctype, depth, rows, plte=b"", trns=b"", interlace=False, iend=True):
    """A PNG from rows of samples (lists of ints, one per channel value)."""
    chans = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}[ctype]

    def pack(row):
        if depth == 16:
            return b"".join(struct.pack(">H", v) for v in row)
        if depth == 8:
            return bytes(row)
        bits = "".join(format(v, f"0{depth}b") for v in row)
        bits += "0" * (-len(bits) % 8)
        return bytes(int(bits[i:i + 8], 2) for i in range(0, len(bits), 8))

    raw = b""
    if interlace:  # Adam7: seven passes, each a small image of its own
        for x0, y0, dx, dy in ((0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4),
                               (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)):
            xs = range(x0, w, dx)
            for y in range(y0, h, dy):
                if xs:
                    raw += b"\0" + pack([v for x in xs for v in rows[y][x * chans:(x + 1) * chans]])
    else:
        raw = b"".join(b"\0" + pack(r) for r in rows)
    data = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, depth, ctype, 0, 0,
                                                            1 if interlace else 0))
    if plte:
        data += chunk(b"PLTE", plte)
    if trns:
        data += chunk(b"tRNS", trns)
    data += chunk(b"IDAT", zlib.compress(raw)) + (chunk(b"IEND", b"") if iend else b"")
    with open(path, "wb") as f:
        f.write(data)
    return path


# A 13x11 picture (odd sizes exercise the interlace passes' edges).
w, h = 13, 11
rgb = [[((x * 19 + y * 7) % 256, (x * 5 + y * 31) % 256, (x * y * 3) % 256) for x in range(w)]
       for y in range(h)]
alpha = [[(x * 17 + y * 11) % 256 for x in range(w)] for y in range(h)]
grey = [[(x * 13 + y * 23) % 256 for x in range(w)] for y in range(h)]
flat = lambda px: [[v for p in row for v in p] for row in px]
rgba8 = png(W("rgba8.png"), w, h, 6, 8, flat([[(*rgb[y][x], alpha[y][x]) for x in range(w)]
                                              for y in range(h)]))
rgb8 = png(W("rgb8.png"), w, h, 2, 8, flat(rgb))
grey8 = png(W("grey8.png"), w, h, 0, 8, grey)
cases = {
    "16-bit RGB holding v*257": (rgb8, png(W("rgb16.png"), w, h, 2, 16,
                                           [[v * 257 for v in r] for r in flat(rgb)])),
    "16-bit grey holding v*257": (grey8, png(W("grey16.png"), w, h, 0, 16,
                                             [[v * 257 for v in r] for r in grey])),
    "16-bit RGBA holding v*257": (rgba8, png(W("rgba16.png"), w, h, 6, 16,
                                             [[v * 257 for v in r] for r in flat(
                                                 [[(*rgb[y][x], alpha[y][x]) for x in range(w)]
                                                  for y in range(h)])])),
    "interlaced RGBA": (rgba8, png(W("rgba8i.png"), w, h, 6, 8, flat(
        [[(*rgb[y][x], alpha[y][x]) for x in range(w)] for y in range(h)]), interlace=True)),
    "interlaced 16-bit grey": (grey8, png(W("grey16i.png"), w, h, 0, 16,
                                          [[v * 257 for v in r] for r in grey], interlace=True)),
    "grey+alpha": (png(W("ga_as_rgba.png"), w, h, 6, 8, flat(
        [[(grey[y][x],) * 3 + (alpha[y][x],) for x in range(w)] for y in range(h)])),
        png(W("ga8.png"), w, h, 4, 8, [[v for x in range(w) for v in (grey[y][x], alpha[y][x])]
                                       for y in range(h)])),
}
# A palette image of 4 colours, 2 bits per index, one colour half transparent.
pal = [(255, 0, 0), (0, 128, 255), (20, 20, 20), (250, 250, 0)]
idx = [[(x + y) % 4 for x in range(w)] for y in range(h)]
cases["palette, 2-bit, tRNS"] = (
    png(W("pal_as_rgba.png"), w, h, 6, 8, flat([[(*pal[idx[y][x]], 128 if idx[y][x] == 1 else 255)
                                                  for x in range(w)] for y in range(h)])),
    png(W("pal2.png"), w, h, 3, 2, idx, plte=bytes(v for p in pal for v in p), trns=b"\xff\x80"))
for what, (a, b) in cases.items():
    r = run("compare", a, b, "--max-diff", "0", "--max-pixels", "0")
    ok(r.returncode == 0 and "identical pixels" in r.stdout,
       f"{what} equals its 8-bit RGBA twin, exactly ({r.stdout.strip()}{r.stderr.strip()})")
r = run("compare", rgb8, png(W("rgb16off.png"), w, h, 2, 16,
                             [[v * 257 + (300 if i == 0 else 0) for i, v in enumerate(r)]
                              for r in flat(rgb)]), "--max-diff", "0", "--max-pixels", "0")
ok(r.returncode == 1 and "largest difference 1" in r.stdout,
   f"a 16-bit sample 300/65535 off is one level off, not lost ({r.stdout.strip()})")

# Headers that ask for too much: refused before decoding, exit 2.
rgb_small = png(W("small.png"), 4, 4, 2, 8, [[0] * 12] * 4)
huge = W("huge.png")
with open(huge, "wb") as f:
    f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 100000, 100000, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(b"\0" * 10)) + chunk(b"IEND", b""))


def zeros_png(path, w, h):
    """A real w x h RGB PNG of zeros, a decompression bomb when large: one
    deflate piece of 100 rows, full-flushed and repeated, so it is quick to make."""
    row = b"\0" * (w * 3 + 1)
    c = zlib.compressobj(9, zlib.DEFLATED, -15)
    piece = c.compress(row * 100) + c.flush(zlib.Z_FULL_FLUSH)
    body = b"\x78\xda" + piece * (h // 100) + zlib.compressobj(9, zlib.DEFLATED, -15).flush()
    body += struct.pack(">I", ((len(row) * h) % 65521) << 16 | 1)  # adler32 of zeros
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", body) + chunk(b"IEND", b""))
    return path


bomb = zeros_png(W("bomb.png"), 20000, 20000)
for what, path, size in (("a tiny PNG declaring 100000x100000", huge, os.path.getsize(huge)),
                         ("a 20000x20000 decompression bomb", bomb, os.path.getsize(bomb))):
    # The peak memory of the child alone: measured in a fresh process.
    probe = subprocess.run([sys.executable, "-c",
                            "import resource, subprocess, sys; "
                            "r = subprocess.run(sys.argv[1:], capture_output=True, text=True); "
                            "print(r.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss); "
                            "print(r.stderr)", exe, "compare", rgb_small, path],
                           capture_output=True, text=True, timeout=60)
    rc, rss = (int(v) for v in probe.stdout.split("\n")[0].split())
    ok(rc == 2 and "100000000" in probe.stdout and rss < 300 * 1024,
       f"{what} ({size} bytes): exit 2, limit named, peak RSS {rss // 1024} MiB "
       f"({probe.stdout.strip()[:200]})")

# Truncations: a PNG missing IEND is refused like any other.
noend = png(W("noend.png"), w, h, 2, 8, flat(rgb), iend=False)
r = run("compare", rgb8, noend)
ok(r.returncode == 2 and "noend.png" in r.stderr, f"a PNG without IEND: exit 2 ({r.stderr.strip()})")

# A FIFO named *.png, alone or in a folder: refused, never waited on.
fe, fa = W("fifo_e"), W("fifo_a")
os.makedirs(fe), os.makedirs(fa)
for d in (fe, fa):
    shutil.copy(rgb8, os.path.join(d, "a.png"))
os.mkfifo(os.path.join(fa, "pipe.png"))
os.mkfifo(os.path.join(fe, "pipe.png"))
try:
    r = run("compare", fe, fa, timeout=20)
    ok(r.returncode == 2 and "ERROR pipe.png" in r.stdout and "not a regular file" in r.stderr,
       f"a FIFO named *.png in a folder: an error, no hang ({r.stdout.strip()})")
    r = run("compare", os.path.join(fe, "pipe.png"), rgb8, timeout=20)
    ok(r.returncode == 2, f"a FIFO as EXPECTED: exit 2 ({r.stderr.strip()})")
except subprocess.TimeoutExpired:
    ok(False, "a FIFO named *.png hangs compare")
    ok(False, "a FIFO as EXPECTED hangs compare")

# --diff never removes what it did not make.
empty = W("emptydir")
os.makedirs(empty)
moved = W("rgb8b.png")
png(moved, w, h, 2, 8, [[255 - v for v in r] for r in flat(rgb)])
r = run("compare", rgb8, moved, "--diff", empty)
ok(r.returncode == 2 and os.path.isdir(empty) and "folder" in r.stderr,
   f"compare a b --diff EMPTYDIR: refused, the folder stays ({r.stderr.strip()})")

# stdout that cannot be written: a message and exit 1, not 0.
with open("/dev/full", "w") as full:
    r = subprocess.run([exe, "compare", rgb8, rgb8], stdout=full, stderr=subprocess.PIPE,
                       text=True, cwd=work)
ok(r.returncode == 1 and "stdout" in r.stderr, f"compare > /dev/full: exit 1 ({r.stderr.strip()})")

# Renders for the rest.
default = os.path.join(scenes, "default.ini")
for name, extra in (("a", []), ("b", []), ("moved", ["--at", "3.05"]),
                    ("small", ["--size", "160x120"]), ("damped", ["--set", "pendulum.damping=0.1"])):
    args = (["--at", "3"] if "--at" not in extra else []) + \
        (["--size", "320x240"] if "--size" not in extra else [])  # each option once
    run("still", default, *args, *extra, "-o", f"{name}.png", "-q")

# Exact first: the same pixels in other bytes (16-bit, another zlib level).
r = run("compare", W("a.png"), W("b.png"))
ok(r.returncode == 0 and "identical pixels" in r.stdout, f"two renders: identical pixels ({r.stdout.strip()})")
r = run("compare", W("a.png"), W("moved.png"))
ok(r.returncode == 1 and "ssim 0." in r.stdout, f"a moved bob: fuzzy rule, SSIM beside the counts ({r.stdout.strip()})")



def read_png(path):
    """8-bit RGB or RGBA, not interlaced (what springpend writes), to rows of RGB."""
    d = open(path, "rb").read()
    i, idat, hdr = 8, b"", None
    while i < len(d):
        n, kind = struct.unpack(">I4s", d[i:i + 8])
        if kind == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", d[i + 8:i + 21])
        elif kind == b"IDAT":
            idat += d[i + 8:i + 8 + n]
        i += 12 + n
    width, height, bpc = hdr[0], hdr[1], {2: 3, 6: 4}[hdr[3]]
    raw, stride, prev, rows = zlib.decompress(idat), hdr[0] * bpc, [0] * hdr[0] * bpc, []
    for y in range(height):
        f, line = raw[y * (stride + 1)], list(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - bpc] if x >= bpc else 0
            b, c = prev[x], prev[x - bpc] if x >= bpc else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append([line[x * bpc:x * bpc + 3] for x in range(width)])
        prev = line
    return rows


def ssim(e, a):
    """Wang et al.'s SSIM on BT.601 luma, 8x8 windows every 4 px, population variances."""
    L = lambda img: [[0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2] for p in row] for row in img]
    le, la, c1, c2, vals = L(e), L(a), (0.01 * 255) ** 2, (0.03 * 255) ** 2, []
    for y0 in range(0, len(le) - 7, 4):
        for x0 in range(0, len(le[0]) - 7, 4):
            u = [le[y][x] for y in range(y0, y0 + 8) for x in range(x0, x0 + 8)]
            v = [la[y][x] for y in range(y0, y0 + 8) for x in range(x0, x0 + 8)]
            mu, mv = sum(u) / 64, sum(v) / 64
            vu = sum((p - mu) ** 2 for p in u) / 64
            vv = sum((q - mv) ** 2 for q in v) / 64
            cov = sum((p - mu) * (q - mv) for p, q in zip(u, v)) / 64
            vals.append((2 * mu * mv + c1) * (2 * cov + c2) / ((mu * mu + mv * mv + c1) * (vu + vv + c2)))
    return sum(vals) / len(vals)


run("still", default, "--size", "96x64", "--at", "3", "-o", "s1.png", "-q")
run("still", default, "--size", "96x64", "--at", "3.2", "-o", "s2.png", "-q")
r = run("compare", W("s1.png"), W("s2.png"), "--json")
got = json.loads(r.stdout)["results"][0]["measured"]["ssim"]
want = ssim(read_png(W("s1.png")), read_png(W("s2.png")))
ok(abs(got - want) < 1e-6 and want < 0.999, f"SSIM {got:.6f} agrees with an independent computation {want:.6f}")

# Size mismatch: a failure (exit 1) with both images side by side.
r = run("compare", W("a.png"), W("small.png"), "--diff", W("size-diff.png"), "--json")
j = json.loads(r.stdout)
rec = j["results"][0]
ident = run("compare", W("size-diff.png"), W("size-diff.png"), "--json")
dims = json.loads(ident.stdout)["results"][0]["measured"]["actual_size"]
ok(r.returncode == 1 and rec["size_mismatch"] and rec["verdict"] == "fail"
   and dims == [320 + 8 + 160, 240],
   f"sizes differ: exit 1, side-by-side diff {dims} ({rec.get('error')})")
d, ea, sm = read_png(W("size-diff.png")), read_png(W("a.png")), read_png(W("small.png"))
tint = lambda p: [(p[0] + 255) // 2, p[1] // 2, (p[2] + 255) // 2]
ok(d[10][10] == ea[10][10] and d[200][300] == tint(ea[200][300])
   and d[100][328 + 50] == sm[100][50] and d[200][328 + 50] == [48, 48, 48],
   "the side-by-side diff: the shared area as it is, the expected image's extra area tinted "
   "magenta, the actual image beside it")

# Without --diff a size mismatch is decided from the headers: an actual
# image of 9000x9000 (81 Mpx, under the limit) is not decoded.
big = zeros_png(W("big9000.png"), 9000, 9000)
probe = subprocess.run([sys.executable, "-c",
                        "import resource, subprocess, sys; "
                        "r = subprocess.run(sys.argv[1:], capture_output=True, text=True); "
                        "print(r.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss); "
                        "print(r.stdout)", exe, "compare", W("a.png"), big],
                       capture_output=True, text=True, timeout=60)
rc, rss = (int(v) for v in probe.stdout.split("\n")[0].split())
ok(rc == 1 and "actual 9000x9000" in probe.stdout and rss < 100 * 1024,
   f"a size mismatch without --diff is decided from the headers: exit 1, peak RSS {rss // 1024} MiB")

# Provenance: the scene keys that changed, with both values.
r = run("compare", W("a.png"), W("damped.png"))
ok(r.returncode == 1 and "scene: pendulum.damping = 0 (expected) vs 0.1 (actual)"
   in r.stdout, f"a changed scene names the key and both values ({r.stdout.strip()[-300:]})")

run("still", default, "--size", "320x240", "--at", "3", "--set", "view.theme=light", "--set",
    "initial.angle=12", "--set", "view.panels=r,energy", "-o", "looks.png", "-q")
r = run("compare", W("a.png"), W("looks.png"), "--json")
ch = {c["key"]: (c["expected"], c["actual"]) for c in json.loads(r.stdout)["results"][0]["scene_changes"]}
ok(ch == {"initial.angle": ("10", "12"), "view.theme": ("dark", "light"),
          "view.panels": ("r, theta, energy, extension", "r, energy")},
   f"scene changes as a scene file spells them (degrees, names, panel lists): {ch}")

# JSON: one schema for a pair and for folders; a list of results always.
r1 = json.loads(run("compare", W("a.png"), W("moved.png"), "--json").stdout)
base, act = W("base"), W("act")
os.makedirs(base), os.makedirs(act)
for n in ("one", "two", "three"):
    shutil.copy(W("a.png"), os.path.join(base, n + ".png"))
    shutil.copy(W("a.png" if n != "two" else "moved.png"), os.path.join(act, n + ".png"))
r2 = json.loads(run("compare", base, act, "--json").stdout)
keys = lambda d: sorted(d)
ok(keys(r1) == keys(r2) and isinstance(r1["results"], list) and len(r1["results"]) == 1
   and len(r2["results"]) == 3 and keys(r1["results"][0]) == keys(r2["results"][0])
   and {"max_channel_diff", "rms"} <= set(r1["results"][0]["measured"])
   and {"max_channel_diff", "max_rms"} <= set(r1["results"][0]["tolerance"]),
   f"--json: one schema for a pair and a folder ({keys(r1)}, {keys(r1['results'][0])})")

# JUnit: a test case per image, the failure named.
r = run("compare", base, act, "--junit", W("junit.xml"))
cases_x = ET.parse(W("junit.xml")).getroot().findall("./testsuite/testcase")
fails = [c.get("name") for c in cases_x if c.find("failure") is not None]
ok(r.returncode == 1 and len(cases_x) == 3 and fails == ["two.png"],
   f"--junit: 3 test cases, two.png fails ({fails})")

# compare.ini beside the baselines: per-file tolerance and masks.
with open(os.path.join(base, "compare.ini"), "w") as f:
    f.write("# tolerances\n[*]\nmax_diff = 3\n\n[two.png]\nmask = 0, 0, 320, 240\n")
r = run("compare", base, act)
ok(r.returncode == 0 and "76800 pixels masked" in r.stdout,
   f"compare.ini: a mask over the whole image lets two.png pass ({r.stdout.strip()})")
with open(os.path.join(base, "compare.ini"), "w") as f:
    f.write("[two.png]\nmax_pixels = 100%\n")
r = run("compare", base, act)
ok(r.returncode == 0, f"compare.ini: max_pixels = 100% for two.png ({r.stdout.strip()})")
with open(os.path.join(base, "compare.ini"), "w") as f:
    f.write("[*]\nmax_diff = 3\n[two.png]\nmask = 1, 2, -3, 4\nmax_dif = 3\n")
r = run("compare", base, act)
ok(r.returncode == 2 and "compare.ini:4: mask 1, 2, -3, 4" in r.stderr
   and "compare.ini:5: unknown key 'max_dif'" in r.stderr,
   f"compare.ini errors say FILE:LINE ({r.stderr.strip()})")
# doc/ci.md's compare.ini, as printed there, parses; [chart.png] names no
# image here and is warned about.
readme = manual(os.path.join(src, ".."))   # README.md and doc/*.md
example = next(b for b in readme.split("```ini\n")[1:] if "[hud.png]" in b).split("```")[0]
with open(os.path.join(base, "compare.ini"), "w") as f:
    f.write(example.replace("hud.png", "two.png"))
r = run("compare", base, act)
ok(r.returncode == 0 and "pixels masked" in r.stdout
   and "compare.ini:6: warning: [chart.png] matches no compared image" in r.stderr,
   f"doc/ci.md's compare.ini works as printed ({r.stderr.strip()})")
os.remove(os.path.join(base, "compare.ini"))

# --update: never without asking; missing, changed, all.
shutil.copy(W("a.png"), os.path.join(act, "four.png"))
r = run("compare", base, act)
ok(r.returncode == 2 and "ERROR four.png: no baseline" in r.stdout and "--update=missing" in r.stdout
   and not os.path.exists(os.path.join(base, "four.png")),
   f"a missing baseline fails and says how to add it ({r.stdout.strip()[-200:]})")
r = run("compare", base, act, "--update=missing")
ok(r.returncode == 1 and os.path.exists(os.path.join(base, "four.png")) and "added" in r.stdout
   and "FAIL two.png" in r.stdout, f"--update=missing adds four.png, two.png still fails ({r.stdout.strip()[-200:]})")
r = run("compare", base, act, "--update=changed")
same = open(os.path.join(base, "two.png"), "rb").read() == open(os.path.join(act, "two.png"), "rb").read()
ok(r.returncode == 0 and same and "replaced" in r.stdout,
   f"--update=changed replaces two.png, exit 0 ({r.stdout.strip()[-200:]})")
os.remove(os.path.join(act, "three.png"))
r = run("compare", base, act, "--update=changed")
ok(r.returncode == 2 and os.path.exists(os.path.join(base, "three.png")),
   "--update=changed never deletes a baseline")
r = run("compare", base, act, "--update=all")
ok(r.returncode == 0 and not os.path.exists(os.path.join(base, "three.png"))
   and "removed" in r.stdout and "three.png" in r.stdout and not
   [n for n in os.listdir(base) if n.endswith((".tmp", ".part"))],
   f"--update=all removes three.png and lists it ({r.stdout.strip()[-200:]})")

# Videos: the same frames at another rate differ.
for name, extra in (("v30", ["--fps", "30"]), ("v15", ["--fps", "15", "--set", "video.speed=0.5"])):
    run("render", default, "--size", "96x64", "--set", "video.duration=0.4", "--set", "view.panels=none",
        *extra, "-o", f"{name}.mp4", "-q")
r = run("compare", W("v30.mp4"), W("v15.mp4"), "--json")
rec = json.loads(r.stdout)["results"][0] if r.stdout else {}
v = rec.get("video") or {}
# (frame 0 may differ too: speed 0.5 is marked "speed ×0.5" on every frame)
ok(r.returncode == 1 and v.get("failed_frames", 0) >= v.get("frames", 0) - 1
   and round(v.get("expected_fps", 0)) == 30 and round(v.get("actual_fps", 0)) == 15,
   f"the same frames retimed to 15 fps differ ({v}, {rec.get('notes')})")

# compare.ini also applies to a single pair and to videos, by the
# baseline's file name.
cfg_dir = W("cfg")
os.makedirs(cfg_dir)
for name, extra in (("v.mp4", []), ("v11.mp4", ["--set", "initial.angle=30"])):
    run("render", default, "--size", "160x120", "--set", "video.duration=0.4", "--fps", "30",
        *extra, "-o", os.path.join(cfg_dir, name), "-q")
shutil.copy(W("a.png"), os.path.join(cfg_dir, "a.png"))
r1 = run("compare", os.path.join(cfg_dir, "a.png"), W("moved.png"))
r2 = run("compare", os.path.join(cfg_dir, "v.mp4"), os.path.join(cfg_dir, "v11.mp4"))
with open(os.path.join(cfg_dir, "compare.ini"), "w") as f:
    f.write("[a.png]\nmax_pixels = 100%\n[v.mp4]\nmask = 0, 0, 160, 120\n")
r3 = run("compare", os.path.join(cfg_dir, "a.png"), W("moved.png"))
r4 = run("compare", os.path.join(cfg_dir, "v.mp4"), os.path.join(cfg_dir, "v11.mp4"))
ok((r1.returncode, r2.returncode, r3.returncode, r4.returncode) == (1, 1, 0, 0)
   and "19200 pixels masked" in r4.stdout,
   f"compare.ini beside a single pair and beside videos ({r3.stdout.strip()} | {r4.stdout.strip()})")


# Signals: a long folder compare stops at once with 128 + signal.
big_e, big_a = W("big_e"), W("big_a")
os.makedirs(big_e), os.makedirs(big_a)
run("still", default, "--size", "1280x720", "--at", "2", "-o", "big.png", "-q")
for i in range(300):
    os.link(W("big.png"), os.path.join(big_e, f"{i:03d}.png"))
    os.link(W("big.png"), os.path.join(big_a, f"{i:03d}.png"))
for sig in (signal.SIGINT, signal.SIGTERM):
    p = subprocess.Popen([exe, "compare", big_e, big_a], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, cwd=work)
    wait_caught(p, sig)
    time.sleep(0.5)
    p.send_signal(sig)
    out, err = p.communicate(timeout=30)
    ok(p.returncode == 128 + sig and "interrupted" in out,
       f"{signal.Signals(sig).name} stops a folder compare: exit {p.returncode} "
       f"({out.strip()[-80:]})")

# ... and a long video compare (180 frames of 720p, about 2 s here).
run("render", default, "--size", "1280x720", "--fps", "30", "--set", "video.duration=6",
    "--set", "view.panels=none", "-o", "long.mp4", "-q")
os.link(W("long.mp4"), W("long2.mp4"))
for sig in (signal.SIGINT, signal.SIGTERM):
    p = subprocess.Popen([exe, "compare", W("long.mp4"), W("long2.mp4")], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, cwd=work)
    wait_caught(p, sig)
    time.sleep(0.4)
    p.send_signal(sig)
    out, err = p.communicate(timeout=30)
    ok(p.returncode == 128 + sig and "interrupted at frame" in out,
       f"{signal.Signals(sig).name} stops a video compare: exit {p.returncode} ({out.strip()[-80:]})")

print(f"1..{count}")
sys.exit(1 if failed else 0)
