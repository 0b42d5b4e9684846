#!/usr/bin/env python3
"""springpend tests: documented orders and formats, each asserted as written.
data's CSV headers as the manual lists them (doc/integrators.md, doc/sweeps.md);
sweep's CSV columns as doc/sweeps.md's table and src/sweep/sweep.h give them, rows in the grid's order
(the first axis varies fastest) and lyapunov_half equal to lambda over T/2;
every range check of `sweep --merge` (exit 2, FILE:LINE, nothing written);
FILE:LINE with LF, CRLF and CR line ends;
.part files created with O_EXCL: with the random part of the name forced
(fixed_suffix.so: a fixed pid and clock), a symlink or a file already at the
would-be .part name is left alone and the run writes a new name, and two runs
at once to the same target both complete.
usage: test_formats.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR FIXED_SUFFIX_SO   (TAP)"""
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys

from sptest import diag, done, manual, ok, runner

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "formats"))
shim = os.path.abspath(sys.argv[4])
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
run = runner(exe, work)
readme = manual(os.path.join(src, ".."))   # README.md and doc/*.md
CHAOTIC = os.path.join(src, "..", "scenes", "chaotic.ini")
DEFAULT = os.path.join(src, "..", "scenes", "default.ini")


def err(r):
    return r.stderr.strip()[-300:]


def path(name):
    return os.path.join(work, name)


def read(name):
    with open(path(name)) as f:
        return f.read()


# ---- data's headers, as the manual writes them -----------------------------
m = re.search(r"`springpend data SCENE -o - \[--every S\]` writes\n`([^`]+)`", readme)
want = m.group(1) if m else "(not found in the manual)"
r = run("data", DEFAULT, "-o", "-", "--set", "video.duration=0.1")
ok(r.stdout.split("\n")[0] == want, f"data's header is the manual's: {want}")
m = re.search(r"`--poincare` writes the Poincaré\nsection instead, `([^`]+)`", readme)
want = m.group(1) if m else "(not found in the manual)"
r = run("data", CHAOTIC, "-o", "-", "--poincare", "--set", "video.duration=5")
ok(r.stdout.split("\n")[0] == want, f"data --poincare's header is the manual's: {want}")
m = re.search(r"writes the members \(`([^`]+)`", readme)
want = (m.group(1) if m else "(not found)").replace("KEY", "initial.length")
r = run("data", DEFAULT, "-o", "-", "--set", "video.duration=0.1", "--set", "ensemble.count=3",
        "--set", "ensemble.key=initial.length", "--set", "ensemble.spread=0.1")
ok(r.stdout.split("\n")[0] == want, f"data's ensemble header is the manual's: {want}")

# ---- sweep: columns from doc/sweeps.md's table, rows in the grid's order -------
table = dict(re.findall(r"^\| `(lyapunov|orbit|poincare)` \|[^|]*\| `([^`]+)`", readme, re.M))
A = ("initial.angle", [10, 20, 30])
L = ("initial.length", [1.0, 1.1, 1.2])


def sweep(name, measure, axes, *extra):
    """Runs a sweep into name.csv; returns (exit, header line 2, rows as lists of floats)."""
    vary = [a for key, v in axes for a in ("--vary", f"{key}={v[0]}:{v[-1]}:{len(v)}")]
    r = run("sweep", CHAOTIC, "--measure", measure, *vary, "--csv", path(name + ".csv"), "-q",
            *extra)
    if r.returncode:
        diag(f"{name}: {err(r)}")
        return r.returncode, "", []
    lines = read(name + ".csv").strip().split("\n")
    return 0, lines[0], [[float(v) for v in line.split(",")] for line in lines[1:]]


def columns(measure, keys):
    c = table.get(measure, "?")
    c = c.replace("KEY[,KEY2]", ",".join(keys)).replace("KEY", keys[0])
    return c


rc, head, rows = sweep("lyap2", "lyapunov", [A, L], "--time", "4", "-o", path("lyap2.png"))
ok(rc == 0 and head == columns("lyapunov", [A[0], L[0]]),
   f"lyapunov over two keys: columns {head!r} as doc/sweeps.md's table")
grid = [(p, a, l) for p, (l, a) in enumerate((l, a) for l in L[1] for a in A[1])]
got = [(int(r[0]), r[1], r[2]) for r in rows]
ok(got == grid, "rows in the grid's order, the first axis (initial.angle) varying fastest "
   f"(sweep.h): {got[:4]} ...")
# lyapunov_half is lambda at T/2: the same run over T/2 gives it
rc2, _, half = sweep("lyap2h", "lyapunov", [A, L], "--time", "2", "-o", path("lyap2h.png"))
ok(rc2 == 0 and len(half) == len(rows) and
   all(abs(h[3] - r[4]) <= 1e-8 * abs(h[3]) for h, r in zip(half, rows)),
   "lyapunov_half of a run over T = 4 s equals lyapunov over T = 2 s, point by point")
