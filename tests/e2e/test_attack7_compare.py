#!/usr/bin/env python3
"""springpend tests (issue 28): the attacker's seventh pass
(doc/notes/2026-11-27/attack7.md) on compare and its neighbours, each check
run as the attacker ran it (smaller images, a few seconds at most):
- finding 22: compare --jobs under a memory limit counted no thread's own
  cost (stack, malloc arena), so tiny images came out "missing or
  unreadable" (exit 2) or libpng aborted (exit 134); failed allocations were
  input errors and messages lost their arguments;
- finding 14: the memory cap counted PNGs only: videos ran every thread and
  came out "cannot decode" (exit 2);
- finding 26: the default thread counts (compare --jobs, sweep, the PNG
  sequence's writers) counted the machine's CPUs, not those the process may
  use (taskset -c 0 ran every core's threads on one);
- finding 8: `keys --` was refused;
- finding 16: a check of several keys blamed the scene file for a value that
  came from --set;
- finding 17: scene --help and its refusal said a GIF carries a record;
- finding 20: compare --approve interrupted printed an ordinary FAIL, and
  took --json, --report, --env, --jobs... silently;
- finding 11: a baseline NAME.KEY.KEY.png beside NAME.KEY.png was in
  neither list: never compared, never reported;
- finding 27: --update all --env KEY never retired NAME.KEY.png once the
  plain baseline matched again, so the old look passed for ever.
(finding 4, the cgroup memory limit, is test memory-limit: a made-up tree.)
usage: test_attack7_compare.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import os
import re
import resource
import shutil
import struct
import subprocess
import time
import zlib

import sptest
from sptest import done, err, ok

exe, src, work, _ = sptest.setup("attack7_compare", [])
run = sptest.runner_bytes(exe, work)
default = os.path.join(src, "..", "scenes", "default.ini")
chaotic = os.path.join(src, "..", "scenes", "chaotic.ini")


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


def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


def flat_png(p, w, h, stripe):
    """A w x h RGB PNG, flat but for a stripe every 97 rows (small files)."""
    row0, row1 = b"\0" + bytes((10, 20, 30)) * w, b"\0" + bytes(stripe) * w
    raw = b"".join(row1 if y % 97 == 0 else row0 for y in range(h))
    write(p, b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
          + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def address_limit(kb):
    """preexec_fn: ulimit -v kb (RLIMIT_AS) in the child only."""
    return lambda: resource.setrlimit(resource.RLIMIT_AS, (kb << 10, kb << 10))


sanitized = b"__asan_init" in read(exe)  # a sanitizer's shadow memory needs no limit
for t, name in ((1, "b1.png"), (2, "b2.png")):  # the attacker's 320x180 stills
    r = run("still", default, "--at", str(t), "--size", "320x180", "-q", "-o", name)
    assert r.returncode == 0, err(r)
b1, b2 = path("b1.png"), path("b2.png")


def summary(r):
    lines = r.stdout.decode(errors="replace").strip().splitlines()
    return lines[-1] if lines else ""


# ---- finding 22: --jobs 256 of tiny images under ulimit -v 600000 -------------------
for i in range(300):
    copy(b1, path("pj", "e", f"{i}.png"))
    copy(b2, path("pj", "a", f"{i}.png"))
if not sanitized:
    # main: rc 2 ("6 compared ... 294 missing or unreadable") or 134 (libpng's
    # abort), stderr full of "%s: cannot open: %s"
    runs = [run("compare", "pj/e", "pj/a", "--jobs", "256", preexec_fn=address_limit(600000),
                timeout=120) for _ in range(3)]
    ok(all(r.returncode == 1 and "300 compared, 0 passed, 300 failed, 0 missing or unreadable"
           in summary(r) for r in runs)
       and all("%s" not in err(r) and "--jobs 256: each thread holds" in err(r)
               and "of its own (stack, malloc arena)" in err(r) for r in runs),
       f"--jobs 256 of 300 tiny pairs under ulimit -v 600000: every image compared, rc 1, "
       f"the threads cut for their own cost, said once "
       f"({[r.returncode for r in runs]} {summary(runs[0])} | {err(runs[0])[:300]})")
else:
    ok(True, "compare --jobs 256 under ulimit -v", skip="a sanitizer build")

# one pair too large for the limit even alone: "out of memory", exit 1, said once;
# never "missing or unreadable" (exit 2), never a libpng abort, whatever the point
# where the memory runs out
for i in range(2):
    flat_png(path("big", "e", f"p{i}.png"), 2000, 2000, (200, 200, 200))
    flat_png(path("big", "a", f"p{i}.png"), 2000, 2000, (100, 200, 200))
if not sanitized:
    seen, bad, oom = [], [], 0
    for kb in range(14000, 46000, 2000):
        r = run("compare", "big/e", "big/a", "--jobs", "1", preexec_fn=address_limit(kb),
                timeout=60)
        line, e = summary(r), err(r)
        seen.append((kb, r.returncode))
        said = e.count("out of memory")
        oom += "out of memory" in line
        if (r.returncode != 1 or "%s" in e or "%d" in e or said > 1
                or ("missing or unreadable" in line and not re.search(r" 0 missing or unreadable", line))
                or ("out of memory" in line and said != 1)):
            bad.append((kb, r.returncode, line, e[:300]))
    ok(not bad and oom > 0,
       f"a 2000x2000 pair under ulimit -v 14-44 MB: exit 1 at every limit, 'out of memory' "
       f"said once where it ran out ({oom} runs), never an unreadable input nor an abort "
       f"({bad[:2] or seen})")
else:
    ok(True, "compare under a tight ulimit -v", skip="a sanitizer build")

# the JSON says which records ran out of memory
if not sanitized:
    r = run("compare", "big/e", "big/a", "--jobs", "1", "--json", preexec_fn=address_limit(24000))
    try:
        doc = json.loads(r.stdout)
    except ValueError:
        doc = {}
    counts = doc.get("counts", {})
    ok(r.returncode == 1 and counts.get("errors") == 0 and counts.get("out_of_memory", 0) >= 1
       and any(x.get("out_of_memory") for x in doc.get("results", [])),
       f"--json under ulimit -v 24 MB: out_of_memory counted apart from errors "
       f"(rc {r.returncode}, {counts}, {err(r)[:200]})")
else:
    ok(True, "compare --json under a tight ulimit -v", skip="a sanitizer build")

# ---- finding 14: videos are counted in the memory cap ---------------------------------
for name, sets in (("v1.mp4", []), ("v2.mp4", ["--set", "initial.angle=12"])):
    r = run("render", default, "--size", "640x360", "--fps", "10", "--set", "video.duration=0.3",
            *sets, "-q", "-o", name, timeout=120)
    assert r.returncode == 0, err(r)
for i in range(6):
    copy(path("v1.mp4"), path("vj", "e", f"{i}.mp4"))
    copy(path("v2.mp4"), path("vj", "a", f"{i}.mp4"))
if not sanitized:
    # main: "cannot decode" or "cannot read", "3 compared ... 3 missing or unreadable", rc 2
    r = run("compare", "vj/e", "vj/a", "--jobs", "6", preexec_fn=address_limit(500000),
            timeout=120)
    ok(r.returncode == 1 and "6 compared, 0 passed, 6 failed, 0 missing or unreadable" in summary(r)
       and re.search(r"--jobs 6: each thread holds up to \d+ MB for the largest image \(0\.2 Mpx\)",
                     err(r)),
       f"6 video pairs (640x360) on --jobs 6 under ulimit -v 500000: the videos' decoders are "
       f"counted, every pair compared, rc 1 (rc {r.returncode}: {summary(r)} | {err(r)[:300]})")
else:
    ok(True, "compare videos --jobs under ulimit -v", skip="a sanitizer build")
r = run("compare", "vj/e", "vj/a", "--jobs", "2", timeout=120)
ok(r.returncode == 1 and "--jobs" not in err(r),
   f"without a limit, 2 threads of 640x360 videos run as asked, nothing said ({err(r)[:200]})")

# ---- finding 26: the CPUs the process may use ---------------------------------------
def most_tasks(args, cpus):
    """Runs springpend args under taskset -c cpus: (rc, the most threads it
    had at once, sampled from /proc/PID/task every 10 ms)."""
    env = dict(os.environ, LP_NUM_THREADS="1")  # llvmpipe's threads: as many for both
    p = subprocess.Popen(["taskset", "-c", cpus, exe, *args], cwd=work, env=env,
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    most, t0 = 0, time.time()
    while p.poll() is None and time.time() - t0 < 60:
        try:
            most = max(most, len(os.listdir(f"/proc/{p.pid}/task")))
        except OSError:
            pass
        time.sleep(0.01)
    p.communicate(timeout=60)
    return p.returncode, most


allowed = sorted(os.sched_getaffinity(0))
if not shutil.which("taskset") or len(allowed) < 2:
    for what in ("sweep", "PNG sequence", "compare --jobs"):
        ok(True, f"{what} under taskset -c 0", skip="taskset missing or a single CPU")
else:
    two = f"{allowed[0]},{allowed[1]}"
    # main: 3 threads (2 workers) on the one CPU allowed; T = 100 s, about 0.2 s of
    # work, so that the 10 ms samples see every worker
    sweep = ["sweep", chaotic, "--vary", "initial.angle=1:179:16", "--vary",
             "initial.length=0.8:1.2:8", "--measure", "lyapunov", "--time", "100", "-q",
             "-o", "-"]
    (r1, t1), (r2, t2) = most_tasks(sweep, str(allowed[0])), most_tasks(sweep, two)
    for _ in range(3):  # sampled: on a loaded machine a 10 ms sample can miss a worker
        if t1 < t2:
            break
        r2, t = most_tasks(sweep, two)
        t2 = max(t2, t)
    ok(r1 == 0 and r2 == 0 and t1 < t2,
       f"sweep under taskset -c {allowed[0]} runs fewer workers than under taskset -c {two} "
       f"(most threads at once: {t1} and {t2})")
    seq = ["render", default, "--size", "320x180", "--fps", "25", "--set", "video.duration=4",
           "-q", "-o", "sq/f%05d.png"]
    (r1, t1) = most_tasks(seq, str(allowed[0]))
    shutil.rmtree(path("sq"), ignore_errors=True)
    (r2, t2) = most_tasks(seq, two)
    for _ in range(3):
        if t1 < t2:
            break
        shutil.rmtree(path("sq"), ignore_errors=True)
        r2, t = most_tasks(seq, two)
        t2 = max(t2, t)
    ok(r1 == 0 and r2 == 0 and t1 < t2,
       f"a PNG sequence under taskset -c {allowed[0]} runs fewer writers than under taskset -c "
       f"{two} (most threads at once: {t1} and {t2})")
    if not sanitized:
        def pinned(cpus, kb):
            def f():
                os.sched_setaffinity(0, cpus)
                resource.setrlimit(resource.RLIMIT_AS, (kb << 10, kb << 10))
            return f
        # a limit that fits one thread: the default --jobs is said when cut
        r1 = run("compare", "big/e", "big/a", preexec_fn=pinned({allowed[0]}, 120000))
        r2 = run("compare", "big/e", "big/a", preexec_fn=pinned(set(allowed[:2]), 120000))
        ok(r1.returncode == 1 and "--jobs" not in err(r1) and r2.returncode == 1
           and "--jobs 2:" in err(r2),
           f"compare's default --jobs is the CPUs the process may use: 1 under one CPU, 2 "
           f"under two ({err(r1)[:150]} | {err(r2)[:150]})")
    else:
        ok(True, "compare --jobs under taskset", skip="a sanitizer build")

# ---- finding 8: `keys --` -------------------------------------------------------------
r = run("keys", "--")
r2 = run("keys", "--", "x")
ok(r.returncode == 0 and b"[pendulum]" in r.stdout and r2.returncode == 2
   and "not 'x'" in err(r2),
   f"keys -- prints the keys (rc {r.returncode}: {err(r)[:120]}); an operand after it is "
   f"refused (rc {r2.returncode})")

# ---- finding 16: a check of several keys names the origin of the key it asks to change -
r = run("still", default, "--at", "1", "--set", "pendulum.mass=1e6", "--set",
        "pendulum.stiffness=1e-300", "-o", "k16.png")
r2 = run("still", default, "--at", "1", "--set", "pendulum.stiffness=1e12", "--set",
         "pendulum.mass=1e-300", "-o", "k16.png")
r3 = run("still", default, "--at", "1", "--set", "video.duration=1e-9", "-o", "k16.png")
write(path("k16.ini"), "[pendulum]\nmass = 1e6\nstiffness = 1e-300\n")
r4 = run("still", "k16.ini", "--at", "1", "-o", "k16.png")
ok(r.returncode == 2 and err(r).startswith("--set pendulum.stiffness=1e-300: pendulum.stiffness")
   and r2.returncode == 2 and err(r2).startswith("--set pendulum.mass=1e-300: pendulum.mass")
   and r3.returncode == 2 and err(r3).startswith("--set video.duration=1e-9: ")
   and r4.returncode == 2 and err(r4).startswith("k16.ini:3: pendulum.stiffness")
   and not os.path.exists(path("k16.png")),
   f"stiffness/mass and frame-count checks name the --set (or FILE:LINE) of the key to change "
   f"({err(r)[:80]} | {err(r2)[:80]} | {err(r3)[:60]} | {err(r4)[:60]})")

# ---- finding 17: a GIF carries no record, and scene says so ----------------------------
r = run("render", default, "--size", "160x90", "--fps", "10", "--set", "video.duration=0.3",
        "-q", "-o", "g.gif", timeout=120)
assert r.returncode == 0, err(r)
help_text = run("scene", "--help").stdout.decode()
r = run("scene", "g.gif")
r2 = run("scene", "g.gif", "--command")
ok("GIF (the same" not in help_text and "A GIF is\nthe one output that records neither" in help_text
   and r.returncode == 2 and "a GIF never" in err(r) and r2.returncode == 2
   and "but a GIF" in err(r2),
   f"scene --help and both refusals say a GIF carries no record ({err(r)[-90:]} | "
   f"{err(r2)[-70:]})")

# ---- finding 20: --approve interrupted, --approve with options it does not use --------
for i in range(150):
    copy(path("big", "e", "p0.png"), path("apc", f"{i:03d}.png"))
p = subprocess.Popen([exe, "compare", "--approve", "apc", "apb"], cwd=work,
                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
t0 = time.time()
while time.time() - t0 < 30 and p.poll() is None and not (
        os.path.isdir(path("apb")) and os.listdir(path("apb"))):
    time.sleep(0.005)
p.send_signal(15)  # the first copy is in place: stop it there
out, e = p.communicate(timeout=60)
last = (out.strip().splitlines() or [""])[-1]
m = re.match(r"interrupted: (\d+) added, 0 replaced, 0 unchanged, (\d+) not approved", last)
ok(p.returncode == 143 and m and "FAIL" not in last
   and int(m.group(1)) + int(m.group(2)) == 150
   and int(m.group(1)) == len(os.listdir(path("apb"))),
   f"--approve stopped by SIGTERM says it was interrupted and how many were left, rc 143 "
   f"(rc {p.returncode}: {last})")
copy(b1, path("apc2", "x.png"))
r = run("compare", "--approve", "apc2", "apb2", "--report", "r.html", "--junit", "j.xml",
        "--summary", "s.md", "--env", "llvm", "--diff", "dd", "--jobs", "3", "--json")
names = ("--diff", "--json", "--report", "--junit", "--summary", "--jobs")
# --env it takes since attack12 #15 (it lets an alternative NAME.KEY.png be approved)
listed = re.search(r"but --env KEY: (.*?) given", err(r))
ok(r.returncode == 2 and all(n in err(r) for n in names) and listed
   and "--env" not in listed.group(1)
   and not os.path.exists(path("apb2"))
   and not any(os.path.exists(path(f)) for f in ("r.html", "j.xml", "s.md", "dd")),
   f"--approve with options it does not use: refused, each named, nothing written "
   f"(rc {r.returncode}: {err(r)[:200]})")
r = run("compare", "--approve", "apc2", "apb2")
ok(r.returncode == 0 and os.path.exists(path("apb2", "x.png")),
   f"--approve alone still copies ({err(r)[:100]})")

# ---- finding 11: NAME.KEY.KEY.png beside NAME.KEY.png is reported -----------------------
write(path("ev", "e", "compare.ini"), "envs = llvm\n")
copy(b1, path("ev", "e", "x.png"))
copy(b2, path("ev", "e", "x.llvm.png"))
copy(b2, path("ev", "e", "x.llvm.llvm.png"))
copy(b1, path("ev", "a", "x.png"))
r = run("compare", "ev/e", "ev/a", "--json")
try:
    recs = {x["name"]: x for x in json.loads(r.stdout)["results"]}
except (ValueError, KeyError):
    recs = {}
nested = recs.get("x.llvm.llvm.png", {})
ok(r.returncode == 2 and nested.get("verdict") == "error"
   and "alternative of x.llvm.png, which is an alternative itself" in (nested.get("error") or "")
   and recs.get("x.png", {}).get("verdict") == "pass",
   f"x.llvm.llvm.png beside the alternative x.llvm.png: an error naming it, rc 2 "
   f"(rc {r.returncode}: {nested.get('error')})")
r = run("compare", "ev/e", "ev/a", "--update", "all")
ok(os.path.exists(path("ev", "e", "x.llvm.llvm.png")) and b"x.llvm.llvm.png" in r.stdout,
   f"--update all leaves x.llvm.llvm.png in place and names it ({summary(r)})")

# ---- finding 27: --update all --env KEY retires an alternative the plain one matches ----
write(path("eu", "e", "compare.ini"), "envs = llvm\n")
copy(b1, path("eu", "e", "x.png"))
copy(b2, path("eu", "a", "x.png"))
r1 = run("compare", "eu/e", "eu/a", "--update", "all", "--env", "llvm")
added = os.path.exists(path("eu", "e", "x.llvm.png"))
copy(b1, path("eu", "a", "x.png"))  # llvm renders the plain look again
r2 = run("compare", "eu/e", "eu/a", "--update", "all", "--env", "llvm")
copy(b2, path("eu", "a", "x.png"))  # a regression to the old llvm look
r3 = run("compare", "eu/e", "eu/a")
ok(added and r2.returncode == 0 and not os.path.exists(path("eu", "e", "x.llvm.png"))
   and b"removed eu/e/x.llvm.png: llvm now matches x.png" in r2.stdout and r3.returncode == 1,
   f"--update all --env llvm removes x.llvm.png once x.png matches, and the old look then "
   f"fails (rc {r2.returncode}, {r3.returncode}: {r2.stdout.decode()[:160]})")

done()
