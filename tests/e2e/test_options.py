#!/usr/bin/env python3
"""springpend tests: every command-line option shown to change what it
should, not only the image size (an option parsed and then ignored passed a
test that looked at the size alone). render: -o, --format, --quality,
--frames, --shard, --gl, --size, --fps, --set, -q, -v; still: --at, --state,
--scale, --fps, --quality; data: --every, --poincare; sweep: --measure,
--time, --transient, --energy, --threads; compare: --max-diff, --max-pixels
(a count and a percentage), --metric rms --tol, --diff, --update, --report,
--junit, --json, -q. Expected values come from the option's documented
meaning: frames from k * speed / fps, pixels of the same frame rendered
otherwise, energies from the closed form, differences counted here.
usage: test_options.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import zlib

from sptest import diag, done, ok, runner, sets

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "options"))
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
run = runner(exe, work)
DEFAULT = os.path.join(src, "..", "scenes", "default.ini")
CHAOTIC = os.path.join(src, "..", "scenes", "chaotic.ini")
W, H = 96, 64
SMALL = sets({"video.width": W, "video.height": H, "video.duration": 1, "video.fps": 20})
FRAME = W * H * 4


def p(name):
    return os.path.join(work, name)


def err(r):
    return (r.stderr if isinstance(r.stderr, str) else r.stderr.decode(errors="replace")).strip()[-200:]


def raw(*args, scene=DEFAULT):
    """render's raw RGBA frames as a list of bytes objects, one per frame."""
    r = subprocess.run([exe, "render", scene, "--format", "raw", "-o", "-", "-q", *SMALL, *args],
                       capture_output=True, cwd=work)
    size = FRAME
    for i, a in enumerate(args):
        if a == "--size":
            w, h = args[i + 1].split("x")
            size = int(w) * int(h) * 4
    if r.returncode:
        diag(f"raw {args}: {err(r)}")
    return [r.stdout[i:i + size] for i in range(0, len(r.stdout), size)]


def probe(name):
    r = subprocess.run(["ffprobe", "-v", "error", "-select_streams", "v:0", "-count_frames",
                        "-show_entries", "stream=width,height,avg_frame_rate,nb_read_frames,codec_name",
                        "-of", "json", p(name)], capture_output=True, text=True)
    try:
        return json.loads(r.stdout)["streams"][0]
    except (ValueError, KeyError, IndexError):
        return {}


# ---- render --------------------------------------------------------------------
whole = raw()
ok(len(whole) == 20, f"render 1 s at 20 fps: 20 raw frames ({len(whole)})")
part = raw("--frames", "5:8")
ok(len(part) == 3 and part == whole[5:8], "--frames 5:8: frames 5, 6 and 7 of the whole render, "
   f"pixel for pixel ({len(part)} frames)")
shard = raw("--shard", "2/3")
ok(len(shard) == 7 and shard == whole[6:13],
   f"--shard 2/3 of 20 frames: frames 6..12, pixel for pixel ({len(shard)} frames)")
# without a trail (its length is in frames) and panels (their curves are
# sampled at frame times), of the 40 frames at 40 fps frame 10 is the one
# closest to frame 5 at 20 fps (t = 0.25 s; the camera's pre-pass samples
# frame times, so a few edge pixels may differ)
bare = ["--set", "view.trail=0", "--set", "view.panels=none", "--set", "view.hud=false"]
fps = raw("--fps", "40", *bare)
fps20 = raw(*bare)
def distance(a, b):
    return sum(abs(x - y) for x, y in zip(a, b))


near = min(range(len(fps)), key=lambda k: distance(fps[k], fps20[5])) if len(fps20) == 20 else -1
ok(len(fps) == 40 and near == 10, f"--fps 40: 40 frames ({len(fps)}), frame {near} closest to "
   "frame 5 at 20 fps (want 10)")
