#!/usr/bin/env python3
"""springpend tests (issue 28): the sixteenth attacker's pass
(doc/notes/2026-11-27/attack16.md), compare's PNG reader:
- #2: an sRGB chunk after an iCCP switched the profile check off (libpng's
  png_get_sRGB says yes for the chunk as for a profile it recognised):
  attack15 #11's inverting A2B0 table (built with lcms2, tests/e2e/spicc.py)
  passed, and Chromium draws the image inverted. The profile is now judged
  wherever an iCCP stands, whatever sRGB chunk is before or after it, and
  whatever libpng's colour-space bookkeeping makes of its neighbours (a
  second sRGB, a gAMA out of range, a second cHRM make libpng forget the
  profile; viewers still convert by it): each is refused, exit 2, naming
  the A2B0 table; two iCCP chunks are refused; so is a PNG whose chunks
  of these kinds are past what libpng keeps. lcms2's sRGB profile beside an
  sRGB chunk, in either order, is taken;
- #3: an EXIF Orientation in the Exif directory (IFD0's pointer, tag
  0x8769) was not read, and Chromium turns the PNG by it: refused, exit 2,
  naming the turn, little- and big-endian, before or after the pixels,
  beside an Orientation 1 in IFD0; an Exif directory outside the chunk, or
  whose count runs past it, or two pointers, are refused; one with
  Orientation 1 or none, one pointing back at IFD0, and an Orientation in
  IFD1 (a thumbnail's, which Chromium ignores) are taken.
The expectations come from the bytes written here and from lcms2 run on
the profile by the helper, never from springpend's output.
usage: test_attack16_readers.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import shutil
import struct
import subprocess
import zlib

import sptest
from spicc import HELPER
from sptest import done, err, ok, skip

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack16-readers")


def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


def with_chunks(src_png, out, before=(), after=()):
    """src_png with the chunks (kind, body) right after its IHDR and before its IEND."""
    d = open(src_png, "rb").read()
    end = d.rindex(b"IEND") - 4
    open(out, "wb").write(d[:33] + b"".join(chunk(k, b) for k, b in before) + d[33:end]
                          + b"".join(chunk(k, b) for k, b in after) + d[end:])


def iccp(profile):
    return (b"iCCP", b"display\0\0" + zlib.compress(profile, 9))


SRGB = (b"sRGB", b"\0")


def refused(r, name, *said):
    e = err(r)
    return r.returncode == 2 and f"{name} " in e and all(s in e for s in said) \
        and not r.stdout.strip().startswith(b"ok")


def taken(r):
    return r.returncode == 0 and "identical pixels" in r.stdout.decode()


def said(r):
    return f"exit {r.returncode}: {(err(r) or r.stdout.decode())[-220:]!r}"


r = run("still", scenes + "/default.ini", "--at", "3", "--size", "320x180",
        "--set", "view.panels=r", "-o", "base.png", "-q")
assert r.returncode == 0, err(r)
base = path("base.png")
assert open(base, "rb").read()[12:16] == b"IHDR"

# ---- #2: an iCCP whatever stands beside it -------------------------------------------------
cc = shutil.which("cc") or shutil.which("gcc")
why_not = None if cc else "no C compiler (cc)"
if cc:
    open(path("mkicc.c"), "w").write(HELPER)
    open(path("mksrgb.c"), "w").write("#include <lcms2.h>\nint main(int c, char **v)\n"
                                      "{ return c != 2 || !cmsSaveProfileToFile("
                                      "cmsCreate_sRGBProfile(), v[1]); }\n")
    for name in ("mkicc", "mksrgb"):
        c = subprocess.run([cc, "-O1", "-o", path(name), path(name + ".c"), "-llcms2"],
                           capture_output=True)
        if c.returncode != 0:
            why_not = f"the lcms2 helper does not build (lcms2's headers?): {c.stderr.decode()[-160:]}"
if why_not:
    skip("#2: an inverting A2B0 profile beside sRGB, gAMA, cHRM chunks: refused", why_not)
else:
    h = subprocess.run([path("mkicc"), path("evil.icc"), path("cicp.icc")], capture_output=True)
    assert h.returncode == 0, h.stderr
    # the oracle: lcms2 itself, through the table, moves an in-between colour far (inverted)
    moved = [int(v) for v in h.stdout.split()]
    assert max(abs(a - b) for a, b in zip(moved, (200, 100, 50))) > 100, moved
    assert subprocess.run([path("mksrgb"), path("srgb.icc")]).returncode == 0
    evil, good = iccp(open(path("evil.icc"), "rb").read()), iccp(open(path("srgb.icc"), "rb").read())
    gama_bad = (b"gAMA", struct.pack(">I", 0))                      # out of range: libpng drops it
    chrm = (b"cHRM", struct.pack(">8I", 31270, 32900, 64000, 33000, 30000, 60000, 15000, 6000))
    for name, before, what in (
            ("icc_srgb.png", [evil, SRGB], "an sRGB chunk after it (attack16's reproduction)"),
            ("srgb_icc.png", [SRGB, evil], "an sRGB chunk before it"),
            ("icc_gama.png", [evil, gama_bad], "a gAMA of 0 after it"),
            ("icc_srgb2.png", [evil, SRGB, SRGB], "two sRGB chunks after it"),
            ("icc_chrm2.png", [evil, chrm, chrm], "two cHRM chunks after it"),
            ("good_evil.png", [good, evil], "lcms2's sRGB profile in an iCCP before it")):
        with_chunks(base, path(name), before)
        r = run("compare", "base.png", name)
        need = ("iCCP",) if name == "good_evil.png" else ("A2B0",)
        ok(refused(r, name, *need),
           f"#2: compare base.png {name} (the inverting A2B0 profile, by which lcms2 converts "
           f"200,100,50 to {moved}, with {what}): refused, exit 2, naming {need[0]} "
           f"({said(r)})")
    with_chunks(base, path("evil_good.png"), [evil, good])
    r = run("compare", "base.png", "evil_good.png")
    ok(refused(r, "evil_good.png", "2 ICC colour profiles"),
       f"#2: compare base.png evil_good.png (the inverting profile, then lcms2's sRGB one): "
       f"refused, exit 2, naming the two profiles ({said(r)})")
    # an iCCP not whole (libpng dropped these, and they were refused before too)
    whole = zlib.compress(open(path("evil.icc"), "rb").read(), 9)
    for name, body, what in (("icc_cut.png", b"display\0\0" + whole[:len(whole) // 2],
                              "its zlib stream cut in half"),
                             ("icc_method.png", b"display\0\1" + whole, "compression method 1"),
                             ("icc_noname.png", b"\0\0" + whole, "an empty name")):
        with_chunks(base, path(name), [(b"iCCP", body)])
        r = run("compare", "base.png", name)
        ok(refused(r, name, "iCCP"),
           f"#2: compare base.png {name} (an iCCP with {what}): refused, exit 2, naming the "
           f"iCCP ({said(r)})")
    # many sPLT chunks first: libpng keeps a bounded number of them and of the chunks
    # springpend reads raw, and drops the rest unsaid
    splt = [(b"sPLT", b"p%d\0\x08" % i + b"\0\0\0\0\0\0") for i in range(40)]
    with_chunks(base, path("splt_icc.png"), splt + [evil])
    r = run("compare", "base.png", "splt_icc.png")
    ok(refused(r, "splt_icc.png", "chunk"),
       f"#2: compare base.png splt_icc.png (40 sPLT chunks, then the inverting profile): "
       f"refused, exit 2 ({said(r)})")
    for name, before in (("good_srgb.png", [good, SRGB]), ("srgb_good.png", [SRGB, good]),
                         ("good.png", [good]), ("srgb_gama.png", [SRGB, gama_bad]),
                         ("srgb.png", [SRGB])):
        with_chunks(base, path(name), before)
        r = run("compare", "base.png", name)
        ok(taken(r), f"#2: compare base.png {name} (lcms2's sRGB profile and sRGB chunks, "
           f"or an sRGB chunk, which overrides a gAMA): taken, identical pixels ({said(r)})")


# ---- #3: an Orientation in the Exif directory ----------------------------------------------
def tiff(order="<", ifd0=(), sub=(), ifd1=(), sub_at=None, ptr_kind=4, ptrs=1, count=None):
    """TIFF data: IFD0 with the entries ifd0 (tag, kind, count, value) and, when sub is not
    None, the ExifIFD pointer (ptrs of them) to a directory with the entries sub (its offset
    sub_at, or right after IFD0; its count `count`, or the entries'); IFD1 with ifd1."""
    def entry(tag, kind, n, value):
        v = struct.pack(order + "HH", value, 0) if kind == 3 else struct.pack(order + "I", value)
        return struct.pack(order + "HHI", tag, kind, n) + v
    n0 = len(ifd0) + (ptrs if sub is not None else 0)
    size0 = 2 + 12 * n0 + 4
    sub_off = 8 + size0 if sub_at is None else sub_at
    size_sub = 2 + 12 * len(sub) + 4 if sub is not None else 0
    ifd1_off = 8 + size0 + size_sub if ifd1 else 0
    e0 = [entry(*e) for e in ifd0] + ([entry(0x8769, ptr_kind, 1, sub_off)] * ptrs
                                      if sub is not None else [])
    out = (b"II" if order == "<" else b"MM") + struct.pack(order + "HI", 42, 8)
    out += struct.pack(order + "H", n0) + b"".join(e0) + struct.pack(order + "I", ifd1_off)
    if sub is not None:
        out += struct.pack(order + "H", len(sub) if count is None else count)
        out += b"".join(entry(*e) for e in sub) + struct.pack(order + "I", 0)
    if ifd1:
        out += struct.pack(order + "H", len(ifd1)) + b"".join(entry(*e) for e in ifd1)
        out += struct.pack(order + "I", 0)
    return out


def orient(v):
    return (0x0112, 3, 1, v)


EXPOSURE = (0x829A, 4, 1, 0)  # ExposureTime's place: any other tag
for name, data, after, what, need in (
        ("exififd.png", tiff(sub=[orient(6)]), False, "Orientation 6 (attack16's reproduction)",
         "turned by 90 degrees clockwise"),
        ("exififd_be_after.png", tiff(">", sub=[EXPOSURE, orient(3)]), True,
         "big-endian Orientation 3, the eXIf after the pixels", "turned by 180 degrees"),
        ("exififd_o1.png", tiff(ifd0=[orient(1)], sub=[orient(8)]), False,
         "Orientation 8, IFD0's Orientation 1", "turned by 90 degrees counterclockwise"),
        ("exififd_far.png", tiff(sub=[orient(1)], sub_at=0xfffffff0), False,
         "its pointer past the chunk's end", "eXIf"),
        ("exififd_count.png", tiff(sub=[orient(1)], count=0xffff), False,
         "a count of 65535 entries, past the chunk's end", "eXIf"),
        ("exififd_twice.png", tiff(sub=[orient(1)], ptrs=2), False,
         "its pointer twice in IFD0", "eXIf"),
        ("exififd_short.png", tiff(sub=[orient(1)], ptr_kind=3), False,
         "its pointer a SHORT", "eXIf")):
    with_chunks(base, path(name), *(([], [(b"eXIf", data)]) if after else ([(b"eXIf", data)],)))
    r = run("compare", "base.png", name)
    ok(refused(r, name, need),
       f"#3: compare base.png {name} (an Exif directory with {what}): refused, exit 2, "
       f"naming '{need}' ({said(r)})")
for name, data, what in (
        ("exififd_one.png", tiff(sub=[EXPOSURE, orient(1)]), "Orientation 1"),
        ("exififd_none.png", tiff(ifd0=[orient(1)], sub=[EXPOSURE]), "no Orientation"),
        ("exififd_loop.png", tiff(sub=[], sub_at=8), "the pointer back at IFD0"),
        ("ifd1.png", tiff(ifd1=[orient(6)]), "no Exif directory, IFD1's Orientation 6")):
    with_chunks(base, path(name), [(b"eXIf", data)])
    r = run("compare", "base.png", name)
    ok(taken(r), f"#3: compare base.png {name} ({what}): taken, identical pixels ({said(r)})")

done()
