#!/usr/bin/env python3
"""springpend tests (issue 28): what the twelfth attacker's pass
(doc/notes/2026-11-27/attack12.md) found in compare's readers:
- attack12 #11: the PNG colour rule (attack11 #21) refused any ICC profile
  (iCCP) and any cHRM without an sRGB chunk, though an sRGB profile (as
  GIMP embeds) and sRGB's own chromaticities are drawn as the pixels read:
  an iCCP that converts every colour to sRGB within 2 levels is taken, and
  so is a cHRM of sRGB's values standing alone; other profiles are refused.
  A cHRM beside a gAMA (even sRGB's 1/2.2, as ImageMagick writes without
  an sRGB chunk) is still refused: Chromium then draws a pure 2.2 power
  curve, up to 9 levels off (computed here, not read from springpend);
- attack12 #10: a cICP chunk (PNG's third edition: BT.709 with a linear
  transfer, or BT.2020 with PQ) and the HDR chunks mDCv and cLLi passed as
  "identical pixels": refused, naming the chunk; a cICP of sRGB's own code
  points (1 13 0 1) is taken;
- attack12 #12: the display-matrix rule (attack11 #8) read the matrix's
  angle alone: a video mirrored top to bottom (angle 0) passed, and one
  mirrored left to right was "turned by -180 degrees": any matrix but the
  identity is refused (a translation alone moves no pixel), a mirror said
  as one, which way;
- attack12 #8: WebM and Matroska share FFmpeg's demuxer, so an H.264
  Matroska file named .webm was compared as WebM (browsers do not play it
  as one): a .webm must hold VP8, VP9 or AV1 video, else it is refused,
  exit 2; springpend's own .webm (VP9) and the H.264 file named .mkv are
  read;
- attack12 #5: under ulimit -v, a lone decode that failed with an error
  FFmpeg gives for damaged data (which its decoders also give for a failed
  allocation) called an intact 1080p video damaged, exit 2: the file's
  container, read packet by packet with little memory, decides; where it
  is whole, "cannot decode X under this memory limit", exit 1;
- attack12 #6: under a ulimit -v too low to map FFmpeg's libraries, the
  module message said "reinstall springpend" and compare "cannot read",
  exit 2: out of memory, naming the limit, exit 1.
The ICC profiles are built here from the ICC specification (a v2 display
profile: its colorants and tone curves), one through lcms2's own sRGB.
usage: test_attack12_readers.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import ctypes
import os
import resource
import shutil
import subprocess
import struct
import zlib

import sptest
from sptest import done, err, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack12-readers")
default = os.path.join(scenes, "default.ini")


# ---- PNG and ICC building blocks ---------------------------------------------------------
def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


def with_chunks(src_png, out, *chunks):
    """src_png's PNG with the chunks (kind, body) before its first IDAT."""
    d = open(src_png, "rb").read()
    at = d.index(b"IDAT") - 4
    open(out, "wb").write(d[:at] + b"".join(chunk(k, b) for k, b in chunks) + d[at:])


def gray_png(out):
    """A 64x32 8-bit gray PNG: every level 0..255 once in each 4 rows (by hand)."""
    rows = b"".join(b"\0" + bytes((x + 64 * (y % 4)) for x in range(64)) for y in range(32))
    ihdr = struct.pack(">IIBBBBB", 64, 32, 8, 0, 0, 0, 0)
    open(out, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr)
                          + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def s15(v):
    return struct.pack(">i", int(round(v * 65536)))


def xyz(x, y, z):
    return b"XYZ \0\0\0\0" + s15(x) + s15(y) + s15(z)


def curv(table):
    return b"curv\0\0\0\0" + struct.pack(">I", len(table)) + b"".join(
        struct.pack(">H", v) for v in table)


