#!/usr/bin/env python3
"""springpend tests: the still-open findings 9 and 12 of the attacker's fifth
pass (doc/notes/2026-11-27/attack5.md), each run as the attacker ran it:
- a dotted baseline name (fig.1.png, chaotic.lyapunov.png) is an image of its
  own unless its last part is an environment key declared on compare.ini's
  `envs` line: a missing one is reported missing, and a wrong image no
  longer passes against it; --env needs a declared key, and refuses diff;
- compare.ini sections that match no image are named in a warning;
- the rest of finding 12's small things (see the sections below).
usage: test_attack6_fixes.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import hashlib
import json
import os
import re
import struct
import zlib

import sptest
from sptest import done, err, ok

exe, src, work, _ = sptest.setup("attack6_fixes", [])
run = sptest.runner_bytes(exe, work)
root = os.path.join(src, "..")
default = os.path.join(root, "scenes", "default.ini")
chaotic = os.path.join(root, "scenes", "chaotic.ini")


def path(*names):
    return os.path.join(work, *names)


def read(p):
    with open(p, "rb") as f:
        return f.read()


def write(p, data):
    os.makedirs(os.path.dirname(p) or ".", exist_ok=True)
    with open(p, "wb" if isinstance(data, bytes) else "w") as f:
        f.write(data)


def copy(a, b):
    write(b, read(a))


for t, name in ((1, "b1.png"), (2, "b2.png")):
    r = run("still", default, "--at", str(t), "--size", "64x48", "-q", "-o", name)
    assert r.returncode == 0, err(r)
b1, b2 = path("b1.png"), path("b2.png")

# ---- finding 9: dotted names are images of their own -----------------------------
copy(b1, path("alt2", "e", "chaotic.png"))
copy(b2, path("alt2", "e", "chaotic.lyapunov.png"))
copy(b1, path("alt2", "a", "chaotic.png"))  # the job no longer makes chaotic.lyapunov.png
r = run("compare", "alt2/e", "alt2/a", "--json")
recs = {x["name"]: x for x in json.loads(r.stdout)["results"]} if r.stdout else {}
ok(r.returncode == 2 and recs.get("chaotic.lyapunov.png", {}).get("verdict") == "error"
   and recs.get("chaotic.png", {}).get("alternatives") == 0,
   f"a missing chaotic.lyapunov.png is reported missing, not taken for an alternative "
   f"of chaotic.png (exit {r.returncode})")
copy(b1, path("alt", "e", "a.png"))
copy(b2, path("alt", "e", "a.b.png"))
copy(b2, path("alt", "a", "a.png"))
r = run("compare", "alt/e", "alt/a")
ok(r.returncode == 2 and b"matched the alternative" not in r.stdout
   and b"FAIL a.png" in r.stdout,
   f"a.png does not pass against an undeclared a.b.png (exit {r.returncode})")
write(path("alt", "e", "compare.ini"), "envs = b   # the key of a.b.png\n")
r = run("compare", "alt/e", "alt/a")
ok(r.returncode == 0 and b"matched the alternative baseline for b" in r.stdout,
   f"declared on the envs line, a.b.png is a.png's alternative (exit {r.returncode})")
r = run("compare", "alt/e", "alt/a", "--update=changed", "--env", "zz")
ok(r.returncode == 2 and "alt/e/compare.ini:1: --env zz is not among the keys declared"
   in err(r) and not os.path.exists(path("alt", "e", "a.zz.png")),
   f"--update --env of an undeclared key: FILE:LINE, exit 2, nothing written ({err(r)})")
os.unlink(path("alt", "e", "compare.ini"))
r = run("compare", "alt/e", "alt/a", "--candidates", "alt/c", "--env", "zz")
ok(r.returncode == 2 and "--env zz: no alt/e/compare.ini declares it" in err(r)
   and not os.path.exists(path("alt", "c", "a.zz.png")),
   f"--env without a compare.ini: refused with what to write ({err(r)})")
for line, want in (("envs = b, diff", "compare.ini:1: envs: 'diff': reserved"),
                   ("envs = b, b", "compare.ini:1: envs: 'b' is listed twice"),
                   ("envs = a/b", "compare.ini:1: envs: 'a/b': expected a key"),
                   ("[*]\nmax_diff = 3\nenvs = b", "compare.ini:3: 'envs' comes before")):
    write(path("alt", "e", "compare.ini"), line + "\n")
    r = run("compare", "alt/e", "alt/a")
    ok(r.returncode == 2 and want in err(r) if not line.startswith("[") else
       r.returncode == 2 and "compare.ini:3:" in err(r),
       f"compare.ini {line!r}: refused at its line ({err(r)[:160]})")
os.unlink(path("alt", "e", "compare.ini"))

# ---- finding 12: --env diff collides with the diff images -------------------------
copy(b1, path("ev", "e", "x.png"))
copy(b2, path("ev", "a", "x.png"))
write(path("ev", "e", "compare.ini"), "envs = ci\n")
for key in ("diff", "DIFF", "png", "mp4"):
    r = run("compare", "ev/e", "ev/a", "--candidates", "ev/c", "--env", key)
    ok(r.returncode == 2 and f"--env {key}: reserved" in err(r)
       and not os.path.exists(path("ev", "c")),
       f"--env {key}: refused, nothing written ({err(r)[:120]})")
r = run("compare", "ev/e", "ev/a", "--candidates", "ev/c", "--env", "ci")
ok(r.returncode == 1 and os.path.exists(path("ev", "c", "x.ci.png"))
   and os.path.exists(path("ev", "c", "x.diff.png")),
   f"--env ci: the candidate x.ci.png beside its diff x.diff.png (exit {r.returncode})")

# ---- finding 12: compare.ini sections that match no image are named ----------------
copy(b1, path("cf", "e", "x.png"))
copy(b1, path("cf", "a", "x.png"))
write(path("cf", "e", "compare.ini"),
      "[X.PNG]\nmax_diff = 3\n[ x.png]\nmax_diff = 3\n[../x.png]\nmax_diff = 3\n"
      "[sub/*]\nmax_diff = 3\n[[]\nmax_diff = 3\n[x.png]\nmax_diff = 3\n")
r = run("compare", "cf/e", "cf/a")
e = err(r)
ok(r.returncode == 0 and all(f"compare.ini:{n}: warning: [{s}] matches no compared image" in e
                             for n, s in ((1, "X.PNG"), (3, " x.png"), (5, "../x.png"),
                                          (7, "sub/*"), (9, "[")))
   and "[x.png] matches" not in e,
   f"each compare.ini section that matches no image is named at its line ({e[:200]})")

# ---- finding 12: sweep options that clash -----------------------------------------
grid = ["--measure", "lyapunov", "--time", "2"]
r = run("sweep", chaotic, "--vary", "initial.angle=1:179:4", "--set", "initial.angle=30", *grid,
        "-o", "setvary.svg")
ok(r.returncode == 2 and "--set initial.angle=30" in err(r) and "--vary initial.angle" in err(r)
   and not os.path.exists(path("setvary.svg")),
   f"--set of the varied key: exit 2 naming both ({err(r)[:160]})")
r = run("sweep", chaotic, "--vary", "initial.angle=1:179:1", *grid, "-o", "one.svg")
ok(r.returncode == 2 and "initial.angle=1:179:1" in err(r)
   and not os.path.exists(path("one.svg")),
   f"--vary K=1:179:1 (one value, two ends): exit 2 ({err(r)[:160]})")
r = run("sweep", chaotic, "--vary", "initial.angle=30:30:1", "--vary", "initial.length=0.8:1.6:3",
        *grid, "--csv", "one.csv", "-o", "one.svg")
rows = [ln for ln in open(path("one.csv")).read().splitlines() if ln[:1].isdigit()] \
    if os.path.exists(path("one.csv")) else []
ok(r.returncode == 0 and len(rows) == 3, f"--vary K=30:30:1 is one value: 3 points ({err(r)[:160]})")
r = run("sweep", chaotic, "--vary", "initial.angle=1:179:2", "--vary", "initial.angle=1:10:2",
        *grid, "-o", "twice.svg")
ok(r.returncode == 2 and "given twice" in err(r), f"--vary of one key twice: exit 2 ({err(r)})")

# ---- finding 12: a sweep figure at a degenerate aspect ----------------------------
for size in ("1inx200in", "200inx1in", "1.9inx20in"):
    code, e = sptest.hangs(run, "sweep", chaotic, "--vary", "initial.angle=1:179:4", *grid,
                           "--size", size, "--dpi", "20", "-o", f"thin{size}.png", timeout=60)
    ok(code == 2 and "ticks and axis labels need at least" in e and "allowed: a page at least"
       in e and not os.path.exists(path(f"thin{size}.png")) and not sptest.part_files(work),
       f"sweep --size {size}: refused with the least page that fits ({e[:160]})")
r = run("sweep", chaotic, "--vary", "initial.angle=1:179:4", *grid, "--size", "2.5in", "--dpi",
        "100", "-o", "narrow.png")
ok(r.returncode == 0 and os.path.exists(path("narrow.png")),
   f"sweep --size 2.5in (the least width at the default aspect) is drawn ({err(r)[:160]})")

# ---- finding 12: the CSV's metadata sidecar never replaces the scene --------------
scene_text = read(chaotic)
write(path("a.csv-metadata.json"), scene_text)
r = run("sweep", "a.csv-metadata.json", "--vary", "initial.angle=1:179:4", *grid, "-o", "s4.svg",
        "--csv", "a.csv")
ok(r.returncode == 2 and "would overwrite" in err(r)
   and read(path("a.csv-metadata.json")) == scene_text and not os.path.exists(path("a.csv")),
   f"sweep --csv a.csv with the scene a.csv-metadata.json: refused, the scene kept ({err(r)})")
write(path("d.csv-metadata.json"), read(default))
r = run("data", "d.csv-metadata.json", "-o", "d.csv")
ok(r.returncode == 2 and "would overwrite the scene file" in err(r)
   and read(path("d.csv-metadata.json")) == read(default) and not os.path.exists(path("d.csv")),
   f"data -o d.csv with the scene d.csv-metadata.json: refused, the scene kept ({err(r)})")
write(path("second.ini"), scene_text)
r = run("data", default, "second.ini", "-o", "second.ini")
ok(r.returncode == 2 and read(path("second.ini")) == scene_text,
   f"data A B -o B: the second scene is not replaced either ({err(r)})")

# ---- finding 12: --size means nothing to data and info ----------------------------
for cmd in (["data", default, "-o", "u.csv"], ["info", default]):
    r = run(*cmd, "--size", "320x180")
    ok(r.returncode == 2 and "--size is for 'springpend render' and 'springpend still'" in err(r)
       and not os.path.exists(path("u.csv")) and not r.stdout,
       f"{cmd[0]} --size: exit 2 naming the commands that take it ({err(r)})")

# ---- finding 12: UTF-8 provenance goes into iTXt, not Latin-1 zTXt ---------------
def chunks(p):
    d, i, out = read(p), 8, []
    while i < len(d):
        n, kind = struct.unpack(">I4s", d[i:i + 8])
        out.append((kind, d[i + 8:i + 8 + n]))
        i += 12 + n
    return out


def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


title = "你好 é"
r = run("still", default, "--at", "1", "--size", "320x180", "--set", f"view.title={title}", "-q",
        "-o", "u8.png")
assert r.returncode == 0, err(r)
itxt = {b.split(b"\0", 1)[0]: b for kind, b in chunks(path("u8.png")) if kind == b"iTXt"}
zt = {b.split(b"\0", 1)[0]: zlib.decompress(b.split(b"\0", 1)[1][1:])
      for kind, b in chunks(path("u8.png")) if kind == b"zTXt"}
scene_itxt = itxt.get(b"springpend.scene-file", b"")
flag = scene_itxt.split(b"\0", 1)[1][:1] if scene_itxt else b""
texts = sptest.png_text(path("u8.png"), compressed=True)
ok(b"springpend.scene-file" in itxt and b"springpend.scene" in itxt and flag == b"\1"
   and not any(any(c >= 0x80 for c in v) for v in zt.values())
   and title in texts.get("springpend.scene-file", ""),
   f"a UTF-8 title: the scene's chunks are compressed iTXt, no zTXt holds bytes beyond "
   f"ASCII ({sorted(itxt)}, zTXt {sorted(zt)})")
r = run("scene", "u8.png")
ok(r.returncode == 0 and f'title = "{title}"'.encode() in r.stdout,
   f"springpend scene reads the iTXt back ({err(r)[:120]})")
# an older PNG, the scene as UTF-8 in zTXt: still read
old = b"\x89PNG\r\n\x1a\n"
for kind, b in chunks(path("u8.png")):
    if kind == b"iTXt":
        k, rest = b.split(b"\0", 1)
        v = rest[2:].split(b"\0", 2)[2]
        old += chunk(b"zTXt", k + b"\0\0" + v)  # v is deflated already (flag 1)
    else:
        old += chunk(kind, b)
write(path("old.png"), old)
r = run("scene", "old.png")
ok(r.returncode == 0 and f'title = "{title}"'.encode() in r.stdout,
   f"a PNG with the UTF-8 scene in zTXt (as springpend wrote before) is read too ({err(r)[:120]})")
r = run("compare", "u8.png", "old.png")
ok(r.returncode == 0, f"compare reads both ({r.stdout[-120:]!r})")

# ---- finding 12: compare --jobs is bounded by memory ------------------------------
def flat_png(p, w, h, stripe):
    row0, row1 = b"\0" + bytes((10, 20, 30)) * w, b"\0" + bytes(stripe) * w
    raw = b"".join(row1 if y % 97 == 0 else row0 for y in range(h))
    write(p, b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
          + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


for i in range(4):  # 2000x2000: 32 MB a pair decoded as RGBA
    flat_png(path("mem", "e", f"p{i}.png"), 2000, 2000, (200, 200, 200))
    flat_png(path("mem", "a", f"p{i}.png"), 2000, 2000, (100, 200, 200))
sanitized = b"__asan_init" in read(exe)  # a sanitizer's shadow memory needs no limit


def data_limit(mb):
    import resource
    return lambda: resource.setrlimit(resource.RLIMIT_DATA, (mb << 20, mb << 20))


if not sanitized:
    # ulimit -d 100 MB: four threads of 32 MB and more ran out of memory and
    # reported images as unreadable; the threads are fitted to half the limit
    r = run("compare", "mem/e", "mem/a", "--jobs", "4", preexec_fn=data_limit(100), timeout=120)
    out = r.stdout.decode()
    ok(r.returncode == 1 and "4 compared, 0 passed, 4 failed, 0 missing or unreadable" in out
       and "--jobs 4: each thread holds up to 48 MB" in err(r) and "half of ulimit -d" in err(r)
       and "comparing on 1 thread" in err(r),
       f"compare --jobs 4 under ulimit -d 100 MB: every image compared, on the threads "
       f"that fit, said on stderr ({out.strip()[-90:]} | {err(r)[:200]})")
else:
    ok(True, "compare --jobs under ulimit -d", skip="a sanitizer build")
r = run("compare", "mem/e", "mem/a", "--jobs", "4", timeout=120)
ok(r.returncode == 1 and "--jobs" not in err(r),
   f"without a limit, --jobs 4 of 2000x2000 images runs on 4 threads, nothing said ({err(r)[:120]})")

# ---- sweep --merge: a shard holding the next shard's point is refused --------------
# (the planted bug merge-takes-next-shards-point, tests/plant_bugs.py)
for i in (1, 2):
    r = run("sweep", chaotic, "--vary", "initial.angle=1:179:4", *grid, "--shard", f"{i}/2",
            "--csv", f"sh{i}.csv", "-q")
    assert r.returncode == 0, err(r)
one = read(path("sh1.csv")).splitlines(True)
two = read(path("sh2.csv")).splitlines(True)
forged = one[0] + one[1] + two[1]  # point 1 replaced by point 2, the next shard's first
meta = read(path("sh1.csv-metadata.json")).decode()
meta = re.sub(r'"schema:sha256": "[0-9a-f]+"',
              f'"schema:sha256": "{hashlib.sha256(forged).hexdigest()}"', meta)
write(path("f1.csv"), forged)
write(path("f1.csv-metadata.json"), meta.replace('"url": "sh1.csv"', '"url": "f1.csv"'))
r = run("sweep", "--merge", "f1.csv", "sh2.csv", "-o", "forged.svg")
ok(r.returncode == 2 and "f1.csv:3: the point is not one of this shard's" in err(r)
   and not os.path.exists(path("forged.svg")),
   f"--merge: shard 1/2 holding point 2 (shard 2's), its SHA-256 recomputed: refused at "
   f"its line ({err(r)[:140]})")

done()
