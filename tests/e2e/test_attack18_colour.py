#!/usr/bin/env python3
"""springpend tests (issue 28): the eighteenth attacker's pass
(doc/notes/2026-11-27/attack18.md), compare's PNG reader:
- #1: gAMA and cHRM were judged through libpng's colour-space state, which
  forgets a gAMA or cHRM written twice, or after a palette (PLTE: a
  truecolour PNG may carry a suggested one), while Chromium draws the image
  by the first (up to 73 levels off for a gAMA of 1.0, 103 for other
  primaries: measured by the attacker). Every colour chunk (gAMA, cHRM,
  sRGB, iCCP, cICP) is now read as it stands: one twice, or after PLTE or
  the pixels (where PNG allows none), is refused, exit 2, naming it; one
  gAMA of 1/2.2 or one cHRM of sRGB's alone is taken, as is sRGB + gAMA +
  cHRM (what ImageMagick writes), and springpend's own PNG;
- #4: a profile that only claims to be one of the ICC's sRGB profiles was
  taken unjudged (libpng's test binds the header's MD5 field, the length,
  intent, Adler-32 and CRC-32, not the content). data/attack18_forged_
  srgb.icc is the attacker's forgery (attack18's forge.py): lcms2's sRGB
  profile with its red and blue primaries (rXYZ, bXYZ) swapped, padded and
  set so that all five match png.c's entry for sRGB_IEC61966-2-1_black_
  scaled.icc; checked here from its bytes. It is now refused, naming the
  iCCP; lcms2's own sRGB profile is still taken.
The expectations come from the bytes written here, never from springpend's
output.
usage: test_attack18_colour.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil
import struct
import subprocess
import zlib

import sptest
from sptest import done, err, ok, skip

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack18-colour")
HERE = os.path.dirname(os.path.abspath(__file__))


def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


def build(src_png, out, head=(), before_idat=(), after=()):
    """src_png with the chunks (kind, body) head right after its IHDR, before_idat right before
    its first IDAT and after right before its IEND."""
    d = open(src_png, "rb").read()
    idat = d.index(b"IDAT") - 4
    end = d.rindex(b"IEND") - 4
    mk = lambda cs: b"".join(chunk(k, b) for k, b in cs)
    open(out, "wb").write(d[:33] + mk(head) + d[33:idat] + mk(before_idat) + d[idat:end]
                          + mk(after) + d[end:])


def refused(r, name, *said):
    e = err(r)
    return r.returncode == 2 and f"{name} " in e and all(s in e for s in said) \
        and not r.stdout.strip().startswith(b"ok")


def taken(r):
    return r.returncode == 0 and "identical pixels" in r.stdout.decode()


def said(r):
    return f"exit {r.returncode}: {(err(r) or r.stdout.decode())[-220:]!r}"


r = run("still", scenes + "/default.ini", "--at", "1", "--size", "320x180", "-o", "base.png",
        "-q")
assert r.returncode == 0, err(r)
base = path("base.png")
assert open(base, "rb").read()[12:16] == b"IHDR" and open(base, "rb").read()[25] in (2, 6)  # truecolour

G = (b"gAMA", struct.pack(">I", 45455))                   # 1/2.2
G1 = (b"gAMA", struct.pack(">I", 100000))                 # 1.0
OC = (b"cHRM", struct.pack(">8I", 31270, 32900, 70000, 30000, 20000, 70000, 15000, 6000))
SC = (b"cHRM", struct.pack(">8I", 31270, 32900, 64000, 33000, 30000, 60000, 15000, 6000))
SRGB = (b"sRGB", b"\0")
CICP = (b"cICP", bytes((1, 13, 0, 1)))                    # sRGB's code points
PLTE = (b"PLTE", bytes(range(48)))                        # a suggested palette, 16 colours

# ---- #1: each colour chunk once, before PLTE and IDAT ---------------------------------------
for name, head, before_idat, after, need, what in (
        ("g_oc_oc.png", [G, OC, OC], [], [], "2 sets of chromaticities", "cHRM (other) twice"),
        ("g_oc_sc.png", [G, OC, SC], [], [], "cHRM chunks", "cHRM (other), then sRGB's"),
        ("g_sc_sc.png", [G, SC, SC], [], [], "cHRM chunks", "sRGB's cHRM twice beside a gAMA"),
        ("oc_g_dup.png", [OC, G, G], [], [], "2 gammas (gAMA chunks)", "gAMA twice"),
        ("g1_g.png", [G1, G], [], [], "gAMA chunks", "a gAMA of 1.0, then 1/2.2"),
        ("plte_g1.png", [], [PLTE, G1], [], "gAMA chunk after its palette", "gAMA 1.0 after PLTE"),
        ("plte_g_oc.png", [G], [PLTE, OC], [], "cHRM chunk after its palette",
         "cHRM (other) after PLTE"),
        ("srgb2.png", [SRGB, SRGB], [], [], "sRGB chunks", "two sRGB chunks"),
        ("cicp2.png", [CICP, CICP], [], [], "cICP chunks", "two cICP of sRGB's"),
        ("g1_after.png", [], [], [G1], "gAMA chunk after its pixels", "gAMA 1.0 after IDAT"),
        ("oc_after.png", [G], [], [OC], "cHRM chunk after its pixels", "cHRM (other) after IDAT"),
        ("g_short.png", [(b"gAMA", b"\0\xb1\x8f")], [], [], "gAMA chunk that is not 4 bytes",
         "a gAMA of 3 bytes")):
    build(base, path(name), head, before_idat, after)
    r = run("compare", "base.png", name)
    ok(refused(r, name, need), f"#1: compare base.png {name} ({what}): refused, exit 2, saying "
       f"{need!r} ({said(r)})")

# still refused as before: one chunk that moves colours
for name, head, need in (("g1.png", [G1], "gAMA"), ("oc.png", [OC], "cHRM"),
                         ("g_sc.png", [G, SC], "beside a gamma")):
    build(base, path(name), head)
    r = run("compare", "base.png", name)
    ok(refused(r, name, need), f"#1: compare base.png {name}: refused, exit 2, naming {need} "
       f"({said(r)})")

# taken: springpend's own PNG, one gAMA of 1/2.2, one sRGB cHRM, sRGB + gAMA + cHRM, a
# suggested palette after the colour chunks
shutil.copy(base, path("own.png"))
r = run("compare", "base.png", "own.png")
ok(taken(r), f"#1: compare base.png own.png (springpend's own PNG): taken ({said(r)})")
for name, head, before_idat, what in (("g.png", [G], [], "one gAMA of 1/2.2"),
                                      ("sc.png", [SC], [], "one cHRM of sRGB's"),
                                      ("srgb_g_sc.png", [SRGB, G, SC], [], "sRGB, gAMA, cHRM"),
                                      ("g_plte.png", [G], [PLTE], "a gAMA, then a PLTE"),
                                      ("cicp.png", [CICP], [], "one cICP of sRGB's")):
    build(base, path(name), head, before_idat)
    r = run("compare", "base.png", name)
    ok(taken(r), f"#1: compare base.png {name} ({what}): taken, identical pixels ({said(r)})")

# ---- #4: a profile that only claims to be the ICC's sRGB --------------------------------------
forged = open(os.path.join(HERE, "data", "attack18_forged_srgb.icc"), "rb").read()


def tag(p, sig):
    n = struct.unpack(">I", p[128:132])[0]
    for k in range(n):
        s, off, size = struct.unpack(">4sII", p[132 + 12 * k:144 + 12 * k])
        if s == sig:
            return p[off:off + size]
    return None


# what libpng's known-sRGB test binds (png.c: sRGB_IEC61966-2-1_black_scaled.icc): all set
assert len(forged) == 3048 == struct.unpack(">I", forged[:4])[0]
assert forged[84:100].hex() == "29f83ddeaff255ae7842fae4ca83390d"
assert zlib.adler32(forged) == 0x0a3fd9f6 and zlib.crc32(forged) == 0x3b8772b9
assert struct.unpack(">I", forged[64:68])[0] == 0  # perceptual intent
# and its content: red's primary is blue's (X of sRGB's red, D50: 0.4361; of blue: 0.1431)
rx = struct.unpack(">i", tag(forged, b"rXYZ")[8:12])[0] / 65536
bx = struct.unpack(">i", tag(forged, b"bXYZ")[8:12])[0] / 65536
assert abs(rx - 0.1431) < 0.01 and abs(bx - 0.4361) < 0.01, (rx, bx)
build(base, path("forged.png"), [(b"iCCP", b"icc\0\0" + zlib.compress(forged, 9))])
r = run("compare", "base.png", "forged.png")
ok(refused(r, "forged.png", "iCCP"),
   f"#4: compare base.png forged.png (a profile with red and blue swapped, forged to pass "
   f"libpng's known-sRGB test, rXYZ X = {rx:.4f}): refused, exit 2, naming the iCCP "
   f"({said(r)})")

cc = shutil.which("cc") or shutil.which("gcc")
why_not = None if cc else "no C compiler (cc)"
if cc:
    open(path("mksrgb.c"), "w").write("#include <lcms2.h>\nint main(int c, char **v)\n"
                                      "{ return c != 2 || !cmsSaveProfileToFile("
                                      "cmsCreate_sRGBProfile(), v[1]); }\n")
    c = subprocess.run([cc, "-O1", "-o", path("mksrgb"), path("mksrgb.c"), "-llcms2"],
                       capture_output=True)
    if c.returncode != 0:
        why_not = f"the lcms2 helper does not build: {c.stderr.decode()[-160:]}"
if why_not:
    skip("#4: lcms2's sRGB profile: taken", why_not)
else:
    assert subprocess.run([path("mksrgb"), path("srgb.icc")]).returncode == 0
    good = open(path("srgb.icc"), "rb").read()
    build(base, path("good.png"), [(b"iCCP", b"icc\0\0" + zlib.compress(good, 9))])
    r = run("compare", "base.png", "good.png")
    ok(taken(r), f"#4: compare base.png good.png (lcms2's sRGB profile): taken, judged by its "
       f"content ({said(r)})")
done()