sized = raw("--size", "80x40")
ok(len(sized) == 20 and all(len(f) == 80 * 40 * 4 for f in sized), "--size 80x40: 80x40 frames")
light = raw("--set", "view.theme=light")
ok(len(light) == 20 and sum(light[0][0:4 * W:4]) > sum(whole[0][0:4 * W:4]) + 100 * W,
   "--set view.theme=light: a lighter top row")
magic = {"mp4": (4, b"ftyp"), "webm": (0, b"\x1a\x45\xdf\xa3"), "gif": (0, b"GIF89a"),
         "png": (0, b"\x89PNG")}
for kind, (at, sig) in magic.items():
    name = f"fmt-{kind}.bin" if kind != "png" else "fmt-png-%02d.bin"
    r = run("render", DEFAULT, "--format", kind, "-o", p(name), "-q", *SMALL, "--frames", "0:2")
    got = open(p(name.replace("%02d", "00")), "rb").read(16) if r.returncode == 0 else b""
    ok(got[at:at + len(sig)] == sig, f"--format {kind} on a .bin name writes {kind} ({got[:8]!r}) {err(r)}")
for q, (w, h, rate) in {"low": (854, 480, 15), "medium": (1280, 720, 30),
                        "high": (1920, 1080, 60)}.items():
    r = run("render", DEFAULT, "--quality", q, "--frames", "0:3", "-q", "-o", p(f"q-{q}.mp4"))
    st = probe(f"q-{q}.mp4") if r.returncode == 0 else {}
    ok((st.get("width"), st.get("height"), st.get("avg_frame_rate")) == (w, h, f"{rate}/1"),
       f"--quality {q}: {w}x{h} at {rate} fps ({st.get('width')}x{st.get('height')} at "
       f"{st.get('avg_frame_rate')}) {err(r)}")
r = run("render", DEFAULT, "-o", p("loud.mp4"), *SMALL)
rq = run("render", DEFAULT, "-o", p("quiet.mp4"), "-q", *SMALL)
rv = run("render", DEFAULT, "-o", p("verbose.mp4"), "-v", *SMALL)
# (a sanitizer build adds its own summary to stderr)
ok("wrote" in r.stderr and "wrote" not in rq.stderr and "springpend" not in rq.stderr and
   "stage times for 20 frames" in rv.stderr and "stage times" not in r.stderr,
   "-q: no 'wrote' line and no message; without it 'wrote'; -v: the stage times")
egl = raw("--gl", "egl")
if egl:
    # both Mesa here: the same goldens serve both (test_golden.c)
    ok(len(egl) == 20 and egl == raw("--gl", "osmesa"),
       "--gl egl and --gl osmesa render the 20 frames, the same pixels")

# ---- still ----------------------------------------------------------------------
r = run("still", DEFAULT, "--at", "0.35", "--state", p("s.json"), "-o", p("s.png"), "-q", *SMALL)
st = json.load(open(p("s.json"))) if r.returncode == 0 else {}
rd = run("data", DEFAULT, "-o", "-", "--every", "0.35", "--set", "video.duration=0.35")
lines = rd.stdout.strip().split("\n")
row = dict(zip(lines[0].split(","), map(float, lines[-1].split(","))))
ok(st.get("t") == 0.35 == row.get("t") and abs(st.get("x", 9) - row["x"]) < 1e-12 and
   abs(st.get("vy", 9) - row["vy"]) < 1e-12,
   f"still --at 0.35 --state: the state at t = 0.35 s, as data's row there ({st.get('t')})")


def still(name, *args):
    """still as raw pixels: render's frame 7 at 20 fps is t = 0.35 s; still
    writes PNG, so compare through render where the option is shared."""
    r = run("still", DEFAULT, "--at", "0.35", "-o", p(name), "-q", *SMALL, *args)
    return open(p(name), "rb").read() if r.returncode == 0 else b""


def png_size(data):
    return struct.unpack(">II", data[16:24]) if data[:8] == b"\x89PNG\r\n\x1a\n" else None