def srgb_curve(n=1024):
    """sRGB's tone curve (IEC 61966-2-1), encoded value to linear light."""
    out = []
    for i in range(n):
        v = i / (n - 1)
        lin = v / 12.92 if v <= 0.04045 else ((v + 0.055) / 1.055) ** 2.4
        out.append(int(round(lin * 65535)))
    return out


LINEAR = [int(round(i / 1023 * 65535)) for i in range(1024)]
# the colorants of sRGB and of Adobe RGB (1998), adapted to D50 (Bradford), as in their profiles
SRGB_D50 = ((0.4361, 0.2225, 0.0139), (0.3851, 0.7169, 0.0971), (0.1431, 0.0606, 0.7141))
ADOBE_D50 = ((0.6097, 0.3111, 0.0195), (0.2053, 0.6257, 0.0609), (0.1492, 0.0632, 0.7446))


def icc(colorants, curve, gray=False):
    """A v2 display profile (ICC.1:2001-04): matrix/TRC, or a gray TRC."""
    desc = b"test\0"
    tags = [(b"desc", b"desc\0\0\0\0" + struct.pack(">I", len(desc)) + desc + b"\0" * 79),
            (b"wtpt", xyz(0.9642, 1.0, 0.8249)), (b"cprt", b"text\0\0\0\0none\0")]
    if gray:
        tags.append((b"kTRC", curv(curve)))
    else:
        tags += [(n, xyz(*c)) for n, c in zip((b"rXYZ", b"gXYZ", b"bXYZ"), colorants)]
        tags += [(n, curv(curve)) for n in (b"rTRC", b"gTRC", b"bTRC")]
    off, table, data = 128 + 4 + 12 * len(tags), b"", b""
    for name, body in tags:
        data += b"\0" * (-(off + len(data)) % 4)
        table += name + struct.pack(">II", off + len(data), len(body))
        data += body
    body = struct.pack(">I", len(tags)) + table + data
    hdr = (struct.pack(">I", 128 + len(body)) + b"none" + bytes([2, 0x10, 0, 0]) + b"mntr"
           + (b"GRAY" if gray else b"RGB ") + b"XYZ " + b"\0" * 12 + b"acsp" + b"\0" * 28
           + s15(0.9642) + s15(1.0) + s15(0.8249) + b"\0" * 48)
    assert len(hdr) == 128
    return hdr + body


def lcms_srgb():
    """lcms2's built-in sRGB profile (what GIMP embeds is made the same way), or None."""
    try:
        lib = ctypes.CDLL("liblcms2.so.2")
    except OSError:
        return None
    lib.cmsCreate_sRGBProfile.restype = ctypes.c_void_p
    h, n = ctypes.c_void_p(lib.cmsCreate_sRGBProfile()), ctypes.c_uint32(0)
    lib.cmsSaveProfileToMem(h, None, ctypes.byref(n))
    buf = ctypes.create_string_buffer(n.value)
    lib.cmsSaveProfileToMem(h, buf, ctypes.byref(n))
    return buf.raw[:n.value]


def iccp(profile):
    return (b"iCCP", b"a profile\0\0" + zlib.compress(profile))


# a 2.2 power curve shown on an sRGB screen: how far it moves a level (what Chromium draws for
# gAMA + cHRM), computed here
def srgb_encode(lin):
    return 12.92 * lin if lin <= 0.0031308 else 1.055 * lin ** (1 / 2.4) - 0.055


power_off = max(abs(round(255 * srgb_encode((v / 255) ** (1 / 0.45455))) - v) for v in range(256))

