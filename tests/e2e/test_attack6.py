#!/usr/bin/env python3
"""springpend tests: the attacker's sixth pass (doc/notes/2026-11-27/
attack6.md). Each check is a class, run as the attacker ran it:
- sweep --merge draws the figure with the shards' scene's look (title, font,
  font size), the same figure as the one-piece run: it drew the default look
  and its provenance said title = "";
- a CSV and its CSV-metadata.json are put in place together, under a lock on
  their folder: two runs writing the same CSV at once left one run's rows
  with the other's metadata;
- compare's diff and reports must be files: a FIFO, a device or stdout is
  refused before anything is compared (exit 2), not after every comparison
  with the status of "images differ";
- an option with a value given twice is refused, in every command (the
  last one silently won: -o a.png -o b.png wrote b.png alone);
- springpend scene reads a file named -x.png after '--' and takes --cell
  before FILE too, as every command's getopt does.
usage: test_attack6.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import fcntl
import os
import stat
import subprocess
import time

import sptest
from sptest import done, err, ok

exe, src, work, _ = sptest.setup("attack6", [])
run = sptest.runner_bytes(exe, work)
scenes = os.path.join(src, "..", "scenes")
default = os.path.join(scenes, "default.ini")
chaotic = os.path.join(scenes, "chaotic.ini")


def path(*names):
    return os.path.join(work, *names)


def read(p):
    with open(p, "rb") as f:
        return f.read()


# ---- sweep --merge: the figure's look is the shards' scene's -----------------
look = ["--vary", "initial.angle=1:179:8", "--measure", "lyapunov", "--time", "2",
        "--set", "view.title=Merged look", "--set", "view.font_size=14",
        "--set", "view.font=DejaVu Serif", "-q"]
r = run("sweep", chaotic, *look, "-o", "one.png", "--csv", "one.csv")
assert r.returncode == 0, err(r)
for i in (1, 2):
    r = run("sweep", chaotic, *look, "--shard", f"{i}/2", "--csv", f"s{i}.csv")
    assert r.returncode == 0, err(r)
r = run("sweep", "--merge", "s2.csv", "s1.csv", "-o", "merged.png", "--csv", "merged.csv", "-q")
ok(r.returncode == 0 and read(path("merged.csv")) == read(path("one.csv"))
   and read(path("merged.png")) == read(path("one.png")),
   f"sweep --merge: with a title, font and font_size set, the merged figure is byte for "
   f"byte the one-piece figure (exit {r.returncode}: {err(r)[-160:]!r})")
r = run("scene", "merged.png")
ok(r.returncode == 0 and 'title = "Merged look"' in r.stdout.decode(),
   "sweep --merge: the merged figure's scene keeps the shards' title (it said title = \"\")")

# ---- a CSV and its metadata are put in place together ------------------------
# A run holding the folder's lock (as another run putting its pair in place
# does) must keep this run's pair out until it is released: without the lock
# the two runs' renames interleave, leaving one run's rows under the other's
# metadata (4 times in 30 for two data runs at once).
os.makedirs(path("pair"))
fd = os.open(path("pair"), os.O_RDONLY)
fcntl.flock(fd, fcntl.LOCK_EX)
p = subprocess.Popen([exe, "data", default, "--set", "video.duration=0.5", "-q",
                      "-o", "pair/d.csv"], cwd=work, stdout=subprocess.PIPE,
                     stderr=subprocess.PIPE)
time.sleep(1.5)
early = os.path.exists(path("pair", "d.csv")) or os.path.exists(path("pair", "d.csv-metadata.json"))
fcntl.flock(fd, fcntl.LOCK_UN)
os.close(fd)
out, e = p.communicate(timeout=60)
ok(not early and p.returncode == 0 and os.path.exists(path("pair", "d.csv"))
   and os.path.exists(path("pair", "d.csv-metadata.json")),
   f"data: the CSV and its metadata are renamed into place under the folder's lock "
   f"(in place while another run held it: {early}; exit {p.returncode})")

# a process keeping the folder locked delays the pair at most 5 s, said: it
# cannot hang the run (anyone may lock a shared folder such as /tmp)
fd = os.open(path("pair"), os.O_RDONLY)
fcntl.flock(fd, fcntl.LOCK_EX)
t0 = time.monotonic()
r = run("data", default, "--set", "video.duration=0.5", "-o", "pair/held.csv", timeout=60)
took = time.monotonic() - t0
fcntl.flock(fd, fcntl.LOCK_UN)
os.close(fd)
ok(r.returncode == 0 and took < 30 and "keeps locking its folder" in err(r)
   and os.path.exists(path("pair", "held.csv")),
   f"data: a folder locked for good delays the pair a few seconds, with a note "
   f"({took:.1f} s, exit {r.returncode}: {err(r)[-100:]!r})")

for k in range(6):  # and the pairs of two runs at once always match
    a = subprocess.Popen([exe, "data", default, "--set", "video.duration=3", "-q",
                          "-o", "race.csv"], cwd=work)
    b = subprocess.Popen([exe, "data", chaotic, "--set", "video.duration=2", "-q",
                          "-o", "race.csv"], cwd=work)
    a.wait(60), b.wait(60)
    rows = read(path("race.csv")).count(b"\n") - 1
    meta = read(path("race.csv-metadata.json"))
    from_chaotic = b"stiffness = 39.24" in meta
    if (rows == 180) == from_chaotic:
        break
ok((rows == 180) != from_chaotic,
   f"data: two runs writing the same CSV at once leave one run's CSV with that run's "
   f"metadata ({rows} rows, metadata of {'chaotic' if from_chaotic else 'default'}.ini)")

# ---- compare writes its diff and reports to files ----------------------------
for t, name in ((1, "b1.png"), (2, "b2.png")):
    r = run("still", default, "--at", str(t), "--size", "64x48", "-q", "-o", name)
    assert r.returncode == 0, err(r)
os.makedirs(path("same"))
with open(path("same", "x.png"), "wb") as f:
    f.write(read(path("b1.png")))
os.mkfifo(path("report.html"))
t0 = time.monotonic()
r = run("compare", "same", "same", "--report", "report.html", timeout=30)
ok(r.returncode == 2 and "--report report.html is not a regular file" in err(r)
   and b"compared" not in r.stdout and stat.S_ISFIFO(os.lstat(path("report.html")).st_mode),
   f"compare --report FIFO: refused before comparing, exit 2, the FIFO left "
   f"(exit {r.returncode}: {err(r)[-120:]!r})")
r = run("compare", "b1.png", "b2.png", "--diff", "/dev/stdout", "--summary", "s.md")
ok(r.returncode == 2 and "--diff /dev/stdout is not a regular file" in err(r)
   and not os.path.exists(path("s.md")),
   f"compare --diff /dev/stdout: refused before comparing, exit 2 (exit {r.returncode})")
if os.geteuid() == 0:
    os.mknod(path("null"), 0o666 | stat.S_IFCHR, os.makedev(1, 3))
r = run("compare", "same", "same", "--junit", "null") if os.geteuid() == 0 else None
ok(os.geteuid() != 0 or (r.returncode == 2 and "--junit null is not a regular file" in err(r)),
   "compare --junit DEVICE: refused before comparing, exit 2",
   skip=None if os.geteuid() == 0 else "mknod needs root")
os.mkfifo(path("v.mp4"))
r = run("render", default, "--size", "64x48", "-o", "v.mp4", timeout=30)
ok(r.returncode == 2 and "v.mp4 is a FIFO, not a regular file" in err(r),
   f"render -o FIFO.mp4: the message names 'a FIFO' ({err(r)[-120:]!r})")

# ---- an option with a value is given once --------------------------------------
twice = [
    (["still", default, "--at", "1", "--size", "64x48", "-o", "t1.png", "-o", "t2.png"],
     "--output given twice (t1.png, then t2.png)", ["t1.png", "t2.png"]),
    (["still", default, "--at", "1", "--at", "2", "--size", "64x48", "-o", "t3.png"],
     "--at given twice (1, then 2)", ["t3.png"]),
    (["data", default, "--every", "0.1", "--every", "0.5", "-o", "t5.csv"],
     "--every given twice (0.1, then 0.5)", ["t5.csv"]),
    (["compare", "b1.png", "b2.png", "--report", "r1.html", "--report", "r2.html"],
     "--report given twice (r1.html, then r2.html)", ["r1.html", "r2.html"]),
    (["compare", "b1.png", "b2.png", "--max-diff", "3", "--max-diff=5"],
     "--max-diff given twice (3, then 5)", []),
    (["sweep", chaotic, "--vary", "initial.angle=1:179:4", "--measure", "lyapunov",
      "--measure", "orbit", "--time", "2", "-o", "t6.png"],
     "--measure given twice (lyapunov, then orbit)", ["t6.png"]),
]
for args, says, outs in twice:
    r = run(*args)
    ok(r.returncode == 2 and says in err(r) and not any(os.path.exists(path(o)) for o in outs),
       f"{args[0]}: {says}: refused, exit 2, nothing written (exit {r.returncode}: "
       f"{err(r)[-100:]!r})")
r = run("sweep", chaotic, "--vary", "initial.angle=1:179:4", "--vary", "initial.length=1:2:3",
        "--measure", "lyapunov", "--time", "2", "--set", "view.font_size=12",
        "--set", "view.title=T", "-q", "-o", "-")
ok(r.returncode == 0, f"--vary and --set still repeat (exit {r.returncode}: {err(r)[-100:]!r})")
# --size and --fps are render's and still's shorthands for --set video.width,
# video.height and video.fps: they repeat as --set does, the last winning
r = run("render", default, "--size", "64x48", "--fps", "5", "--size=96x64", "--fps", "10",
        "--set", "video.duration=0.2", "--format", "raw", "-o", "-")
ok(r.returncode == 0 and len(r.stdout) == 96 * 64 * 4 * 2,
   f"render --size and --fps repeat as --set does, the last winning: "
   f"{len(r.stdout)} bytes = 2 frames of 96x64 (exit {r.returncode}: {err(r)[-100:]!r})")

# ---- scene: '--' and --cell anywhere -------------------------------------------
with open(path("-lead.png"), "wb") as f:
    f.write(read(path("b1.png")))
r = run("scene", "--", "-lead.png")
ok(r.returncode == 0 and b"[pendulum]" in r.stdout,
   f"scene -- -lead.png: read (exit {r.returncode}: {err(r)[-100:]!r})")
r = run("scene", "--cell", "1", "b1.png")
ok(r.returncode == 0 and r.stdout == run("scene", "b1.png", "--cell", "1").stdout,
   f"scene --cell 1 FILE: as scene FILE --cell 1 (exit {r.returncode}: {err(r)[-100:]!r})")

# ---- a positive font_size too small to read is refused (finding 5) -------------
# It was drawn at the renderer's 4 px floor, every label unreadable, exit 0.
for value in ("0.5", "1e-300", "3.9"):
    r = run("still", default, "--at", "1", "--size", "320x180", "--set", f"view.font_size={value}",
            "-o", f"fs_{value}.png")
    ok(r.returncode == 2 and "too small to read" in err(r) and "4 <= font_size <= 200" in err(r) and
       not os.path.exists(path(f"fs_{value}.png")),
       f"view.font_size={value}: exit 2 with the range, nothing written "
       f"(exit {r.returncode}: {err(r)[-140:]!r})")
with open(path("fs.ini"), "w") as f:
    f.write("[view]\nfont_size = 0.25\n")
r = run("info", path("fs.ini"))
ok(r.returncode == 2 and f"{path('fs.ini')}:2: view.font_size = 0.25 pt is too small" in err(r),
   f"font_size = 0.25 in a scene file: FILE:LINE ({err(r)[-140:]!r})")
for value in ("0", "4"):
    r = run("still", default, "--at", "1", "--size", "320x180", "--set", f"view.font_size={value}",
            "-o", f"fs_ok{value}.png")
    ok(r.returncode == 0 and os.path.exists(path(f"fs_ok{value}.png")),
       f"view.font_size={value} is drawn (exit {r.returncode}: {err(r)[-100:]!r})")

done()