def png_rgba(data):
    """8-bit RGBA or RGB PNG (springpend's, not interlaced) to bytes of RGBA... rows, unfiltered."""
    w, h = png_size(data)
    ctype = data[25]
    idat, i = b"", 8
    while i < len(data):
        n, kind = struct.unpack(">I4s", data[i:i + 8])
        if kind == b"IDAT":
            idat += data[i + 8:i + 8 + n]
        i += 12 + n
    bpp = 4 if ctype == 6 else 3
    raw_ = zlib.decompress(idat)
    stride, prev, out = w * bpp, bytearray(w * bpp), bytearray()
    for y in range(h):
        f, line = raw_[y * (stride + 1)], bytearray(raw_[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b, c = prev[x], prev[x - bpp] if x >= bpp else 0
            pr = a + b - c
            line[x] = (line[x] + (0, a, b, (a + b) // 2,
                                  a if abs(pr - a) <= abs(pr - b) and abs(pr - a) <= abs(pr - c)
                                  else b if abs(pr - b) <= abs(pr - c) else c)[f]) & 255
        out += line
        prev = line
    return bytes(out), bpp


one, two = still("scale1.png"), still("scale2.png", "--scale", "2")
px1, px2 = (png_rgba(one)[0] if one else b""), (png_rgba(two)[0] if two else b"")
shades = [len({px[i:i + 4] for i in range(0, len(px), 4)}) for px in (px1, px2)]
ok(png_size(one) == png_size(two) == (W, H) and px1 != px2 and shades[1] > shades[0],
   f"still --scale 2: the same {W}x{H}, other pixels, more shades (averaged edges): "
   f"{shades[1]} against {shades[0]}")
r = run("still", DEFAULT, "--quality", "low", "-o", p("qlow.png"), "-q")
q = open(p("qlow.png"), "rb").read() if r.returncode == 0 else b""
ok(png_size(q) == (854, 480), f"still --quality low: 854x480 ({png_size(q)})")
t20, t5 = still("fps20.png", "--set", "view.trail=10"), still("fps5.png", "--set", "view.trail=10",
                                                                "--fps", "5")
ok(t20 and t5 and png_rgba(t20)[0] != png_rgba(t5)[0],
   "still --fps 5: a trail of 10 frames spans 2 s instead of 0.5 s (other pixels)")

# ---- data -----------------------------------------------------------------------
for every, dur, n in (("0.25", 1, 5), ("0.3", 1, 4), ("0.1", 0.7, 8)):
    r = run("data", DEFAULT, "-o", "-", "--every", every, "--set", f"video.duration={dur}")
    ts = [float(line.split(",")[0]) for line in r.stdout.strip().split("\n")[1:]]
    want = [k * float(every) for k in range(n)]
    ok(len(ts) == n and all(abs(a - b) < 1e-9 for a, b in zip(ts, want)),
       f"data --every {every} over {dur} s: t = 0, {every}, ... up to the duration inclusive "
       f"({len(ts)} rows, want {n})")
r = run("data", CHAOTIC, "-o", "-", "--poincare", "--set", "video.duration=20")
rows = [list(map(float, line.split(","))) for line in r.stdout.strip().split("\n")[1:]]
ok(len(rows) > 3 and all(row[3] > 0 for row in rows) and all(a[0] < b[0] for a, b in zip(rows, rows[1:])),
   f"data --poincare: crossings going forward (theta_dot > 0), in time order ({len(rows)})")

# ---- sweep ----------------------------------------------------------------------


def sweep_rows(name, *args):
    r = run("sweep", CHAOTIC, "--csv", p(name), "-o", p(name + ".png"), "-q", *args)
    if r.returncode:
        diag(f"{name}: {err(r)}")
        return "", []
    lines = open(p(name)).read().strip().split("\n")
    # the description is in the metadata beside the CSV (dc:description)
    described = " " + json.load(open(p(name) + "-metadata.json"))["dc:description"] + " "
    return described, [list(map(float, line.split(","))) for line in lines[1:]]


vary = ["--vary", "initial.length=1:1.2:3"]
h1, a = sweep_rows("t4.csv", "--measure", "lyapunov", "--time", "4", *vary)
h2, b = sweep_rows("t6.csv", "--measure", "lyapunov", "--time", "6", *vary)
h3, c = sweep_rows("tr.csv", "--measure", "lyapunov", "--time", "4", "--transient", "2", *vary)
h4, d = sweep_rows("th.csv", "--measure", "lyapunov", "--time", "4", "--threads", "1", *vary)
ok(" time=4 " in h1 and " time=6 " in h2 and a and b and a != b and a[0][3] != b[0][3],
   "sweep --time 6 measures another span than --time 4 (header and values)")
# with a transient of 2 s, lambda over [2, 6] s: the halves of --time 6 (over [0, 3]) differ
ok(" transient=2" in h3 and c and c != a, "sweep --transient 2: another lambda, said in the header")
ok(d == a, "sweep --threads 1: the same rows as on every core")
E = 2.5
h5, e = sweep_rows("en.csv", "--measure", "poincare", "--energy", str(E), "--time", "20",
                   "--vary", "initial.length=1.1:1.3:2")
m_, k_, L0, g = 1.0, 39.24, 0.75, 9.81  # chaotic.ini
with open(CHAOTIC) as f:
    for line in f:
        kv = [s.strip() for s in line.split("#")[0].split("=")]
        if len(kv) == 2 and kv[0] in ("mass", "stiffness", "natural_length", "gravity"):
            m_, k_, L0, g = (float(kv[1]) if kv[0] == n else v for n, v in
                             zip(("mass", "stiffness", "natural_length", "gravity"), (m_, k_, L0, g)))
worst = max((abs(0.5 * m_ * (rd ** 2 + r ** 2 * td ** 2) + 0.5 * k_ * (r - L0) ** 2 - m_ * g * r - E)
             for _, _, _, r, rd, td in e), default=math.inf)
ok(" energy=2.5 " in h5 and worst < 1e-4,
   f"sweep --energy 2.5: every section point at E = 1/2 m (r_dot^2 + r^2 theta_dot^2) + "
   f"1/2 k (r - L0)^2 - m g r = 2.5 J (worst {worst:.1e})")
_, o = sweep_rows("orb.csv", "--measure", "orbit", "--time", "20", *vary)
ok(o and len(o[0]) == 5 and o != a, "sweep --measure orbit: orbit rows (point, key, t, theta, r)")


# ---- compare --------------------------------------------------------------------
def write_png(name, w, h, pix):
    """An 8-bit RGB PNG from a function pix(x, y) -> (r, g, b)."""
    rows = b"".join(b"\0" + bytes(c for x in range(w) for c in pix(x, y)) for y in range(h))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    with open(p(name), "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))
    return p(name)


CW, CH = 640, 360  # 0.1% of the pixels: 230.4, so 230 may differ
base = write_png("e.png", CW, CH, lambda x, y: (x % 200, y % 256, 100))


def changed(name, n, delta):
    """base with the first n pixels (row by row) moved by delta levels in red."""
    return write_png(name, CW, CH, lambda x, y: (x % 200 + (delta if y * CW + x < n else 0),
                                                  y % 256, 100))


d5 = changed("d5.png", 1000, 5)
cases = [([d5], 1, "1000 pixels 5 levels off: default rule fails"),
         ([d5, "--max-diff", "5"], 0, "--max-diff 5 passes 5 levels"),
         ([d5, "--max-diff", "4"], 1, "--max-diff 4 fails 5 levels"),
         ([d5, "--max-pixels", "1000"], 0, "--max-pixels 1000 passes 1000 pixels"),
         ([d5, "--max-pixels", "999"], 1, "--max-pixels 999 fails 1000 pixels"),
         ([d5, "--max-pixels", "0.44%"], 0, "--max-pixels 0.44% (1013) passes 1000"),
         ([d5, "--max-pixels", "0.43%"], 1, "--max-pixels 0.43% (990) fails 1000"),
         ([changed("d230.png", 230, 9)], 0, "230 pixels off pass the default 0.1% (230.4)"),
         ([changed("d231.png", 231, 9)], 1, "231 pixels off fail the default 0.1% (230.4)")]
# RMS over RGB: 1000 pixels off by 20 in one channel of three
rms = math.sqrt(1000 * 20 ** 2 / (CW * CH * 3))
d20 = changed("d20.png", 1000, 20)
cases += [([d20, "--metric", "rms", "--tol", f"{rms * 1.02:.4f}"], 0, f"rms {rms:.3f} passes --tol {rms * 1.02:.3f}"),
          ([d20, "--metric", "rms", "--tol", f"{rms * 0.98:.4f}"], 1, f"rms {rms:.3f} fails --tol {rms * 0.98:.3f}")]
for args, want, what in cases:
    r = run("compare", base, *args)
    ok(r.returncode == want, f"compare: {what} (exit {r.returncode}, want {want}) {err(r)[:120]}")
r = run("compare", base, d5, "--diff", p("diff.png"))
dd = open(p("diff.png"), "rb").read() if os.path.exists(p("diff.png")) else b""
px, bpp = png_rgba(dd) if dd else (b"", 4)
magenta = sum(1 for i in range(0, len(px), bpp) if px[i] > 200 and px[i + 1] < 80 and px[i + 2] > 200)
ok(r.returncode == 1 and png_size(dd) == (CW, CH) and magenta == 1000,
   f"--diff: a diff image with the 1000 differing pixels in magenta ({magenta})")
os.makedirs(p("exp"), exist_ok=True)
os.makedirs(p("act"), exist_ok=True)
shutil.copy(base, p("exp/a.png"))
shutil.copy(d5, p("act/a.png"))
shutil.copy(base, p("exp/b.png"))
shutil.copy(base, p("act/b.png"))
r = run("compare", p("exp"), p("act"), "--json")
try:
    recs = {x["name"]: x["verdict"] for x in json.loads(r.stdout)["results"]}
except (ValueError, KeyError, TypeError):
    recs = None
ok(r.returncode == 1 and recs == {"a.png": "fail", "b.png": "pass"},
   f"--json: the records as JSON on stdout ({recs})")
r = run("compare", p("exp"), p("act"), "--junit", p("j.xml"), "--report", p("r.html"))
junit = open(p("j.xml")).read() if os.path.exists(p("j.xml")) else ""
html = open(p("r.html")).read() if os.path.exists(p("r.html")) else ""
ok("<testsuite" in junit and "a.png" in junit and "b.png" in junit and junit.count("<failure") == 1,
   "--junit: a test case per image, a.png's failed")
ok("<html" in html.lower() and "a.png" in html and "b.png" in html, "--report: an HTML page naming both")
r = run("compare", p("exp"), p("act"), "-q")
rl = run("compare", p("exp"), p("act"))
ok(r.returncode == rl.returncode == 1 and "b.png" not in r.stdout + r.stderr and
   "a.png" in r.stdout + r.stderr and "b.png" in rl.stdout + rl.stderr,
   "-q: failures only (a.png listed, the passing b.png not)")
shutil.copy(base, p("act/c.png"))
r = run("compare", p("exp"), p("act"), "--update=missing")
ok(os.path.exists(p("exp/c.png")) and open(p("exp/a.png"), "rb").read() == open(base, "rb").read(),
   "--update=missing: the new c.png added, the failing a.png kept")
r = run("compare", p("exp"), p("act"), "--update=changed")
ok(open(p("exp/a.png"), "rb").read() == open(d5, "rb").read(), "--update=changed: a.png replaced")

# compare.ini masks reach the image's edges: the last column and row differ
os.makedirs(p("mexp"), exist_ok=True)
os.makedirs(p("mact"), exist_ok=True)
shutil.copy(base, p("mexp/m.png"))
write_png("mact/m.png", CW, CH, lambda x, y: (x % 200 + (9 if x == CW - 1 or y == CH - 1 else 0),
                                              y % 256, 100))
for masks, want, what in (([], 1, "no mask: the last column and row (999 pixels) fail"),
                          ([f"{CW - 10}, 0, 10, {CH}", f"0, {CH - 4}, {CW}, 4"], 0,
                           "masks up to the right and bottom edges cover them"),
                          ([f"{CW - 10}, 0, 9, {CH}", f"0, {CH - 4}, {CW}, 4"], 1,
                           "a mask one column short of the edge leaves 360 pixels"),
                          ([f"{CW - 10}, 0, 500, {CH}", f"0, {CH - 4}, {CW}, 400"], 0,
                           "masks past the edges are clipped to them")):
    with open(p("mexp/compare.ini"), "w") as f:
        f.write("[m.png]\n" + "".join(f"mask = {m}\n" for m in masks))
    r = run("compare", p("mexp"), p("mact"))
    ok(r.returncode == want, f"compare.ini: {what} (exit {r.returncode}, want {want}) {err(r)[:100]}")

# data and info: --fps and --quality set the frame times (data samples at
# k * speed / fps; info counts round(length * fps) frames) and their --help
# says so; --gl, -v, and for info -o and -q, do nothing there and are
# refused, naming the commands that take them (attack12 #4: taken and
# ignored, --fps and --quality undocumented).
def csv_rows(*extra):
    r = run("data", DEFAULT, "--set", "video.duration=1", *extra, "-o", "-", "-q")
    return len([l for l in r.stdout.splitlines() if l and l[0].isdigit()])


rows = [csv_rows(), csv_rows("--fps", "30"), csv_rows("--quality", "low")]
helps = {c: run(c, "--help").stdout for c in ("data", "info")}
ok(rows == [60, 30, 15] and all("--fps" in h and "--quality" in h for h in helps.values()),
   f"data samples at the frame times --fps and --quality give (1 s: {rows}, want 60, 30, 15 at 60, "
   "30, 15 fps), and data's and info's --help name both")
for cmd, opt in (("data", ["--gl", "egl"]), ("data", ["-v"]), ("info", ["--gl", "egl"]),
                 ("info", ["-v"]), ("info", ["-o", "x.txt"]), ("info", ["-q"]),
                 ("still", ["-v"])):
    r = run(cmd, DEFAULT, "--set", "video.duration=0.1", *opt)
    ok(r.returncode == 2 and "is for 'springpend render" in err(r) and
       not os.path.exists(p("x.txt")),
       f"{cmd} {' '.join(opt)}: refused, naming who takes it (exit {r.returncode}: {err(r)[:110]})")

# getopt_long's three refusals told apart: a value given to an option that
# takes none, an ambiguous prefix, no such option (attack12 #7: all three
# were "unknown option").
for args, said in ((["sweep", CHAOTIC, "--merge=1"], "--merge takes no value"),
                   (["render", DEFAULT, "--quiet=1"], "--quiet takes no value"),
                   (["sweep", CHAOTIC, "--s", "x"], "ambiguous: --set, --shard or --size"),
                   (["compare", "a.png", "b.png", "--re", "x"],
                    "ambiguous: --report or --report-failures-only"),
                   (["scene", "a.png", "--bogus"], "unknown option '--bogus'")):
    r = run(*args)
    ok(r.returncode == 2 and said in err(r), f"{' '.join(args[:1] + args[2:])}: says {said!r} "
       f"({err(r)[:120]})")
done()