# ---- attack12 #11 and #10: a PNG's colour chunks --------------------------------------------
r = run("still", default, "--at", "0", "--size", "320x180", "-o", "s.png", "-q")
assert r.returncode == 0, err(r)
s = path("s.png")
gray_png(path("gray.png"))
SRGB_CHRM = struct.pack(">8I", 31270, 32900, 64000, 33000, 30000, 60000, 15000, 6000)
WIDE_CHRM = struct.pack(">8I", 31270, 32900, 64000, 33000, 21000, 71000, 15000, 6000)
GAMMA = (b"gAMA", struct.pack(">I", 45455))
cases = [  # name, base, chunks, refused with ("" when taken)
    ("hand.png", s, [iccp(icc(SRGB_D50, srgb_curve()))], ""),
    # libpng warns of its rendering intent (7: outside ICC's four) but keeps it; Chromium
    # draws it as read: judged as any other
    ("intent7.png", s, [iccp(bytes(icc(SRGB_D50, srgb_curve())[:64]) + struct.pack(">I", 7)
                             + icc(SRGB_D50, srgb_curve())[68:])], ""),
    ("adobe.png", s, [iccp(icc(ADOBE_D50, srgb_curve()))], "ICC colour profile (iCCP) other than sRGB"),
    ("linear.png", s, [iccp(icc(SRGB_D50, LINEAR))], "ICC colour profile (iCCP) other than sRGB"),
    ("grayonrgb.png", s, [iccp(icc(None, srgb_curve(), gray=True))], "iCCP"),
    ("grayicc.png", path("gray.png"), [iccp(icc(None, srgb_curve(), gray=True))], ""),
    ("graylin.png", path("gray.png"), [iccp(icc(None, LINEAR, gray=True))], "other than sRGB"),
    ("chrm.png", s, [(b"cHRM", SRGB_CHRM)], ""),
    ("widechrm.png", s, [(b"cHRM", WIDE_CHRM)], "chromaticities (cHRM) other than sRGB's"),
    ("im.png", s, [GAMMA, (b"cHRM", SRGB_CHRM)], f"up to {power_off} levels off"),
    ("srgbim.png", s, [(b"sRGB", b"\0"), GAMMA, (b"cHRM", SRGB_CHRM)], ""),
    ("cicp.png", s, [(b"cICP", bytes([1, 8, 0, 1]))], "(cICP: primaries 1, transfer 8"),
    ("pq.png", s, [(b"cICP", bytes([9, 16, 0, 1]))], "(cICP: primaries 9, transfer 16"),
    ("cicpsrgb.png", s, [(b"cICP", bytes([1, 13, 0, 1]))], ""),
    ("mdcv.png", s, [(b"mDCv", struct.pack(">8HII", *([0] * 8), 10000000, 1))], "(mDCv)"),
    ("clli.png", s, [(b"cLLi", struct.pack(">II", 10000000, 4000000))], "(cLLi)"),
]
srgb_lcms = lcms_srgb()
if srgb_lcms:
    cases.append(("lcms.png", s, [iccp(srgb_lcms)], ""))
else:
    sptest.skip("compare s.png lcms.png (lcms2's sRGB profile)", "liblcms2.so.2 does not load")
# real profiles where Debian's icc-profiles-free and colord-data are installed (not required)
for pkg, prof, said in (("icc-profiles-free", "sRGB.icc", ""),
                        ("colord-data", "colord/sRGB.icc", ""),
                        ("colord-data", "colord/AdobeRGB1998.icc", "other than sRGB"),
                        ("colord-data", "colord/Rec709.icc", "other than sRGB")):
    full = os.path.join("/usr/share/color/icc", prof)
    if os.path.exists(full):
        cases.append(("sys-" + prof.replace("/", "-").replace(".icc", ".png"), s,
                      [iccp(open(full, "rb").read())], said))
    else:
        sptest.skip(f"compare s.png with {prof} embedded", f"{pkg} is not installed")
for name, base, chunks, said in cases:
    with_chunks(base, path(name), *chunks)
    r = run("compare", os.path.basename(base), name)
    if said:
        ok(r.returncode == 2 and said in err(r) and f"{name} " in err(r)
           and ("without the" in err(r) or "save it" in err(r)),
           f"compare {os.path.basename(base)} {name}: refused, exit 2, saying what and what to "
           f"do (exit {r.returncode}: {err(r)[-260:]!r})")
    else:
        ok(r.returncode == 0 and "identical pixels" in r.stdout.decode(),
           f"compare {os.path.basename(base)} {name}: taken, identical pixels (exit "
           f"{r.returncode}: {err(r)[-200:]!r})")

