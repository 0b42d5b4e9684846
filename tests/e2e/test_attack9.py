#!/usr/bin/env python3
"""springpend tests (issue 28): the attacker's ninth pass
(doc/notes/2026-11-27/attack9.md), each check run as the attacker ran it
(smaller), most severe first:
- finding 5: a POSIX ACL that lets another user write a module (its group
  bits are then the ACL's mask, not its group's) passed the group-writable
  rule: a module or folder with such an ACL is refused, named;
- finding 2: a shard's command naming a FIFO as its scene blocked
  sweep --merge for ever, and one naming any readable file made the merge
  print that file's first keys: the merge looks without waiting, and says
  no line of what the named file holds;
- finding 3: a folder compare out of memory for its records wrote reports
  that pass: they now say FAIL;
- finding 4: compare decoded any of FFmpeg's video codecs (TIFF in
  Matroska, QuickTime RLE) and --approve installed such a file: only H.264,
  VP9, GIF and HEVC are read, others refused by name;
- finding 1: a poincare shard's command without --energy passed the
  merge's check though the shard holds another E: refused;
- finding 6: a damaged video was decoded twice with --jobs above 1 (again
  alone after the pool): once, unless the process is near its ulimit;
- finding 7: a diff whose name holds a bidi control was attached in JUnit
  under a path that does not exist: not attached, named in the text;
- finding 8 (MEDIUM): `scene FILE --command` printed a forged record as it
  was, and doc/ci.md's recipe evals it: a received PNG ran any shell
  command. Now the record is read into springpend's own words and written
  again quoted (a $(...) is a plain word), and a line springpend never
  writes is refused;
- finding 9: compare's "to add it as the baseline" hint was not quoted,
  and a missing file was "not a regular file": quoted as records are, and
  "does not exist";
- finding 12: a CSV's record keeps its -o, so the documented "add -o NAME"
  was refused: `scene X.csv --command` now says to change that name, and
  doing so re-makes the CSV's bytes;
- finding 11: when the HTML report could not be written, the JUnit and
  Markdown reports were silently not written: each is tried and said;
- finding 13: under ulimit -v a valid video pair was "cannot decode" (an
  input error, exit 2): near the limit it is out of memory (exit 1).
usage: test_attack9.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import os
import re
import resource
import shutil
import stat
import struct
import subprocess

import sptest
from sptest import done, err, ok, skip

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack9")
chaotic = os.path.join(scenes, "chaotic.ini")
default = os.path.join(scenes, "default.ini")


# ---- finding 5: a module or folder whose ACL lets others write it is not loaded ---------
def acl(users):
    """A system.posix_acl_access value (the kernel's format, version 2): owner rwx, the
    named users (uid, rwx), group r-x, mask rwx, other r-x."""
    undefined = 0xFFFFFFFF
    entries = [(0x01, 7, undefined)] + [(0x02, 7, u) for u in users] + \
              [(0x04, 5, undefined), (0x10, 7, undefined), (0x20, 5, undefined)]
    return struct.pack("<I", 2) + b"".join(struct.pack("<HHI", t, p, i) for t, p, i in entries)


copy = sptest.module_copy(exe, default, work)
if copy is None:
    skip("modules with an ACL", "no springpend-cairo.so in the build, or its path not named")
else:
    still, installed = copy
    folder = os.path.dirname(installed)
    try:
        os.setxattr(installed, "system.posix_acl_access", acl([1000]))
        could = True
    except OSError as e:
        could = False
        skip("a module with an ACL u:1000:rwx", f"no POSIX ACLs here ({e})")
    if could:
        # root:root, group bits rwx (the ACL's mask), owning group gid 0: the rule that
        # trusts root's group took the mask for the group's own permission
        mode = stat.S_IMODE(os.stat(installed).st_mode)
        r = still("m2.svg")
        ok(mode & stat.S_IWGRP and r.returncode != 0 and "has an ACL" in r.stderr
           and installed in r.stderr and not os.path.exists(path("m2.svg")),
           f"a root-owned module (mode {mode:o}) whose ACL lets uid 1000 write it: refused, "
           f"named (exit {r.returncode}: {r.stderr.strip()[-240:]})")
        os.removexattr(installed, "system.posix_acl_access")
        os.chmod(installed, 0o755)
        os.setxattr(folder, "system.posix_acl_access", acl([1000]))
        r = still("m3.svg")
        ok(r.returncode != 0 and "has an ACL" in r.stderr and folder in r.stderr
           and not os.path.exists(path("m3.svg")),
           f"the module's folder with an ACL u:1000:rwx: refused, named "
           f"(exit {r.returncode}: {r.stderr.strip()[-240:]})")
        os.removexattr(folder, "system.posix_acl_access")
        os.chmod(folder, 0o755)
        r = still("m4.svg")
        ok(r.returncode == 0 and os.path.exists(path("m4.svg")),
           f"the ACLs removed, the module loads again ({r.stderr.strip()[-200:]})")

# ---- finding 2: a shard's command that names a FIFO, or a file that is no scene ----------
grid = ["--vary", "initial.angle=1:179:4", "--measure", "lyapunov", "--time", "2"]
for i in (1, 2):
    r = run("sweep", chaotic, *grid, "--shard", f"{i}/2", "--csv", f"r{i}.csv", "-q")
    assert r.returncode == 0, err(r)
meta = "r1.csv-metadata.json"
shutil.copy(path(meta), path("kept.json"))
os.mkfifo(path("ff.ini"))
sptest.edit_file(path(meta), chaotic, path("ff.ini"))
rc, said = sptest.hangs(run, "sweep", "--merge", "r1.csv", "r2.csv", "-o", "mf.png", "-q",
                        timeout=30)
ok(rc != "hung", f"sweep --merge whose shard's command names a FIFO as its scene: returns "
   f"(exit {rc}: {said[-200:]!r})")
shutil.copy(path("kept.json"), path(meta))
with open(path("secret.env"), "w") as f:
    f.write("GITHUB_TOKEN=ghp_x\nAWS_KEY=y\n")
sptest.edit_file(path(meta), chaotic, path("secret.env"))
r = run("sweep", "--merge", "r1.csv", "r2.csv", "-o", "ms.png", "-q")
ok(r.returncode == 2 and "GITHUB_TOKEN" not in err(r) and "AWS_KEY" not in err(r)
   and "secret.env, which is no scene springpend reads" in err(r)
   and not os.path.exists(path("ms.png")),
   f"sweep --merge whose shard's command names a file that is no scene: refused, and not "
   f"a word of what the file holds is said (exit {r.returncode}: {err(r)[-300:]!r})")
shutil.copy(path("kept.json"), path(meta))
r = run("sweep", "--merge", "r1.csv", "r2.csv", "-o", "mk.png", "-q")
ok(r.returncode == 0 and os.path.exists(path("mk.png")),
   f"the shards as made still merge ({err(r)[-200:]!r})")

# ---- finding 3: out of memory for the records: no report passes --------------------------
r = run("still", default, "--size", "64x36", "-q", "-o", "s.png")
assert r.returncode == 0, err(r)
for d in ("mem/e", "mem/a"):
    os.makedirs(path(d))
for i in range(300):  # 300 records: room between the libraries' load and the records
    os.link(path("s.png"), path("mem", "e", f"{i}.png"))
    os.link(path("s.png"), path("mem", "a", f"{i}.png"))
if sanitized:
    skip("compare out of memory for its records", "ulimit -v and a sanitizer's shadow memory")
else:
    found = None
    for kb in range(9000, 60000, 1000):
        def limit(kb=kb):
            resource.setrlimit(resource.RLIMIT_AS, (kb << 10, kb << 10))
        r = run("compare", "mem/e", "mem/a", "--summary", "s.md", "--junit", "j.xml", "--json",
                preexec_fn=limit)
        if "out of memory for the comparison's records" in err(r):
            found = kb
            break
    if found is None:
        skip("compare out of memory for its records", "no ulimit -v from 9 to 60 MB reached it")
    else:
        try:
            rep = json.loads(r.stdout)
        except ValueError:
            rep = {}
        junit = open(path("j.xml")).read() if os.path.exists(path("j.xml")) else ""
        md = open(path("s.md")).read() if os.path.exists(path("s.md")) else ""
        ok(r.returncode != 0 and rep.get("pass") is False and "out of memory" in
           str(rep.get("problem")) and re.search(r'<testsuites[^>]* errors="[1-9]', junit)
           and "FAIL" in md and "### springpend compare: ok" not in md,
           f"compare under ulimit -v {found} KB, out of memory for its records: --json, JUnit "
           f"and the summary say FAIL (exit {r.returncode}; pass {rep.get('pass')}, problem "
           f"{rep.get('problem')!r}; {junit[:160]!r}; {md[:80]!r})")

# ---- finding 4: only the codecs springpend writes are decoded ------------------------------
r = run("render", default, "--size", "160x90", "--fps", "10", "--set", "video.duration=0.3",
        "-o", "a.mp4", "-q", timeout=120)
assert r.returncode == 0, err(r)
if not shutil.which("ffmpeg"):
    skip("videos of other codecs", "no ffmpeg")
else:
    for name, args, codec in (("t.webm", ["-c:v", "tiff", "-f", "matroska"], "TIFF"),
                              ("q.mov", ["-c:v", "qtrle"], "QuickTime Animation")):
        subprocess.run(["ffmpeg", "-v", "error", "-y", "-i", path("a.mp4"), *args, path(name)],
                       check=True, timeout=60)
        r = run("compare", "a.mp4", name)
        ok(r.returncode == 2 and f"{name}: its video is {codec}" in err(r),
           f"compare a.mp4 {name}: a video of codec {codec} is refused by name (exit "
           f"{r.returncode}: {err(r)[-240:]!r})")
    for d in ("ap/base", "ap/cand"):
        os.makedirs(path(d))
    shutil.copy(path("a.mp4"), path("ap", "base", "z.mp4"))
    shutil.copy(path("t.webm"), path("ap", "cand", "z.mp4"))
    r = run("compare", "--approve", "ap/cand", "ap/base")
    ok(r.returncode == 2 and open(path("ap", "base", "z.mp4"), "rb").read()
       == open(path("a.mp4"), "rb").read(),
       f"compare --approve with TIFF frames named z.mp4 as the candidate: refused, the "
       f"baseline kept (exit {r.returncode}: {err(r)[-200:]!r})")
    r = run("compare", "a.mp4", "a.mp4")
    ok(r.returncode == 0, f"an H.264 video springpend wrote still compares ({err(r)[-200:]!r})")

# ---- finding 1: a poincare shard's command without --energy ------------------------------
poincare = ["--vary", "initial.length=0.8:1.2:4", "--measure", "poincare", "--time", "20"]
for i in (1, 2):
    r = run("sweep", chaotic, *poincare, "--energy", "5", "--shard", f"{i}/2", "--csv",
            f"p{i}.csv", "-q", timeout=120)
    assert r.returncode == 0, err(r)
r = run("sweep", "--merge", "p1.csv", "p2.csv", "-o", "pm.png", "-q", timeout=120)
ok(r.returncode == 0, f"poincare shards at --energy 5 merge ({err(r)[-200:]!r})")
sptest.edit_file(path("p1.csv-metadata.json"), " --energy 5", "")
r = run("sweep", "--merge", "p1.csv", "p2.csv", "-o", "pm2.png", "-q", timeout=120)
ok(r.returncode == 2 and "no --energy (the scene's own E = " in err(r) and "E = 5 J" in err(r)
   and not os.path.exists(path("pm2.png")),
   f"a shard's command that drops --energy 5: refused, naming both energies (exit "
   f"{r.returncode}: {err(r)[-300:]!r})")
for i in (1, 2):  # without --energy: the scene's own E, which the check computes alike
    r = run("sweep", chaotic, *poincare, "--shard", f"{i}/2", "--csv", f"q{i}.csv", "-q",
            timeout=120)
    assert r.returncode == 0, err(r)
r = run("sweep", "--merge", "q1.csv", "q2.csv", "-o", "qm.png", "-q", timeout=120)
ok(r.returncode == 0, f"poincare shards at the scene's own energy merge ({err(r)[-200:]!r})")

# ---- finding 6: a damaged video is decoded once with --jobs 2 ------------------------------
r = run("render", default, "--size", "320x180", "--fps", "30", "--set", "video.duration=6",
        "-o", "long.mp4", "-q", timeout=300)
assert r.returncode == 0, err(r)
data = open(path("long.mp4"), "rb").read()
with open(path("cut.mp4"), "wb") as f:
    f.write(data[:int(len(data) * 0.95)])
for i in range(4):
    for side, src_name in (("e", "long.mp4"), ("a", "cut.mp4")):
        os.makedirs(path("rt", side), exist_ok=True)
        os.link(path(src_name), path("rt", side, f"{i}.mp4"))


def read_by(*args):
    """The bytes springpend read() for args (rchar of this process's
    /proc/self/io, which takes in each child's once it is waited for), and
    its run. Not a time: the same on a loaded machine."""
    def rchar():
        with open("/proc/self/io") as f:
            return next(int(l.split()[1]) for l in f if l.startswith("rchar:"))
    before = rchar()
    r = run(*args, timeout=300)
    return rchar() - before, r


# A cut video decoded in the pool and then again alone reads its bytes twice
# (main before the fix: 2.0-2.4x the CPU time). Decoded once, --jobs 2 reads
# what --jobs 1 reads and its memory plan's look at each file's header (a
# cut MP4 has no index: the look reads to its end, about 0.8 of the cut
# files' bytes here), less than the cut files' bytes more; read twice, that
# and the cut files again (about 1.8 times).
(one, r1), (two, r2) = [read_by("compare", "rt/e", "rt/a", "--jobs", j) for j in ("1", "2")]
cut_bytes = 4 * os.path.getsize(path("cut.mp4"))
ok(r1.returncode == 2 and r2.returncode == 2 and two - one < cut_bytes
   and err(r2).count("cannot read the next frame") == err(r1).count("cannot read the next frame"),
   f"4 cut videos: --jobs 2 reads {two} bytes against --jobs 1's {one} (the cut files hold "
   f"{cut_bytes}: each decoded once), its errors said as often")

# ---- finding 7: a diff named with a bidi control is not attached under another path -------
name = "x\u202egnp.png"
for d in ("bd/e", "bd/a"):
    os.makedirs(path(d))
r = run("still", default, "--size", "64x36", "-q", "-o", os.path.join("bd", "e", name))
r = run("still", default, "--at", "2", "--size", "64x36", "-q", "-o", os.path.join("bd", "a", name))
r = run("compare", "bd/e", "bd/a", "--diff", "bd/d", "--junit", "bd.xml")
junit = open(path("bd.xml"), encoding="utf-8").read() if os.path.exists(path("bd.xml")) else ""
attached = re.findall(r"\[\[ATTACHMENT\|([^\]]*)\]\]", junit)
ok(r.returncode == 1 and os.listdir(path("bd", "d"))
   and all(os.path.exists(path(a)) for a in attached) and "\\u202e" in junit,
   f"a failing image named with U+202E: its diff is attached under no path that does not "
   f"exist ({attached}), and is named (escaped) in the text (exit {r.returncode})")

# ---- finding 8: scene --command prints only springpend's words, quoted again -------------


def with_command(src_png, out_png, line):
    """src_png (in the work folder) with its springpend.command set to line."""
    sptest.png_with_command(path(src_png), path(out_png), line)


r = run("still", default, "--at", "1.5", "--size", "64x36", "-q", "-o", "fig.png")
assert r.returncode == 0, err(r)
pwned = path("PWNED")
for forged, shown in ((f"springpend still {default} --at 1.5 $(touch {pwned})", "'$(touch'"),
                      (f"springpend still {default} --at 1.5;touch {pwned}", "'1.5;touch'"),
                      (f"springpend still {default} --at `touch {pwned}`", "'`touch'")):
    with_command("fig.png", "forged.png", forged)
    r = run("scene", "forged.png", "--command")
    line = r.stdout.decode().strip()
    # doc/ci.md's recipe: eval "springpend ${cmd#springpend } -o fig.png"
    subprocess.run(["sh", "-c", 'eval "\"$0\" ${1#springpend } -o again.png -q"', exe, line],
                   cwd=work, capture_output=True, timeout=60)
    ok(r.returncode == 0 and shown in line and not os.path.exists(pwned),
       f"scene --command of a record forged as {forged[-40:]!r}: printed as plain quoted "
       f"words ({line[-60:]!r}), and the recipe's eval runs no command of the file's")
    if os.path.exists(pwned):
        os.unlink(pwned)
for forged in (f"rm -rf {path('nothing')}", f"springpend still '{default}", "springpend scene x.png",
               "springpend  still a.ini"):
    with_command("fig.png", "forged.png", forged)
    r = run("scene", "forged.png", "--command")
    ok(r.returncode == 2 and not r.stdout and "is not a command line springpend writes" in err(r),
       f"scene --command of a record {forged[-30:]!r}: refused, nothing printed (exit "
       f"{r.returncode}: {err(r)[-160:]!r})")
r = run("scene", "fig.png", "--command")
ok(r.returncode == 0 and r.stdout.decode().startswith(f"springpend still {default} --at 1.5 "),
   f"a record springpend wrote prints as before ({r.stdout.decode().strip()[-80:]!r})")

# ---- finding 9: the baseline hint quoted; a missing file called missing ------------------
for d in ("sp e", "spa", "q$(id)"):
    os.makedirs(path(d))
shutil.copy(path("s.png"), path("spa", "y.png"))
for folder, quoted in (("sp e", "'sp e'"), ("q$(id)", "'q$(id)'")):
    r = run("compare", folder, "spa")
    said = r.stdout.decode() + err(r)
    ok(f"to add it as the baseline: springpend compare {quoted} spa --update=missing" in said,
       f"compare {folder!r} spa: the hint names the folder as one quoted word "
       f"({said[-160:]!r})")
r = run("compare", "s.png", "nope.png")
ok(r.returncode == 2 and "nope.png does not exist" in r.stdout.decode()
   and "not a regular file" not in r.stdout.decode(),
   f"compare s.png nope.png: the missing file is said not to exist ({r.stdout.decode()[-120:]!r})")

# ---- finding 11: the JUnit and Markdown reports are written when the HTML is not -----------
for d in ("pass/e", "pass/a"):
    os.makedirs(path(d))
shutil.copy(path("s.png"), path("pass", "e", "x.png"))
shutil.copy(path("s.png"), path("pass", "a", "x.png"))
r = run("compare", "pass/e", "pass/a", "--report", "nodir/r.html", "--junit", "pass/j.xml",
        "--summary", "pass/s.md")
ok(r.returncode != 0 and "nodir/r.html" in err(r) and os.path.exists(path("pass", "j.xml"))
   and os.path.exists(path("pass", "s.md")),
   f"compare whose --report cannot be written: the JUnit and the summary are written still, "
   f"the HTML's failure said (exit {r.returncode}: {err(r)[-200:]!r}; {sorted(os.listdir(path('pass')))})")

# ---- finding 13: near ulimit -v a valid video pair is out of memory, not "cannot decode" ----
r = run("render", default, "--size", "1280x720", "--fps", "10", "--set", "video.duration=0.5",
        "-o", "vm.mp4", "-q", timeout=120)
assert r.returncode == 0, err(r)
if sanitized:
    skip("a video pair near ulimit -v", "ulimit -v and a sanitizer's shadow memory")
else:
    said = {}
    for mb in range(150, 420, 10):
        def limit(mb=mb):
            resource.setrlimit(resource.RLIMIT_AS, (mb << 20, mb << 20))
        r = run("compare", "vm.mp4", "vm.mp4", preexec_fn=limit, timeout=60)
        said[mb] = (r.returncode, r.stdout.decode().strip().splitlines()[-1:])
    decode = [mb for mb, (rc, out) in said.items() if "cannot decode" in str(out)]
    nomem = [mb for mb, (rc, out) in said.items() if rc == 1 and "out of memory" in str(out)]
    passed = [mb for mb, (rc, out) in said.items() if rc == 0]
    ok(not decode and nomem and passed,
       f"compare vm.mp4 vm.mp4 (1280x720) under ulimit -v 150..410 MB: never 'cannot decode'; "
       f"out of memory (exit 1) at {nomem[:1]}..{nomem[-1:]} MB, passes from {passed[:1]} MB "
       f"('cannot decode' at {decode})")

# ---- finding 12: a CSV's command keeps its -o: said, and the recipe that follows it works ---
r = run("data", default, "--set", "video.duration=1", "-o", "out.csv", "-q")
assert r.returncode == 0, err(r)
r = run("scene", "out.csv", "--command")
line = r.stdout.decode().strip()
said = err(r)
again = line.replace(" -o out.csv", " -o again.csv")
sh = "'" + exe.replace("'", "'\\''") + "'" + again[len("springpend"):]
r2 = subprocess.run(["sh", "-c", sh], cwd=work, capture_output=True, timeout=60)
ok(r.returncode == 0 and " -o out.csv" in line and "change that FILE to NAME" in said
   and r2.returncode == 0 and open(path("again.csv"), "rb").read() == open(path("out.csv"), "rb").read(),
   f"scene out.csv --command: the record keeps -o out.csv, stderr says to change it, and the "
   f"command with that name changed re-makes the CSV's bytes ({line[-60:]!r}; {said[:120]!r}; "
   f"{err(r2)[-160:]!r})")

done()
