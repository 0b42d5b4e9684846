#!/usr/bin/env python3
"""springpend tests (issue 28): the fifteenth attacker's pass
(doc/notes/2026-11-27/attack15.md), compare's readers:
- #11: the PNG colour rule took an ICC profile (iCCP) whose A2B0 table
  (a CLUT) is sRGB's on every point compare sampled and inverts every
  colour between them; Chromium converts by that table. A profile is now
  taken only when it is a matrix/TRC profile with no table (A2B*, B2A*,
  D2B*, B2D*) or cicp tag a colour manager would use instead, whose curves
  are sRGB's at every 16-bit value: the table profile (made here with
  lcms2, as the report's reproduction does), one with a cicp tag, and one
  whose curve is sRGB's at every 8-bit level and inverted between them (on
  a 16-bit PNG) are refused, exit 2, naming what;
- #12: a PNG's eXIf chunk with an EXIF Orientation other than 1 (browsers
  turn or mirror the image by it) was not looked at: refused, exit 2,
  naming the turn, big- and little-endian, after the pixels too; an eXIf
  libpng drops (a second one, one that is not TIFF data) and one whose
  directory lies outside the chunk (hostile offsets) are refused; one
  without Orientation or with 1 is taken;
- #16: under ulimit -v or -d (16 GB, far above what compare uses), a video
  whose H.264 payload is damaged, its container whole, was "cannot decode
  ... under this memory limit", exit 1: it is "cannot decode", exit 2, as
  without a limit (the process held far less than the limit: memory was
  not short).
The expectations come from the bytes written here (the orientation, the
profile's curve) and from lcms2 run on the profile by the helper, never
from springpend's output.
usage: test_attack15_readers.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import resource
import shutil
import struct
import subprocess
import zlib

import sptest
from spicc import HELPER
from sptest import done, err, ok, skip

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack15-readers")
default = os.path.join(scenes, "default.ini")


def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


def with_chunks(src_png, out, before=(), after=()):
    """src_png with the chunks (kind, body) before its first IDAT and before its IEND."""
    d = open(src_png, "rb").read()
    at, end = d.index(b"IDAT") - 4, d.rindex(b"IEND") - 4
    open(out, "wb").write(d[:at] + b"".join(chunk(k, b) for k, b in before) + d[at:end]
                          + b"".join(chunk(k, b) for k, b in after) + d[end:])


def iccp(profile):
    return (b"iCCP", b"a profile\0\0" + zlib.compress(profile))


def refused(r, name, *said):
    e = err(r)
    return r.returncode == 2 and f"{name} " in e and all(s in e for s in said)


def taken(r):
    return r.returncode == 0 and "identical pixels" in r.stdout.decode()


r = run("still", default, "--at", "1", "--size", "320x180", "-o", "s.png", "-q")
assert r.returncode == 0, err(r)
s = path("s.png")

# ---- #11: ICC profiles a colour manager converts by other than sRGB's matrix and curves -----
cc = shutil.which("cc") or shutil.which("gcc")
helper, why_not = path("mkicc"), None
if not cc:
    why_not = "no C compiler (cc)"
else:
    open(path("mkicc.c"), "w").write(HELPER)
    c = subprocess.run([cc, "-O1", "-o", helper, path("mkicc.c"), "-llcms2"], capture_output=True)
    if c.returncode != 0:
        why_not = f"the lcms2 helper does not build (lcms2's headers?): {c.stderr.decode()[-160:]}"
if why_not:
    for what in ("an A2B0 table profile", "a cicp tag"):
        skip(f"#11: compare s.png with {what}: refused", why_not)
else:
    h = subprocess.run([helper, path("evil.icc"), path("cicp.icc")], capture_output=True)
    assert h.returncode == 0, h.stderr
    # the oracle: lcms2 itself, through the table, moves an in-between colour far (inverted)
    moved = [int(v) for v in h.stdout.split()]
    assert max(abs(a - b) for a, b in zip(moved, (200, 100, 50))) > 100, moved
    with_chunks(s, path("evil.png"), [iccp(open(path("evil.icc"), "rb").read())])
    r = run("compare", "s.png", "evil.png")
    ok(refused(r, "evil.png", "A2B0", "without the iCCP chunk"),
       f"#11: compare s.png evil.png (an iCCP by whose A2B0 table lcms2 converts 200,100,50 "
       f"to {moved}): refused, exit 2, naming the A2B0 table (exit {r.returncode}: "
       f"{err(r)[-240:]!r})")
    with_chunks(s, path("cicp.png"), [iccp(open(path("cicp.icc"), "rb").read())])
    r = run("compare", "s.png", "cicp.png")
    ok(refused(r, "cicp.png", "cicp"),
       f"#11: compare s.png cicp.png (lcms2's sRGB profile with a cicp tag: BT.2020, PQ): "
       f"refused, exit 2, naming the cicp tag (exit {r.returncode}: {err(r)[-240:]!r})")


# a matrix/TRC profile built by hand (ICC.1:2001-04, as attack12-readers builds them)
def s15(v):
    return struct.pack(">i", int(round(v * 65536)))


def xyz(x, y, z):
    return b"XYZ \0\0\0\0" + s15(x) + s15(y) + s15(z)


def srgb_linear(v):
    return v / 12.92 if v <= 0.04045 else ((v + 0.055) / 1.055) ** 2.4


def srgb_encode(lin):
    return 12.92 * lin if lin <= 0.0031308 else 1.055 * lin ** (1 / 2.4) - 0.055


def matrix_profile(table):
    """sRGB's colorants (D50) and the tone curve `table` (curv) on each channel."""
    curv = b"curv\0\0\0\0" + struct.pack(">I", len(table)) + b"".join(struct.pack(">H", v)
                                                                     for v in table)
    desc = b"test\0"
    colorants = ((0.4361, 0.2225, 0.0139), (0.3851, 0.7169, 0.0971), (0.1431, 0.0606, 0.7141))
    tags = [(b"desc", b"desc\0\0\0\0" + struct.pack(">I", len(desc)) + desc + b"\0" * 79),
            (b"wtpt", xyz(0.9642, 1.0, 0.8249)), (b"cprt", b"text\0\0\0\0none\0")]
    tags += [(n, xyz(*c)) for n, c in zip((b"rXYZ", b"gXYZ", b"bXYZ"), colorants)]
    tags += [(n, curv) for n in (b"rTRC", b"gTRC", b"bTRC")]
    off, table_, data = 128 + 4 + 12 * len(tags), b"", b""
    for name, body in tags:
        data += b"\0" * (-(off + len(data)) % 4)
        table_ += name + struct.pack(">II", off + len(data), len(body))
        data += body
    body = struct.pack(">I", len(tags)) + table_ + data
    hdr = (struct.pack(">I", 128 + len(body)) + b"none" + bytes([2, 0x10, 0, 0]) + b"mntr"
           + b"RGB XYZ " + b"\0" * 12 + b"acsp" + b"\0" * 28 + s15(0.9642) + s15(1.0)
           + s15(0.8249) + b"\0" * 48)
    return hdr + body


