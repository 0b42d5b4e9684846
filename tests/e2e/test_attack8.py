#!/usr/bin/env python3
"""springpend tests (issue 28): the attacker's eighth pass
(doc/notes/2026-11-27/attack8.md), each check run as the attacker ran it:
- finding 1: video compare opened any format FFmpeg detects: a text file
  named y.mp4 that is an HLS playlist naming the baseline passed as
  identical, and --approve installed it. Now only MP4/MOV, WebM/Matroska
  and GIF are read, through the file protocol; anything else is refused
  (exit 2), naming the format found, and --approve replaces nothing;
- finding 2: the module loader trusted group-writable modules and folders;
  now a module, or a folder above it, writable by a group other than root's
  (or the user's private group) is refused, naming the group;
- finding 3: sweep --merge accepted --time, --transient, --energy and
  --measure, used none and recorded them; now refused (exit 2), named;
- finding 4: a merged figure's record put the merge's --size/--dpi after
  the shard's '--', where they are operands; now they go before it, and the
  record re-runs to the one-piece figure's bytes.
usage: test_attack8.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shlex
import shutil

import sptest
from sptest import done, err, ok, skip

exe, src, work, _ = sptest.setup("attack8", [])
run = sptest.runner_bytes(exe, work)
scenes = os.path.abspath(os.path.join(src, "..", "scenes"))
chaotic = os.path.join(scenes, "chaotic.ini")
default = os.path.join(scenes, "default.ini")


def path(*names):
    return os.path.join(work, *names)


command = sptest.scene_command(run)  # what `scene NAME --command` prints


same_bytes = sptest.same_bytes_in(work)


def playlist(target):
    """An HLS playlist (text) whose one segment is the file target."""
    return f"#EXTM3U\n#EXT-X-TARGETDURATION:1\n#EXTINF:1.0,\n{target}\n#EXT-X-ENDLIST\n"


# ---- finding 1: compare reads only the containers springpend writes ------------
r = run("render", default, "--size", "320x180", "--fps", "10", "--set", "video.duration=0.3",
        "-o", "a2.mp4", "-q")
assert r.returncode == 0, err(r)
for d in ("hl/e", "hl/a", "ap/base", "ap/cand", "outside"):
    os.makedirs(path(d))
shutil.copy(path("a2.mp4"), path("hl/e/y.mp4"))
with open(path("hl/a/y.mp4"), "w") as f:
    f.write(playlist(path("hl/e/y.mp4")))
r = run("compare", "hl/e/y.mp4", "a2.mp4")
ok(r.returncode == 0, f"a video springpend wrote still compares (exit {r.returncode}: "
   f"{err(r)[-200:]!r})")
for args in (["hl/e", "hl/a"], ["hl/e/y.mp4", "hl/a/y.mp4"]):
    r = run("compare", *args)
    ok(r.returncode == 2 and b"hls" in r.stderr and b"not a video springpend reads" in r.stderr,
       f"compare {' '.join(args)}: a text file y.mp4 that is an HLS playlist naming the "
       f"baseline is refused (exit 2), naming the format (exit {r.returncode}: "
       f"{err(r)[-240:]!r})")
shutil.copy(path("a2.mp4"), path("outside/s.mp4"))
shutil.copy(path("a2.mp4"), path("ap/base/z.mp4"))
with open(path("ap/cand/z.mp4"), "w") as f:
    f.write(playlist(path("outside/s.mp4")))
r = run("compare", "--approve", "ap/cand", "ap/base")
ok(r.returncode == 2 and same_bytes("ap/base/z.mp4", "a2.mp4"),
   f"compare --approve with a playlist as the candidate: refused, the baseline kept "
   f"(exit {r.returncode}: {err(r)[-240:]!r})")

# ---- finding 2: group-writable modules and folders are not loaded --------------
gid = 100 if os.geteuid() == 0 else next((g for g in os.getgroups() if g not in (0, os.getegid())),
                                          None)
copy = sptest.module_copy(exe, default, work) if gid is not None else None
if gid is None:
    skip("group-writable module folders", "no group to give the folder to")
elif copy is None:
    skip("group-writable module folders", "no springpend-cairo.so in the build, or its path not named")
else:
    still, installed = copy
    folder = os.path.dirname(installed)
    os.chown(folder, -1, gid)
    os.chmod(folder, 0o775)
    r = still("m2.svg")
    ok(r.returncode != 0 and "writable by group" in r.stderr and str(gid) in r.stderr and
       not os.path.exists(path("m2.svg")),
       f"a module folder writable by group {gid}: refused, naming the group "
       f"({r.stderr.strip()[-200:]})")
    os.chown(folder, -1, 0)
    r = still("m3.svg")
    ok(r.returncode == 0 and os.path.exists(path("m3.svg")),
       f"a module folder writable by root's group (gid 0) loads, as documented "
       f"({r.stderr.strip()[-200:]})")
    os.chmod(folder, 0o755)
    os.chown(installed, -1, gid)
    os.chmod(installed, 0o775)
    r = still("m4.svg")
    ok(r.returncode != 0 and "writable by group" in r.stderr and
       not os.path.exists(path("m4.svg")),
       f"a module file writable by group {gid}: refused ({r.stderr.strip()[-200:]})")

# ---- finding 3: --merge refuses the options that describe the sweep ------------
grid = ["--vary", "initial.angle=1:179:8", "--measure", "lyapunov", "--time", "2"]
for i in (1, 2):
    r = run("sweep", chaotic, *grid, "--shard", f"{i}/2", "--csv", f"r{i}.csv", "-q")
    assert r.returncode == 0, err(r)
for extra in (["--transient", "7"], ["--time", "50"], ["--energy", "3"],
              ["--measure", "spectrum"], ["--time", "2", "--transient", "1"]):
    r = run("sweep", "--merge", "r1.csv", "r2.csv", "-o", "mt.png", "-q", *extra)
    named = all(f"--{extra[k][2:]} {extra[k + 1]}".encode() in r.stderr
                for k in range(0, len(extra), 2))
    ok(r.returncode == 2 and named and not os.path.exists(path("mt.png")),
       f"sweep --merge ... {' '.join(extra)}: refused (exit 2), naming it, no figure "
       f"(exit {r.returncode}: {err(r)[-200:]!r})")
r = run("sweep", "--merge", "r1.csv", "r2.csv", "-o", "mok.png", "-q")
ok(r.returncode == 0 and command("mok.png").endswith("--time 2"),
   f"the merge alone still draws, recording the shards' command: {command('mok.png')!r}")

# ---- finding 4: a merge's --size/--dpi go before the shard's '--' -------------
for i in (1, 2):
    r = run("sweep", *grid, "--shard", f"{i}/2", "--csv", f"d{i}.csv", "-q", "--", chaotic)
    assert r.returncode == 0, err(r)
r = run("sweep", "--merge", "d1.csv", "d2.csv", "-o", "dm.png", "--size", "3in", "--dpi", "100",
        "-q")
c = command("dm.png")
ok(r.returncode == 0 and c.endswith(f"--size 3in --dpi 100 -- {chaotic}"),
   f"a merge of shards run with '-- SCENE' records --size/--dpi before '--': {c!r}")
r = run("sweep", *grid, "--size", "3in", "--dpi", "100", "-o", "one.png", "-q", "--", chaotic)
ok(r.returncode == 0 and same_bytes("one.png", "dm.png") and command("one.png") == c,
   f"... and equals the one-piece run's figure and record ({command('one.png')!r})")
words = shlex.split(c) if c.startswith("springpend ") else []
r = run(words[1], "-o", "re.png", "-q", *words[2:]) if words else None
ok(r is not None and r.returncode == 0 and same_bytes("re.png", "dm.png"),
   f"the merged figure's record re-runs to its bytes "
   f"({'no record' if r is None else f'exit {r.returncode}: {err(r)[-200:]!r}'})")

done()