# ---- attack12 #12: a video a display matrix mirrors, written into its tkhd here -----------
def with_matrix(src_mp4, out, edit):
    """src_mp4 with its (first) track header's 3x3 matrix changed by edit(m, w, h)."""
    d = bytearray(open(src_mp4, "rb").read())
    at = d.index(b"tkhd") - 4
    mo = at + 12 + (20 if d[at + 8] == 0 else 32) + 16       # the matrix after the volume
    m = list(struct.unpack(">9i", d[mo:mo + 36]))
    assert m == [1 << 16, 0, 0, 0, 1 << 16, 0, 0, 0, 1 << 30], m   # springpend's: the identity
    w, h = (x >> 16 for x in struct.unpack(">II", d[mo + 36:mo + 44]))
    edit(m, w, h)
    d[mo:mo + 36] = struct.pack(">9i", *m)
    open(out, "wb").write(d)


def vflip(m, w, h):
    m[4], m[7] = -(1 << 16), h << 16


def hflip(m, w, h):
    m[0], m[6] = -(1 << 16), w << 16


def hflip_turn(m, w, h):
    m[0], m[1], m[3], m[4] = 0, 1 << 16, 1 << 16, 0


def turn_cw(m, w, h):
    m[0], m[1], m[3], m[4] = 0, 1 << 16, -(1 << 16), 0


def stretch(m, w, h):
    m[0] = 2 << 16


def move(m, w, h):
    m[6] = 10 << 16


r = run("render", default, "--size", "160x90", "--fps", "10", "--set", "video.duration=0.5",
        "-o", "a.mp4", "-q")
assert r.returncode == 0, err(r)
for name, edit, said in (("vflip.mp4", vflip, "mirrored top to bottom"),
                         ("hflip.mp4", hflip, "mirrored left to right (a display matrix)"),
                         ("hflipturn.mp4", hflip_turn, "mirrored left to right and turned by 90"),
                         ("turned.mp4", turn_cw, "turned by 90 degrees clockwise"),
                         ("stretch.mp4", stretch, "scaled, sheared or in perspective"),
                         ("move.mp4", move, "")):
    with_matrix(path("a.mp4"), path(name), edit)
    r = run("compare", "a.mp4", name)
    if said:
        ok(r.returncode == 2 and said in err(r) and "-180" not in err(r),
           f"compare a.mp4 {name}: refused, exit 2, saying {said!r} (exit {r.returncode}: "
           f"{err(r)[-200:]!r})")
    else:
        ok(r.returncode == 0, f"compare a.mp4 {name} (a translation alone): compared (exit "
           f"{r.returncode}: {err(r)[-200:]!r})")

# ---- attack12 #8: a .webm holds a WebM codec ----------------------------------------------
if shutil.which("ffmpeg"):
    subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", "a.mp4", "-c:v", "libx264", "-f",
                    "matroska", "h264.webm"], cwd=work, check=True, timeout=120)
    shutil.copy(path("h264.webm"), path("h264.mkv"))
    r = run("compare", "a.mp4", "h264.webm")
    ok(r.returncode == 2 and "h264.webm: a Matroska file with H.264" in err(r)
       and "not WebM as its name says" in err(r),
       f"compare a.mp4 h264.webm (H.264 in Matroska): refused, exit 2 (exit {r.returncode}: "
       f"{err(r)[-200:]!r})")
    r = run("compare", "a.mp4", "h264.mkv")
    ok(r.returncode == 0, f"compare a.mp4 h264.mkv (the same file named .mkv): compared (exit "
       f"{r.returncode}: {err(r)[-200:]!r})")
    r = run("scene", "h264.webm", "--command")
    ok(r.returncode == 2 and "not WebM as its name says" in err(r),
       f"scene h264.webm --command: refused, exit 2 (exit {r.returncode}: {err(r)[-200:]!r})")