rc, head, rows = sweep("orbit", "orbit", [A], "--time", "20", "-o", path("orbit.png"))
ok(rc == 0 and head == columns("orbit", [A[0]]) and rows and
   all(int(a[0]) <= int(b[0]) and (a[0] < b[0] or a[2] < b[2]) for a, b in zip(rows, rows[1:])) and
   {int(r[0]) for r in rows} <= {0, 1, 2} and all(r[1] == A[1][int(r[0])] for r in rows),
   f"orbit: columns {head!r}; rows by point, then by t; KEY the point's value")
rc, head, rows = sweep("poinc", "poincare", [L], "--time", "20", "-o", path("poinc.png"))
ok(rc == 0 and head == columns("poincare", [L[0]]) and rows and
   all(int(a[0]) <= int(b[0]) and (a[0] < b[0] or a[2] < b[2]) for a, b in zip(rows, rows[1:])),
   f"poincare: columns {head!r}; rows by point, then by t")

# ---- sweep --merge: every range check ---------------------------------------
vary = ["--measure", "lyapunov", "--vary", "initial.angle=10:30:3", "--vary", "initial.length=1:1.2:2"]
for i in (1, 2):
    r = run("sweep", CHAOTIC, *vary, "--time", "2", "--shard", f"{i}/2", "--csv",
            path(f"s{i}.csv"), "-q")
r3 = run("sweep", CHAOTIC, *vary, "--time", "2", "--shard", "1/3", "--csv", path("t1.csv"), "-q")
ro = run("sweep", CHAOTIC, *vary, "--time", "3", "--shard", "2/2", "--csv", path("o2.csv"), "-q")
good = run("sweep", "--merge", path("s1.csv"), path("s2.csv"), "-o", path("good.png"), "-q")
ok(r.returncode == r3.returncode == ro.returncode == good.returncode == 0,
   f"shards 1/2, 2/2, 1/3 and another sweep's 2/2 written, and 1/2 + 2/2 merge {err(good)}")
s1, s2 = read("s1.csv").split("\n"), read("s2.csv").split("\n")


def edited(name, lines, like="s2.csv", position=None):
    """name: the CSV lines, beside it the metadata of shard `like` with its row
    count and SHA-256 made to match (so that the row checks alone refuse)."""
    text = "\n".join(lines)
    with open(path(name), "w") as f:
        f.write(text)
    meta = json.loads(read(like + "-metadata.json"))
    meta["dc:extent"] = len(text.splitlines()) - 1
    meta["schema:sha256"] = hashlib.sha256(text.encode()).hexdigest()
    if position:
        meta["schema:position"] = position
    with open(path(name + "-metadata.json"), "w") as f:
        json.dump(meta, f)
    return path(name)


def row_point(lines, i, point):
    """lines with data row i (0-based after the header line) given point `point`."""
    out = list(lines)
    out[1 + i] = str(point) + out[1 + i][out[1 + i].index(","):]
    return out


cases = [
    ("shard 0/2", [edited("z.csv", s1, "s1.csv", "0/2"), path("s2.csv")]),
    ("shard 3/2", [path("s1.csv"), edited("z.csv", s2, "s2.csv", "3/2")]),
    ("shard 1/2 twice", [path("s1.csv"), path("s1.csv")]),
    ("one file of two", [path("s1.csv")]),
    ("three files of two", [path("s1.csv"), path("s2.csv"), path("s2.csv")]),
    ("shard 1/3 with 2/2", [path("t1.csv"), path("s2.csv")]),
    ("another sweep's shard (T = 3 s)", [path("s1.csv"), path("o2.csv")]),
    ("other column names", [path("s1.csv"),
                            edited("cols.csv", [s2[0].replace("lyapunov_half", "half")] + s2[1:])]),
    ("a point before the shard's first (2 in 3..5)",
     [path("s1.csv"), edited("before.csv", row_point(s2, 0, 2))]),
    ("the next shard's first point (3 in 0..2)",
     [edited("next.csv", row_point(s1, 2, 3), "s1.csv"), path("s2.csv")]),
    ("a point past the grid (6 of 6)", [path("s1.csv"), edited("past.csv", row_point(s2, 2, 6))]),
    ("a negative point", [edited("neg.csv", row_point(s1, 0, -1), "s1.csv"), path("s2.csv")]),
    ("points out of order", [path("s1.csv"), edited("order.csv", s2[:1] + [s2[2], s2[1], s2[3], ""])]),
    ("a row short of a number", [path("s1.csv"),
                                 edited("short.csv", s2[:2] + [s2[2].rsplit(",", 1)[0]] + s2[3:])]),
    ("a row with a number more", [path("s1.csv"), edited("long.csv", s2[:2] + [s2[2] + ",1"] + s2[3:])]),
    ("a row missing", [path("s1.csv"), edited("missing.csv", s2[:2] + s2[3:])]),
    ("a row repeated", [path("s1.csv"), edited("repeated.csv", s2[:3] + [s2[2]] + s2[3:])]),
    ("cut inside a row", [path("s1.csv"), edited("cut.csv", s2[:3] + [s2[3][:8]])]),
    ("a comment line", [path("s1.csv"), edited("comment.csv", ["# springpend"] + s2)]),
    ("no metadata beside it", [path("s1.csv"), edited("nometa.csv", s2)]),
]
os.remove(path("nometa.csv-metadata.json"))
for what, parts in cases:
    for f in ("m.png", "m.csv"):
        if os.path.exists(path(f)):
            os.remove(path(f))
    r = run("sweep", "--merge", *parts, "-o", path("m.png"), "--csv", path("m.csv"), "-q")
    named = any(os.path.basename(p) in r.stderr for p in parts) or "files were given" in r.stderr
    ok(r.returncode == 2 and not os.path.exists(path("m.png")) and not os.path.exists(path("m.csv"))
       and named, f"--merge refuses {what}: exit 2, the file named, nothing written "
       f"({r.returncode}: {err(r)[:160]})")

