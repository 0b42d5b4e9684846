#!/usr/bin/env python3
"""springpend tests: the attacker's third pass (doc/notes/2026-11-26c/
attack3.md), findings 5, 6, 11 (still), 12, 13 and 14, and the MP4 tag that
FFmpeg read whole before springpend looked at its size. Each check is a
class, run as the attacker ran it:
- a FIFO or folder named .svg or .pdf is refused at once by `scene` (the FIFO
  hung, the folder was exit 1);
- a file name's terminal escapes (ESC, BEL, C1, U+FFFE) never reach the
  terminal from still, render, data, sweep or info, nor data's scene column
  or the side-by-side cell label: they are shown as \\x1b, \\u009b, \\ufffe;
- xlabel/ylabel are counted per plot (phase is two) and the refusal names
  where the value came from (--set or FILE:LINE);
- what would be silently ignored is refused: colorbar_label without a colour
  bar, --energy outside a poincare sweep, commas in view.camera, azimuth or
  top panels on a planar scene;
- a forged SVG character reference is named as such (it was "longer than
  262143 bytes", or wrapped to a newline);
- still --state gives the units of z, vz and azimuth; a merge of shards from
  two sweeps pairs the differing field with itself ("p1.csv: kernel=fast;
  p2.csv: kernel=exact", not kernel=fast against the next shard's vary);
- an MP4 whose metadata box claims 50 MB is refused before FFmpeg reads it
  (it cost about 150 MB of memory before the 256 KiB check).
usage: test_attack3.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import os
import shutil
import struct
import subprocess
import sys

import sptest
from sptest import done


def ok(cond, what):
    return sptest.ok(cond, what.replace("\n", " | "))


exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "attack3"))
scenes = os.path.join(src, "..", "scenes")
default = os.path.join(scenes, "default.ini")
chaotic = os.path.join(scenes, "chaotic.ini")
swing = os.path.join(scenes, "swinging-spring.ini")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def run(*args, timeout=120, **kw):
    kw.setdefault("capture_output", True)
    return subprocess.run([exe, *args], cwd=work, timeout=timeout, **kw)


def path(*names):
    return os.path.join(work, *names)


def err(r):
    return r.stderr.decode(errors="replace").strip()


def hangs(*args):
    """Runs springpend for at most 10 s: (returncode or 'hung', stderr)."""
    return sptest.hangs(run, *args)


def raw_controls(b):
    """The control bytes and noncharacters a terminal or parser would meet
    in b (bytes): C0 but tab and newline, DEL, C1 (as UTF-8), U+FFFE/FFFF."""
    t = b.decode("utf-8", errors="replace")
    return sorted({f"U+{ord(ch):04X}" for ch in t
                   if (ord(ch) < 0x20 and ch not in "\t\n") or 0x7f <= ord(ch) < 0xa0
                   or ord(ch) in (0xfffe, 0xffff)})


def refused(r, *words, out=None):
    """Exit 2, every word in stderr, and no output file at out."""
    e = err(r)
    return (r.returncode == 2 and all(w in e for w in words)
            and (out is None or not os.path.exists(path(out)))), e[:300]


# ---- 5: FIFOs and folders named .svg / .pdf ---------------------------------
for ext in ("svg", "pdf"):
    os.mkfifo(path(f"ff.{ext}"))
    rc, e = hangs("scene", f"ff.{ext}")
    ok(rc == 2 and "is a FIFO, not a regular file" in e,
       f"scene ff.{ext} (a FIFO): refused at once, exit 2 ({rc}: {e[:160]})")
    os.mkdir(path(f"dir.{ext}"))
    rc, e = hangs("scene", f"dir.{ext}")
    ok(rc == 2 and "is a folder, not a regular file" in e,
       f"scene dir.{ext} (a folder): exit 2, 'is a folder' ({rc}: {e[:160]})")

# ---- 6: terminal escapes in file names ---------------------------------------
ESC = "\x1b[31m"
NASTY = "\x1b]2;PWN\x07\x1b[31mX\u009b\ufffe"  # OSC title, BEL, SGR, C1 CSI, U+FFFE
SHOWN = "\\x1b]2;PWN\\x07\\x1b[31mX\\u009b\\ufffe"
outs = [("still", [default, "--at", "1", "--size", "160x90", "-o", f"o{ESC}.png"]),
        ("still (svg)", [default, "--at", "1", "--size", "160x90", "-o", f"o{ESC}.svg"]),
        ("render", [default, "--size", "160x90", "--fps", "10", "--set", "video.duration=0.3",
                    "-o", f"r{ESC}.mp4"]),
        ("data", [default, "--every", "1", "-o", f"d{ESC}.csv"]),
        ("sweep", [chaotic, "--vary", "initial.angle=10:20:2", "--measure", "lyapunov",
                   "--time", "2", "-o", f"s{ESC}.png", "--csv", f"s{ESC}.csv"])]
for what, args in outs:
    cmd = what.split()[0]
    r = run(cmd, *args)
    ok(r.returncode == 0 and not raw_controls(r.stderr) and b"\\x1b[31m" in r.stderr,
       f"{what} -o NAME with ESC: 'wrote' shows \\x1b, no raw control byte "
       f"(rc {r.returncode}, {raw_controls(r.stderr)}: {err(r)[:160]})")

shutil.copy(default, path(NASTY + ".ini"))
shutil.copy(default, path(SHOWN + ".ini"))  # a name that is the escaped text itself
r = run("info", NASTY + ".ini")
first = r.stdout.split(b"\n")[0]
ok(r.returncode == 0 and not raw_controls(r.stdout) and first.decode() ==
   f"scene {SHOWN} ({SHOWN}.ini)",
   f"info on a scene named with OSC, BEL, C1 and U+FFFE: its 'scene' line shown escaped "
   f"({raw_controls(r.stdout)}: {first[:120]!r})")
r = run("info", "nope" + NASTY + ".ini")
ok(r.returncode == 2 and not raw_controls(r.stderr) and SHOWN in err(r),
   f"a missing scene with such a name: the message shows it escaped ({err(r)[:160]})")
r = run("data", NASTY + ".ini", default, "--every", "100", "-o", "-")
rows = r.stdout.decode("utf-8", errors="replace").splitlines()
ok(r.returncode == 0 and not raw_controls(r.stdout) and rows[1].startswith(SHOWN + ","),
   f"data side by side: the scene column holds the name escaped, no raw control byte "
   f"({raw_controls(r.stdout)}: {rows[1][:60] if len(rows) > 1 else rows!r})")


def idat(p):
    """A PNG's pixel data (its IDAT chunks joined): equal pixels, equal bytes
    from one encoder."""
    data, i, out = open(p, "rb").read(), 8, b""
    while i < len(data):
        n, kind = struct.unpack(">I4s", data[i:i + 8])
        out += data[i + 8:i + 8 + n] if kind == b"IDAT" else b""
        i += 12 + n
    return out


# the automatic cell label draws the name as the message shows it (it drew
# the control characters as glyphs). It was checked as the same pixels as a
# scene whose file is named with the escaped text itself; since the eighth
# pass (attack8.md finding 12) the shown form is one-to-one (that file's
# backslashes show as \\), so the two labels now differ, as intended
r1 = run("still", default, NASTY + ".ini", "--at", "1", "--size", "640x360", "-o", "lab1.png")
r2 = run("still", default, SHOWN + ".ini", "--at", "1", "--size", "640x360", "-o", "lab2.png")
ok(r1.returncode == 0 and r2.returncode == 0 and idat(path("lab1.png")) != idat(path("lab2.png")),
   f"side-by-side cell label of a name with control characters: drawn escaped, other "
   f"pixels than the name that is the escaped text's ({err(r1)[:100]}; {err(r2)[:100]})")

# ---- 11: xlabel/ylabel per plot, and the refusal's origin --------------------
r = run("still", chaotic, "--at", "3", "--size", "640x360", "--set", "view.xlabel=A|B|C|D",
        "-o", "xl.png")
ok(*refused(r, "--set view.xlabel=A|B|C|D:", "5 plots", "phase r, phase theta",
            "'phase' is two plots", out="xl.png"))
r = run("still", chaotic, "--at", "3", "--size", "640x360", "--set", "view.xlabel=A|B|C|D|E",
        "-o", "xl.png")
ok(r.returncode == 0, f"chaotic.ini's 4 panels, 5 plots: 5 xlabel entries accepted ({err(r)[:120]})")
with open(path("xl.ini"), "w") as f:
    f.write("[view]\npanels = r, theta\nylabel = a|b|c\n")
r = run("still", "xl.ini", "--at", "1", "-o", "xl2.png")
ok(*refused(r, "xl.ini:3: view.ylabel = 'a|b|c' has 3 entries for 2 plots (r, theta)",
            out="xl2.png"))

# ---- 12: what was silently ignored -------------------------------------------
r = run("still", swing, "--at", "3", "--size", "320x180", "--set", "view.colorbar_label=SPEED",
        "-o", "cb.png")
ok(*refused(r, "--set view.colorbar_label: view.colorbar_label = 'SPEED'",
            "view.colorbar = false draws none",
            "allowed:", out="cb.png"))
with open(path("cb.ini"), "w") as f:
    f.write("[pendulum]\nmass = 0.5\n[view]\ncolorbar_label = X\n")
r = run("render", "cb.ini", "--size", "160x90", "--fps", "10", "-o", "cb.mp4")
ok(*refused(r, "cb.ini:4: view.colorbar_label = 'X'", out="cb.mp4"))
r = run("still", "cb.ini", "--set", "view.colorbar=true", "--at", "1", "--size", "320x180",
        "-o", "cb2.png")
ok(r.returncode == 0, f"colorbar_label with view.colorbar = true: accepted ({err(r)[:120]})")
r = run("sweep", "cb.ini", "--vary", "initial.angle=10:20:2", "--measure", "lyapunov",
        "--time", "2", "-q", "-o", "cbs.png")
ok(r.returncode == 0, f"a sweep's map names its own colour bar: colorbar_label accepted there "
   f"({err(r)[:120]})")

r = run("sweep", chaotic, "--vary", "initial.angle=1:179:4", "--measure", "lyapunov", "--time",
        "2", "--energy", "1", "-o", "en.png", "--csv", "en.csv")
ok(*refused(r, "--energy 1:", "poincare", out="en.csv"))

for cam in ("35,25", "35,,25", "35,25,", ",35,25", "35, 25, 3"):
    r = run("still", swing, "--at", "3", "--size", "320x180", "--set", f"view.camera={cam}",
            "-o", "cam.png")
    ok(*refused(r, f"--set view.camera={cam}:", "blanks, not commas",
                "AZIMUTH ELEVATION [DISTANCE]", out="cam.png"))

with open(path("planar.ini"), "w") as f:
    f.write("[pendulum]\nmass = 0.5\n[view]\npanels = r, azimuth, top\n")
r = run("still", "planar.ini", "--at", "1", "-o", "pl.png")
ok(*refused(r, "planar.ini:4: view.panels holds azimuth and top", "planar",
            "allowed on a planar scene:", out="pl.png"))
r = run("still", default, "--at", "1", "--set", "view.panels=top", "-o", "pl.png")
ok(*refused(r, "--set view.panels: view.panels holds top,", out="pl.png"))
r = run("still", swing, "--at", "1", "--set", "initial.azimuth_rate=0", "-o", "pl.png")
ok(*refused(r, "swinging-spring.ini:27: view.panels holds azimuth and top",
            "at --set initial.azimuth_rate", out="pl.png"))
r = run("info", swing, "--set", "initial.azimuth_rate=0")
ok(r.returncode == 0, f"info draws no panels: the planar swinging spring is described ({err(r)[:100]})")
r = run("still", swing, "--at", "3", "--size", "320x180", "--set", "view.panels=azimuth,top",
        "-o", "pl3.png")
ok(r.returncode == 0, f"azimuth and top on the 3-D scene: accepted ({err(r)[:120]})")

# ---- 13: forged SVG character references ------------------------------------
r = run("still", default, "--at", "1", "--size", "160x90", "-q", "-o", "f.svg")
assert r.returncode == 0, err(r)
svg = open(path("f.svg"), encoding="utf-8").read()
mark = '<metadata id="springpend.scene-file">'
at = svg.index("\n", svg.index("\n", svg.index(mark)) + 1)  # end of the record's 2nd line
for ref in ("&#-1;", "&#x110000;", "&#4294967306;", "&#xD800;", "&# 65;", "&nbsp;"):
    with open(path("g.svg"), "w", encoding="utf-8") as f:
        f.write(svg[:at] + ref + svg[at:])
    r = run("scene", "g.svg")
    ok(*refused(r, f"g.svg: its scene record holds '{ref}'", "character reference",
                "U+0001..U+10FFFF"))
with open(path("g.svg"), "w", encoding="utf-8") as f:
    eq = svg.index("=", svg.index(mark) + len(mark))
    f.write(svg[:eq] + "&#61;" + svg[eq + 1:])  # '=' as a reference: the same text
r = run("scene", "g.svg")
ok(r.returncode == 0, f"a valid reference (&#61;) still reads ({err(r)[:120]})")

# ---- 14: --state units; merge names one field on both sides -----------------
r = run("still", swing, "--at", "3", "--size", "160x90", "-q", "-o", "st.png", "--state", "st.json")
units = json.load(open(path("st.json")))["units"] if r.returncode == 0 else {}
ok(units.get("z") == "m" and units.get("vz") == "m/s" and
   units.get("azimuth", "").startswith("degrees"),
   f"still --state of a 3-D scene: units of z, vz, azimuth given ({units})")
base = [chaotic, "--vary", "initial.angle=1:179:8", "--measure", "lyapunov", "--time", "2", "-q"]
r1 = run("sweep", *base, "--fast", "--shard", "1/2", "--csv", "p1.csv")
r2 = run("sweep", *base, "--shard", "2/2", "--csv", "p2.csv")
r = run("sweep", "--merge", "p1.csv", "p2.csv", "-o", "m.png")
ok(r1.returncode == 0 and r2.returncode == 0 and refused(r, "(p1.csv: kernel=fast; p2.csv: kernel=exact)",
                                                         out="m.png")[0],
   f"merge of a fast and an exact shard: names kernel on both sides ({err(r)[:200]})")

# ---- an MP4 whose metadata box FFmpeg would read whole -----------------------


def head(kind, size):
    return struct.pack(">I4s", 8 + size, kind)


def box(kind, payload):
    return head(kind, len(payload)) + payload


def forge_mp4(src_path, dst_path, text, pad=0):
    """src's boxes with moov's udta replaced by one holding the
    springpend.scene-file tag text (bytes) and pad bytes more, as springpend
    writes a tag (udta/meta/hdlr mdta, keys, ilst). The padding is written
    in pieces: the test itself never holds it (its memory would count in
    the child's peak)."""
    b = open(src_path, "rb").read()
    top, o = [], 0
    while o + 8 <= len(b):
        size, kind = struct.unpack(">I4s", b[o:o + 8])
        top.append((kind, b[o:o + size]))
        o += size
    moov = dict(top)[b"moov"]
    kids, o = [], 8
    while o < len(moov):
        size, kind = struct.unpack(">I4s", moov[o:o + 8])
        kids += [] if kind == b"udta" else [moov[o:o + size]]
        o += size
    kids = b"".join(kids)
    key = b"springpend.scene-file"
    keys = box(b"keys", struct.pack(">II", 0, 1) + struct.pack(">I", 8 + len(key)) + b"mdta" + key)
    hdlr = box(b"hdlr", struct.pack(">II", 0, 0) + b"mdta" + bytes(12) + b"\0")
    data_n = 8 + len(text) + pad                   # type, locale, the text
    item_n, ilst_n = 8 + data_n, 8 + 8 + data_n
    meta_n = 4 + len(hdlr) + len(keys) + 8 + ilst_n
    udta_n = 8 + meta_n
    with open(dst_path, "wb") as f:
        for kind, blob in top:
            if kind != b"moov":
                f.write(blob)
                continue
            f.write(head(b"moov", len(kids) + 8 + udta_n) + kids + head(b"udta", udta_n) +
                    head(b"meta", meta_n) + struct.pack(">I", 0) + hdlr + keys +
                    head(b"ilst", ilst_n) + head(struct.pack(">I", 1), item_n) +
                    head(b"data", data_n) + struct.pack(">II", 1, 0) + text)
            for _ in range(pad // (1 << 20)):
                f.write(b"#" * (1 << 20))
            f.write(b"#" * (pad % (1 << 20)))


def peak_kb(*args):
    """Runs springpend; (returncode, stderr, its peak resident memory in KiB)."""
    p = subprocess.Popen([exe, *args], cwd=work, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    e = p.stderr.read().decode(errors="replace")
    _, status, usage = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    return p.returncode, e.strip(), usage.ru_maxrss


r = run("render", default, "--size", "160x90", "--fps", "10", "--set", "video.duration=0.5",
        "-q", "-o", "v.mp4")
if r.returncode != 0:
    sptest.skip("forged MP4 tags", f"no MP4 here: {err(r)[:100]}")
else:
    text = run("scene", "v.mp4").stdout
    forge_mp4(path("v.mp4"), path("small.mp4"), text)
    rc, e, small_kb = peak_kb("scene", "small.mp4")
    ok(rc == 0 and text.startswith(b"[pendulum]"),
       f"an MP4 with the tag forged as springpend writes it: read ({e[:120]})")
    forge_mp4(path("v.mp4"), path("big.mp4"), text, 50_000_000)
    rc, e, big_kb = peak_kb("scene", "big.mp4")
    sptest.diag(f"peak memory: {small_kb} KiB for the small tag, {big_kb} KiB for 50 MB")
    ok(rc == 2 and "big.mp4: its metadata box udta holds 500" in e and "at most" in e
       and big_kb < small_kb + 20_000,
       f"scene on an MP4 whose tag is 50 MB: refused before FFmpeg reads it (exit {rc}, "
       f"{big_kb} KiB against {small_kb} KiB: {e[:200]})")
    rc, e, cmp_kb = peak_kb("compare", "big.mp4", "v.mp4")
    ok(rc == 2 and "its metadata box udta" in e and cmp_kb < small_kb + 20_000,
       f"compare on it: refused the same way (exit {rc}, {cmp_kb} KiB: {e[:200]})")

done()