# 4096 entries: the two around each 8-bit level's place (k * 4095 / 255) are sRGB's, every
# other one inverted; a 16-bit sample between the levels is converted by inverted entries
N = 4096
near = {p for k in range(256) for p in (k * (N - 1) // 255, -(-k * (N - 1) // 255))}
table = [int(round(srgb_linear(i / (N - 1)) * 65535)) for i in range(N)]
table = [v if i in near else 65535 - v for i, v in enumerate(table)]
# the 16-bit samples: halfway between 8-bit levels (never a multiple of 257)
samples = [257 * k + 128 for k in range(0, 255, 3)]


def curve_at(v):
    """The profile's curve at 16-bit value v (linear between entries, as ICC says)."""
    p = v / 65535 * (N - 1)
    i = min(int(p), N - 2)
    return (table[i] + (table[i + 1] - table[i]) * (p - i)) / 65535


off = max(abs(srgb_encode(curve_at(v)) - v / 65535) * 255 for v in samples)
eight = max(abs(srgb_encode(curve_at(k * 257)) - k / 255) * 255 for k in range(256))
assert off > 50 and eight < 1, (off, eight)
rows = b"".join(b"\0" + b"".join(struct.pack(">HHH", samples[(x + y) % len(samples)],
                                             samples[(2 * x + y) % len(samples)],
                                             samples[(x + 3 * y) % len(samples)])
                                 for x in range(32)) for y in range(16))
open(path("deep.png"), "wb").write(b"\x89PNG\r\n\x1a\n"
                                   + chunk(b"IHDR", struct.pack(">IIBBBBB", 32, 16, 16, 2, 0, 0, 0))
                                   + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))
with_chunks(path("deep.png"), path("deepicc.png"), [iccp(matrix_profile(table))])
r = run("compare", "deep.png", "deepicc.png")
ok(refused(r, "deepicc.png", "tone curve", "16-bit"),
   f"#11: compare deep.png deepicc.png (16-bit; a curve sRGB's at every 8-bit level, {off:.0f} "
   f"levels off between them): refused, exit 2, naming the curve (exit {r.returncode}: "
   f"{err(r)[-240:]!r})")

# ---- #12: eXIf ----------------------------------------------------------------------------
def tiff(orientation, order=">", kind=3, count=1, ifd=8, entries=1):
    head = (b"MM" if order == ">" else b"II") + struct.pack(order + "HI", 42, ifd)
    if orientation is None:
        return head + struct.pack(order + "HI", 0, 0)
    return head + struct.pack(order + "H", entries) + struct.pack(
        order + "HHIHH", 0x0112, kind, count, orientation, 0) + struct.pack(order + "I", 0)


with_chunks(s, path("o1.png"), [(b"eXIf", tiff(1))])
with_chunks(s, path("none.png"), [(b"eXIf", tiff(None, "<"))])
ones = [run("compare", "s.png", n) for n in ("o1.png", "none.png")]
kept = all(taken(x) for x in ones)
for name, before, after, said in (
        ("o3.png", [(b"eXIf", tiff(3))], [], "turned by 180 degrees"),
        ("o6le.png", [(b"eXIf", tiff(6, "<"))], [], "turned by 90 degrees clockwise"),
        ("o2.png", [(b"eXIf", tiff(2))], [], "mirrored left to right"),
        ("o8after.png", [], [(b"eXIf", tiff(8))], "turned by 90 degrees counterclockwise"),
        ("twice.png", [(b"eXIf", tiff(1))], [(b"eXIf", tiff(3))], "eXIf"),
        ("exifhead.png", [(b"eXIf", b"Exif\0\0" + tiff(3))], [], "eXIf"),
        ("farifd.png", [(b"eXIf", tiff(3, ifd=0xfffffff0))], [], "eXIf"),
        ("manyentries.png", [(b"eXIf", tiff(3, entries=0xffff))], [], "eXIf")):
    with_chunks(s, path(name), before, after)
    r = run("compare", "s.png", name)
    ok(refused(r, name, said) and kept,
       f"#12: compare s.png {name}: refused, exit 2, naming '{said}' (exit {r.returncode}: "
       f"{err(r)[-200:]!r}); an eXIf with Orientation 1 or none taken "
       f"({[x.returncode for x in ones]})")

# ---- #16: a damaged payload under a memory limit far above what compare uses ---------------
def limited(which, kb):
    return lambda: resource.setrlimit(which, (kb << 10, kb << 10))


if sanitized:
    skip("#16: a damaged payload under ulimit -v and -d", "ulimit -v and a sanitizer's shadow memory")
else:
    r = run("render", default, "--set", "video.duration=1", "--size", "320x180", "-o", "v.mp4",
            "-q", timeout=120)
    assert r.returncode == 0, err(r)
    d = bytearray(open(path("v.mp4"), "rb").read())
    at = d.index(b"mdat")
    for k in range(at + 3000, len(d) - 2000, 7):
        d[k] ^= 0xFF
    open(path("bad.mp4"), "wb").write(d)
    free = run("compare", "v.mp4", "bad.mp4")
    assert free.returncode == 2, err(free)    # without a limit: the file's
    for flag, which in (("-v", resource.RLIMIT_AS), ("-d", resource.RLIMIT_DATA)):
        r = run("compare", "v.mp4", "bad.mp4", preexec_fn=limited(which, 16000000), timeout=120)
        out = r.stdout.decode() + err(r)
        ok(r.returncode == 2 and "cannot decode bad.mp4" in out and "allow more memory" not in out
           and "out of memory" not in out,
           f"#16: compare v.mp4 bad.mp4 (its H.264 payload damaged) under ulimit {flag} "
           f"16000000 kB: 'cannot decode', exit 2, as without a limit, not memory's (exit "
           f"{r.returncode}: {out[-240:]!r})")

done()