else:
    sptest.skip("an H.264 Matroska file named .webm", "ffmpeg is not installed")
r = run("render", default, "--size", "160x90", "--fps", "10", "--set", "video.duration=0.5",
        "-o", "v.webm", "-q", timeout=120)
assert r.returncode == 0, err(r)
shutil.copy(path("v.webm"), path("v2.webm"))
r = run("compare", "v.webm", "v2.webm")
ok(r.returncode == 0, f"compare v.webm v2.webm (springpend's VP9 WebM): compared (exit "
   f"{r.returncode}: {err(r)[-200:]!r})")

# ---- attack12 #5 and #6: under ulimit -v, memory is not the file's fault -------------------
def under(kb):
    """A preexec_fn: ulimit -v kb (soft and hard, as the shell's ulimit sets them)."""
    return lambda: resource.setrlimit(resource.RLIMIT_AS, (kb << 10, kb << 10))


if sanitized:
    sptest.skip("compare under ulimit -v", "ulimit -v and a sanitizer's shadow memory")
else:
    r = run("render", default, "--size", "1920x1080", "--fps", "10", "--set", "video.duration=2",
            "-o", "big.mp4", "-q", timeout=180)
    assert r.returncode == 0, err(r)
    shutil.copy(path("big.mp4"), path("big2.mp4"))
    whole = open(path("big.mp4"), "rb").read()
    open(path("cut.mp4"), "wb").write(whole[:len(whole) * 80 // 100])
    r = run("compare", "big.mp4", "big2.mp4", timeout=120)
    assert r.returncode == 0, err(r)           # intact: what memory enough shows
    seen, cut = {}, {}
    for kb in range(254000, 282000, 2000):
        # 127: the dynamic loader itself could not map a library, before springpend ran
        r = run("compare", "big.mp4", "big2.mp4", preexec_fn=under(kb), timeout=120)
        if r.returncode != 127:
            seen[kb] = (r.returncode, r.stdout.decode()[-110:].strip())
        r = run("compare", "big.mp4", "cut.mp4", preexec_fn=under(kb), timeout=120)
        if r.returncode != 127:
            cut[kb] = r.returncode
    damaged = {kb: v for kb, v in seen.items() if v[0] not in (0, 1) or "damaged" in v[1]}
    ok(seen and not damaged,
       f"compare big.mp4 big2.mp4 (intact, 1920x1080) under ulimit -v 254000..280000 kB: never "
       f"'damaged' (exit 2), out of memory or ok ({damaged or sorted(set(v[0] for v in seen.values()))})")
    told = [v[1] for v in seen.values() if "under this memory limit (ulimit -v" in v[1]]
    ok(all("may be the file's or memory's" in t for t in told),
       f"where a lone decode fails on a whole container: 'cannot decode ... under this memory "
       f"limit' ({len(told)} of {len(seen)} limits; {told[:1]})")
    ok(cut and all(rc in (1, 2) for rc in cut.values()),
       f"compare big.mp4 cut.mp4 (cut at 80 %) under the same limits: never compared "
       f"(exits {cut})")
    for kb in (100000, 200000):
        for cmd in (["compare", "big.mp4", "big2.mp4"], ["scene", "big.mp4", "--command"]):
            r = run(*cmd, preexec_fn=under(kb), timeout=120)
            e = err(r) + r.stdout.decode()
            ok(r.returncode in (1, 127) and "reinstall" not in e and "cannot read" not in e
               and (r.returncode == 127 or (f"out of memory (ulimit -v {kb} kB)" in e
                                            and "allow more memory" in e)),
               f"{' '.join(cmd)} under ulimit -v {kb}: the module out of memory, exit 1 (exit "
               f"{r.returncode}: {e[-240:]!r})")

done()