# ---- FILE:LINE counts lines as a reader does, whatever ends them ----------
lines = ["# a scene", "[pendulum]", "mass = 1", "", "stiffness = -2", "[video]", "fps = 0x1e"]
for what, end in (("LF", "\n"), ("CRLF", "\r\n"), ("CR", "\r")):
    with open(path(f"eol-{what}.ini"), "w", newline="") as f:
        f.write(end.join(lines) + end)
    r = run("data", path(f"eol-{what}.ini"), "-o", path("eol.csv"))
    ok(r.returncode == 2 and f"eol-{what}.ini:5: pendulum.stiffness" in r.stderr and
       f"eol-{what}.ini:7: video.fps" in r.stderr and not os.path.exists(path("eol.csv")),
       f"a scene with {what} line ends: its errors at lines 5 and 7 ({err(r)[:160]})")

# ---- .part files with O_EXCL, the random name forced -------------------------
env = dict(os.environ, LD_PRELOAD=shim, SP_OPEN_LOG=path("open.log"),
           ASAN_OPTIONS=os.environ.get("ASAN_OPTIONS", "") + ":verify_asan_link_order=0")


def forced(*args):
    if os.path.exists(path("open.log")):
        os.remove(path("open.log"))
    r = subprocess.run([exe, *args], capture_output=True, text=True, cwd=work, env=env)
    log = read("open.log").split("\n") if os.path.exists(path("open.log")) else []
    return r, [line.rsplit(" ", 1)[0] for line in log if line]


still = ["still", DEFAULT, "--size", "64x48", "-q", "-o"]
r, names = forced(*still, path("a.png"))
ok(r.returncode == 0 and names and names[0].startswith(path("a.png.")),
   f"a still through a .part ({names[:1]}) {err(r)}")
first = names[0] if names else path("a.png.none.part")
r2, names2 = forced(*still, path("a.png"))
ok(names2[:1] == [first], "the forced random part repeats: the same .part name again")
with open(path("victim.txt"), "w") as f:
    f.write("keep me\n")
os.remove(path("a.png"))
os.symlink(path("victim.txt"), first)
r, names = forced(*still, path("a.png"))
png = open(path("a.png"), "rb").read(8) if os.path.exists(path("a.png")) else b""
ok(r.returncode == 0 and open(path("victim.txt"), "rb").read() == b"keep me\n" and
   os.path.islink(first) and
   png == b"\x89PNG\r\n\x1a\n" and len(names) >= 2 and names[0] == first and names[1] != first,
   f"a symlink at the would-be .part name: not written through, left alone, another name "
   f"taken, the PNG written ({names[:2]}) {err(r)}")
if os.path.lexists(first):
    os.remove(first)
with open(first, "w") as f:
    f.write("someone else's part\n")
r, names = forced(*still, path("a.png"))
ok(r.returncode == 0 and open(first, "rb").read() == b"someone else's part\n" and
   open(path("a.png"), "rb").read(8) == b"\x89PNG\r\n\x1a\n",
   f"a file at the would-be .part name: left as it was, the PNG written {err(r)}")
if os.path.lexists(first):
    os.remove(first)
# two runs at once, the same target, the same forced names
vid = ["render", DEFAULT, "--size", "160x96", "--set", "video.duration=2", "--fps", "30", "-q",
       "-o", path("both.mp4")]
ps = [subprocess.Popen([exe, *vid], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, cwd=work,
                       env=env) for _ in range(2)]
codes = [p.wait(timeout=120) for p in ps]
probe = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0",
                        "-show_entries", "stream=nb_read_frames", "-of", "csv=p=0", path("both.mp4")],
                       capture_output=True, text=True) if shutil.which("ffprobe") else None
frames = probe.stdout.strip() if probe else "60"
ok(codes == [0, 0] and frames == "60" and not [f for f in os.listdir(work) if f.startswith("both.mp4.")],
   f"two renders at once with the same forced .part names: both exit 0, the MP4 whole "
   f"({frames} of 60 frames), no .part left")
done()
