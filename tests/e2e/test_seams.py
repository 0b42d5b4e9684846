#!/usr/bin/env python3
"""springpend tests: defects found where the merged pieces meet (safety's
outfile, the sweep's figures, still's vector figures, compare's CI outputs).
Device-node cases need root and are skipped without it.
usage: test_review.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import os
import re
import resource
import shutil
import signal
import stat
import subprocess
import time
import xml.dom.minidom

from sptest import done, err, manual, ok, runner_bytes, setup, wait_caught

exe, src, work, _ = setup("review", [])
default = os.path.join(src, "..", "scenes", "default.ini")
root = os.geteuid() == 0
SWEEP = ["sweep", default, "--vary", "initial.angle=5:40:4", "--measure", "lyapunov",
         "--time", "2", "--threads", "1", "-q"]


run = runner_bytes(exe, work)


def path(*names):
    return os.path.join(work, *names)


# ---- a sweep's figure to a full device: the write error is not lost ----
# cairo 1.16's own file stream dropped the ENOSPC of a small PDF: exit 0 and
# "wrote" with nothing written.
for ext in ("pdf", "svg", "png"):
    full = path(f"full.{ext}")
    if not root:
        ok(True, f"sweep -o a full device (.{ext}) fails", skip="mknod needs root")
        continue
    os.mknod(full, 0o666 | stat.S_IFCHR, os.makedev(1, 7))
    r = run(*SWEEP, "-o", full)
    ok(r.returncode == 1 and "No space left" in err(r),
       f"sweep -o a full device (.{ext}) exits 1 naming the cause: {r.returncode} {err(r)}")
    ok(stat.S_ISCHR(os.stat(full).st_mode), f"the device full.{ext} is still a device")

# ---- a sweep never replaces what it reads ----
# --csv (or -o) naming the scene, or one of --merge's shards, replaced it with
# the sweep's rows: exit 0 and the input gone.
with open(default) as f:
    scene_text = f.read()
scene = path("s.ini")
with open(scene, "w") as f:
    f.write(scene_text)
r = run(*[scene if a == default else a for a in SWEEP], "-o", path("m.png"), "--csv", scene)
with open(scene) as f:
    ok(r.returncode == 2 and "would overwrite an input" in err(r) and f.read() == scene_text,
       f"sweep --csv SCENE is refused, the scene intact: {r.returncode} {err(r)}")
base = [a for a in SWEEP if a != "-q"] + ["-q"]
for i in (1, 2):
    r = run(*base, "--shard", f"{i}/2", "--csv", path(f"part{i}.csv"))
    ok(r.returncode == 0, f"shard {i}/2 written: {err(r)}")
with open(path("part1.csv"), "rb") as f:
    part1 = f.read()
r = run("sweep", "--merge", path("part1.csv"), path("part2.csv"), "-o", path("m.png"),
        "--csv", path("part1.csv"), "-q")
with open(path("part1.csv"), "rb") as f:
    ok(r.returncode == 2 and "would overwrite an input" in err(r) and f.read() == part1,
       f"sweep --merge ... --csv PART is refused, the shard intact: {r.returncode} {err(r)}")
r = run("sweep", "--merge", path("part1.csv"), path("part2.csv"), "-o", path("m.png"),
        "--csv", path("whole.csv"), "-q")
ok(r.returncode == 0 and os.path.getsize(path("whole.csv")) > 0,
   f"sweep --merge to other paths still works: {r.returncode} {err(r)}")

# ---- a vector figure cut short by `ulimit -f` is an error, not a file ----
# cairo 1.16's own file stream lost the EFBIG of a PDF's last write: `still
# -o fig.pdf` printed "wrote", exited 0 and left an 8 KiB, truncated PDF.
def fsize_limit():
    resource.setrlimit(resource.RLIMIT_FSIZE, (8192, 8192))


os.makedirs(path("limited"))
for ext in ("pdf", "svg"):
    target = path("limited", f"still.{ext}")
    r = run("still", default, "-o", target, preexec_fn=fsize_limit)
    ok(r.returncode == 1 and "File too large" in err(r) and not os.path.exists(target),
       f"still -o .{ext} over ulimit -f: exit 1, no file: {r.returncode} {err(r)}")
    target = path("limited", f"sweep.{ext}")
    r = run(*SWEEP[:3], "initial.angle=5:40:40", *SWEEP[4:], "-o", target,
            preexec_fn=fsize_limit)
    ok(r.returncode == 1 and "File too large" in err(r) and not os.path.exists(target),
       f"sweep -o .{ext} over ulimit -f: exit 1, no file: {r.returncode} {err(r)}")
ok(not os.listdir(path("limited")), f"no .part left: {os.listdir(path('limited'))}")

# ---- a signal while a sweep draws its figure writes nothing ----
# The help promises "Ctrl-C stops and writes nothing (exit 130)"; a signal
# after the integration (while drawing, or during --merge) was swallowed: the
# figure and --csv were written, exit 0. The figure goes to a FIFO whose
# reader takes one byte, then the signal is sent, then the rest is read: the
# signal surely arrives while the figure is being written (it is far larger
# than a pipe's buffer).
parametric = os.path.join(src, "..", "scenes", "parametric.ini")
r = run("sweep", parametric, "--vary", "pivot.amplitude=0:0.06:60", "--measure", "orbit",
        "--time", "30", "-q", "--shard", "1/1", "--csv", path("orbit.csv"))
ok(r.returncode == 0, f"an orbit shard to merge: {err(r)}")
for sig, name in ((signal.SIGTERM, "SIGTERM"), (signal.SIGINT, "SIGINT")):
    fifo = path(f"fig-{name}.svg")
    os.mkfifo(fifo)
    p = subprocess.Popen([exe, "sweep", "--merge", path("orbit.csv"), "-o", fifo,
                          "--csv", path(f"whole-{name}.csv"), "-q"], cwd=work,
                         stderr=subprocess.PIPE)
    with open(fifo, "rb") as f:
        first = f.read(1)
        p.send_signal(sig)
        rest = f.read()
    p.wait(timeout=60)
    e = p.stderr.read().decode(errors="replace").strip()
    ok(first and p.returncode == 128 + sig and "interrupted" in e,
       f"{name} during sweep --merge's figure: exit {p.returncode}, {e!r}")
    ok(not os.path.exists(path(f"whole-{name}.csv")),
       f"{name} during the figure: no --csv written")
    ok(not [n for n in os.listdir(work) if n.endswith(".part")], "no .part left")

# ---- a signal while `still` writes an SVG or PDF writes nothing ----
# doc/outputs.md: still "stops at once and writes nothing"; a signal after the
# integration, while the figure was drawn, was swallowed (exit 0, "wrote").
chaotic = os.path.join(src, "..", "scenes", "chaotic.ini")
for ext, sig in (("svg", signal.SIGTERM), ("pdf", signal.SIGINT)):
    fifo = path(f"still-{ext}.fifo.{ext}")
    os.mkfifo(fifo)
    p = subprocess.Popen([exe, "still", chaotic, "--at", "30", "--size", "320x240", "--set",
                          "view.trail=all", "-o", fifo], cwd=work, stderr=subprocess.PIPE)
    with open(fifo, "rb") as f:
        first = f.read(1)
        p.send_signal(sig)
        rest = f.read()
    p.wait(timeout=60)
    e = p.stderr.read().decode(errors="replace").strip()
    ok(first and p.returncode == 128 + sig and "interrupted" in e and "wrote" not in e,
       f"signal {int(sig)} during still -o .{ext}: exit {p.returncode}, {e!r}")

# ---- every option the manual's commands use is in that command's --help ----
# `still ... -q` (snapshots.sh) and `still --fps 30` ran but still's --help
# did not list them; the top-level help called still "one frame as a PNG".
readme = manual(os.path.join(src, ".."))   # README.md and doc/*.md
blocks = "\n".join(re.findall(r"^```(?:sh|yaml)?\n(.*?)^```", re.sub(
    r"^```(?!sh\n|yaml\n|\n).*?^```\n", "", readme, flags=re.S | re.M), re.S | re.M))
blocks = blocks.replace("\\\n", " ")
used = {}
for line in blocks.splitlines():
    for m in re.finditer(r"springpend (render|still|data|info|compare|sweep)\b([^|#;&]*)", line):
        for opt in re.findall(r"(?<![\w-])(--?[a-zA-Z][\w-]*)", m.group(2)):
            used.setdefault(m.group(1), set()).add(opt.split("=")[0])
for cmd in sorted(used):
    h = run(cmd, "--help").stdout.decode()
    missing = sorted(o for o in used[cmd] if not re.search(r"(?<![\w-])" + re.escape(o) + r"\b", h))
    ok(not missing, f"{cmd} --help lists every option the manual uses with it: missing {missing}")
top = run("--help").stdout.decode()
ok(re.search(r"still .*SVG", top), "springpend --help says still writes SVG and PDF too")

# ---- doc/ci.md's worked CI example runs as written ----
# Its JSON check read snapshots/default_t3.json, which no step put there
# (--update copies PNGs only): FileNotFoundError on the first run.
def block(marker):
    for b in re.findall(r"^```[a-z]*\n(.*?)^```", readme, re.S | re.M):
        if marker in b:
            return b
    return ""


ci = path("ci")
os.makedirs(path("ci", "bin"))
os.symlink(exe, path("ci", "bin", "springpend"))
os.symlink(os.path.join(src, "..", "scenes"), path("ci", "scenes"))
with open(path("ci", "snapshots.sh"), "w") as f:
    f.write(block("# snapshots.sh OUTDIR"))
env = dict(os.environ, PATH=path("ci", "bin") + os.pathsep + os.environ["PATH"])
steps = ["sh snapshots.sh actual",
         *[l for l in block("--update=missing").splitlines() if not l.startswith("git ")],
         block('json.load(open(d + "/default_t3.json"))')]
for step in steps:
    r = subprocess.run(step, shell=True, cwd=ci, env=env, capture_output=True, timeout=120)
    ok(step.strip() and r.returncode == 0,
       f"doc/ci.md worked example: {step.strip()[:60]!r} exits 0: {r.returncode} {err(r)[-300:]}")

# ---- --merge refuses a shard cut short or edited ----
# A shard truncated in copying (its last row cut mid-number), missing a row,
# or with a row that is not numbers, was merged and drawn, exit 0.
with open(path("part2.csv")) as f:
    p2 = f.read()
bad = {"cut": p2[:-7], "row-missing": "".join(p2.splitlines(True)[:1] + p2.splitlines(True)[2:]),
       "not-numbers": p2.replace(p2.splitlines()[-1], p2.splitlines()[-1].rsplit(",", 1)[0] + ",x"),
       "columns": p2.replace("lyapunov_half", "other")}
for what, text in bad.items():
    with open(path(f"bad-{what}.csv"), "w") as f:
        f.write(text)
    shutil.copy(path("part2.csv-metadata.json"), path(f"bad-{what}.csv-metadata.json"))
    r = run("sweep", "--merge", path("part1.csv"), path(f"bad-{what}.csv"), "-o",
            path(f"bad-{what}.png"), "-q")
    ok(r.returncode == 2 and not os.path.exists(path(f"bad-{what}.png")),
       f"sweep --merge with a shard {what}: exit 2, no figure: {r.returncode} {err(r)}")
with open(path("orbit.csv")) as f:
    orbit = f.read()
with open(path("orbit-cut.csv"), "w") as f:
    f.write(orbit[:len(orbit) // 2])
shutil.copy(path("orbit.csv-metadata.json"), path("orbit-cut.csv-metadata.json"))
r = run("sweep", "--merge", path("orbit-cut.csv"), "-o", path("orbit-cut.png"), "-q")
ok(r.returncode == 2 and "cut short" in err(r),
   f"sweep --merge of an orbit shard cut in half: exit 2: {r.returncode} {err(r)}")

# ---- sweep --csv to a stream says why it is refused ----
# The refusal said "CSV can be written through one" (outfile's message for
# data -o -) while refusing the CSV; --help called the CSV "streamed".
r = run(*SWEEP, "-o", path("s.png"), "--csv", "-")
ok(r.returncode == 2 and "can be written through" not in err(r) and "regular file" in err(r),
   f"sweep --csv - is refused with a message that fits: {r.returncode} {err(r)}")

# ---- a Poincare mosaic no point can draw is refused ----
# --energy below every grid point's reach skipped all of them and wrote an
# empty figure, exit 0.
r = run("sweep", chaotic, "--set", "initial.angle=0", "--vary", "initial.length=0.4:1.8:4",
        "--measure", "poincare", "--energy", "-1e300", "--time", "5", "-q", "-o", path("empty.png"))
ok(r.returncode == 2 and not os.path.exists(path("empty.png")),
   f"sweep --measure poincare with an energy no point has: exit 2, no figure: {r.returncode} {err(r)}")
r = run("sweep", chaotic, "--set", "initial.angle=0", "--vary", "initial.length=0.4:1.8:4",
        "--measure", "poincare", "--energy", "-1e300", "--time", "5", "-q", "--shard", "1/2",
        "--csv", path("empty-shard.csv"))
ok(r.returncode == 0, f"...but a shard may hold no reachable point (others may): {r.returncode} {err(r)}")

# ---- scene names that are not one plain word ----
# A sweep of "my scene.ini" computed every point, then failed "not a sweep
# CSV" (the name split the CSV header); a name that is not UTF-8, or is cut
# mid-character at 63 bytes, failed the figure ("input string not valid
# UTF-8", exit 1), and so did `still -o fig.pdf` (the PDF's title).
names = {"space": b"my scene.ini", "latin1": b"donn\xe9es.ini",
         "long-utf8": ("\u00e4" * 40 + ".ini").encode()}
for what, name in names.items():
    scene_path = os.path.join(os.fsencode(work), name)
    with open(scene_path, "w") as f:
        f.write(scene_text)
    for ext in ("png", "pdf"):
        r = run(*[scene_path if a == default else a for a in SWEEP], "-o", path(f"n-{what}.{ext}"),
                "--csv", path(f"n-{what}.csv"))
        ok(r.returncode == 0 and os.path.getsize(path(f"n-{what}.{ext}")) > 0,
           f"sweep of a scene named {what}, -o .{ext}: {r.returncode} {err(r)}")
    r = run("still", scene_path, "--size", "160x120", "-o", path(f"n-{what}-still.pdf"), "-q")
    ok(r.returncode == 0, f"still -o .pdf of a scene named {what}: {r.returncode} {err(r)}")

# ---- JSON and JUnit stay valid UTF-8 whatever the file names ----
# `info --json` of a scene named donn\xe9es.ini (Latin-1) and compare's --json
# and --junit for such an image wrote the raw byte: not JSON, not XML.
latin1 = os.path.join(os.fsencode(work), b"donn\xe9es.ini")
r = run("info", latin1, "--json")
try:
    scene_name = json.loads(r.stdout)["scene"]
except ValueError as e:
    scene_name = f"invalid: {e}"
ok(r.returncode == 0 and scene_name.startswith("donn"),
   f"info --json of a Latin-1 file name is valid JSON: {scene_name!r}")
for side in ("exp", "act"):
    os.makedirs(path(side))
    r = run("still", default, "--size", "64x48", "--at", "0" if side == "exp" else "1", "-q",
            "-o", os.path.join(os.fsencode(path(side)), b"fig\xfe.png"))
r = run("compare", path("exp"), path("act"), "--json", "--junit", path("j.xml"))
try:
    names = [x["name"] for x in json.loads(r.stdout)["results"]]
except ValueError as e:
    names = [f"invalid: {e}"]
ok(r.returncode == 1 and names and names[0].endswith(".png"),
   f"compare --json with a non-UTF-8 file name is valid JSON: {names}")
try:
    xml.dom.minidom.parse(path("j.xml"))
    junit = "valid"
except Exception as e:
    junit = f"invalid: {e}"
ok(junit == "valid", f"compare --junit with a non-UTF-8 file name is valid XML: {junit}")

# ---- keys refuses what it does not take ----
# `springpend keys --bogus` (or a scene: `keys scene.ini`) printed the table, exit 0.
for extra in ("--bogus", default):
    r = run("keys", extra)
    ok(r.returncode == 2 and not r.stdout, f"keys {os.path.basename(extra)}: exit 2: {r.returncode} {err(r)}")
r = run("keys")
ok(r.returncode == 0 and b"font_scale" in r.stdout, "keys alone still lists the keys")

# ---- render's options are refused where they would do nothing ----
# `still --format raw -o -` wrote a PNG to stdout; still --shard / --frames
# and data --format were taken and ignored, exit 0.
for args in (["still", "--format", "raw", "-o", "-"], ["still", "--shard", "1/2", "-o", path("x.png")],
             ["still", "--frames", "0:1", "-o", path("x.png")], ["data", "--format", "raw", "-o", path("x.csv")]):
    r = run(args[0], default, "--size", "64x48", "-q", *args[1:])
    ok(r.returncode == 2 and "is for 'springpend render'" in err(r) and not r.stdout,
       f"{' '.join(args[:3])}: exit 2: {r.returncode} {err(r)}")

# ---- a failed sweep removes the folders it made ----
# doc/outputs.md: a failed run removes "the folders it created when they are left
# empty"; a sweep's figure failing (here over ulimit -f) left them.
r = run(*SWEEP[:3], "initial.angle=5:40:40", *SWEEP[4:], "-o", path("made", "fig", "x.pdf"),
        "--csv", path("made", "rows", "x.csv"), preexec_fn=fsize_limit)
ok(r.returncode == 1 and not os.path.exists(path("made")),
   f"a failed sweep leaves no folder it made: {r.returncode} {err(r)} "
   f"{os.listdir(path('made')) if os.path.exists(path('made')) else ''}")

# ---- text keys set on the command line are UTF-8 text, as in a file ----
# `--set view.caption=x\xff` was taken (exit 1 "cairo failed" for a PDF);
# a scene file with that byte is refused with exit 2, so --set must be too.
for bad, what in ((b"x\xff", "a byte that is not UTF-8"), (b"a\tb", "a control character"),
                  (b"\xe2\x9c", "a cut-off sequence")):
    for ext in ("png", "pdf"):
        out = path(f"caption-bad.{ext}")
        r = subprocess.run([exe.encode(), b"still", default.encode(), b"--at", b"0", b"--size",
                            b"160x120", b"-q", b"--set", b"view.caption=" + bad, b"-o",
                            out.encode()], cwd=work, capture_output=True, timeout=60)
        ok(r.returncode == 2 and "not text" in err(r) and not os.path.exists(out),
           f"--set view.caption with {what} (.{ext}): exit 2, no file: {r.returncode} {err(r)}")
r = run("still", default, "--at", "0", "--size", "160x120", "-q", "--set",
        "view.caption=Résumé ✓ ω", "-o", path("caption-ok.pdf"))
ok(r.returncode == 0 and os.path.exists(path("caption-ok.pdf")),
   f"--set view.caption with UTF-8 text is drawn: {r.returncode} {err(r)}")

# ---- the figure's extension in any case, as still takes it ----
for ext in ("PNG", "Svg", "PDF"):
    out = path(f"upper.{ext}")
    r = run(*SWEEP, "-o", out)
    head = open(out, "rb").read(5) if os.path.exists(out) else b""
    ok(r.returncode == 0 and head[:4] in (b"\x89PNG", b"<?xm", b"%PDF"),
       f"sweep -o x.{ext} writes that format: {r.returncode} {head!r} {err(r)}")

# ---- Ctrl-C while a FIFO scene waits for its writer: 130 at once ----
# The wait ignored the signal once the parser stopped reading the process's
# flag (and read() then blocked); the parser itself reads no global state.
fifo_scene = path("waiting.ini")
os.mkfifo(fifo_scene)
p = subprocess.Popen([exe, "info", fifo_scene], cwd=work, stdout=subprocess.PIPE,
                     stderr=subprocess.PIPE)
wait_caught(p, signal.SIGINT)
time.sleep(0.5)
p.send_signal(signal.SIGINT)
t0 = time.monotonic()
try:
    p.communicate(timeout=3)
    waited = time.monotonic() - t0
except subprocess.TimeoutExpired:
    p.kill()
    p.communicate()
    waited = None
ok(waited is not None and p.returncode == 130,
   f"Ctrl-C while a FIFO scene waits for its writer: exit 130 promptly: {p.returncode} {waited}")

done()
