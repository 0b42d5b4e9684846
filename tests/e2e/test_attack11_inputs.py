#!/usr/bin/env python3
"""springpend tests (issue 28): the attacker's eleventh pass
(doc/notes/2026-11-27/attack11.md), findings 5 and 6, on what a reader opens:
- finding 6 (MEDIUM): every reader but the merge's look opened what a name
  led to before looking at it: a shard's or CSV's `-metadata.json`, a PNG
  or a video linked to /proc/kmsg made a root `sweep --merge`, `scene
  X.csv` or compare take the kernel's log and block, deaf to SIGTERM; a
  link to a device ran its driver's open. Nothing on a kernel's file
  system is read (/proc/self/status stands in for /proc/kmsg here: the
  same file system, and it does not block if this check ever fails), and
  a FIFO or a device is refused without being opened (inotify sees no
  open);
- finding 5: the merge's look at the scene a shard names stat'ed the path,
  then opened it by name: a path flipped between a scene and a device got
  the device opened in a few percent of merges. Nothing but the file
  looked at is opened now (a FIFO stands in for the device; inotify counts
  its opens while a thread flips the two names);
- attack11 #10: a merge out of file descriptors exited 2 (bad input): 1;
- attack12 #1: compare's memory plan (--jobs) read each pair's PNG or
  video header through its own open() after the walk had looked: a folder
  entry swapped for a link to a FIFO (a device's stand-in) was opened.
usage: test_attack11_inputs.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import ctypes
import os
import select
import struct
import threading
import time

import sptest
from sptest import done, err, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack11-inputs")
chaotic = os.path.join(scenes, "chaotic.ini")
default = os.path.join(scenes, "default.ini")
libc = ctypes.CDLL(None, use_errno=True)
IN_OPEN = 0x20
AT_FDCWD = -100
RENAME_EXCHANGE = 2



def link(target, name):
    if os.path.lexists(path(name)):
        os.unlink(path(name))
    os.symlink(target, path(name))


class Opens:
    """Counts the opens of the files at paths (inotify's IN_OPEN; an O_PATH
    handle, which runs no driver's open, is not one)."""

    def __init__(self, *paths):
        self.fd = libc.inotify_init1(os.O_NONBLOCK | os.O_CLOEXEC)
        assert self.fd >= 0, ctypes.get_errno()
        for p in paths:
            assert libc.inotify_add_watch(self.fd, p.encode(), IN_OPEN) >= 0, p

    def count(self, wait=0.2):
        n = 0
        while select.select([self.fd], [], [], wait)[0]:
            data = os.read(self.fd, 65536)
            while data:  # struct inotify_event: wd, mask, cookie, len, name[len]
                _, mask, _, size = struct.unpack("iIII", data[:16])
                n += bool(mask & IN_OPEN)
                data = data[16 + size:]
        return n


args = ["--vary", "initial.angle=1:179:4", "--measure", "lyapunov", "--time", "2"]
for i in (1, 2):
    r = run("sweep", chaotic, *args, "--shard", f"{i}/2", "--csv", f"r{i}.csv", "-q")
    assert r.returncode == 0, err(r)
r = run("still", default, "--at", "0", "--size", "160x90", "-o", "a.png", "-q")
assert r.returncode == 0, err(r)
with open(path("r2.csv-metadata.json"), "rb") as f:
    metadata = f.read()

# ---- finding 6: nothing on a kernel's file system is read --------------------------------
kernel = "/proc/self/status"
link(kernel, "r2.csv-metadata.json")
rc, said = sptest.hangs(run, "sweep", "--merge", "r1.csv", "r2.csv", "-o", "m.png")
ok(rc == 2 and "kernel's file" in said and not os.path.exists(path("m.png")),
   f"sweep --merge: a shard's metadata linked to {kernel} is refused unread, nothing written "
   f"(exit {rc}: {said[-140:]!r})")
with open(path("y.csv"), "w") as f:
    f.write("x\n")
link(kernel, "y.csv-metadata.json")
rc, said = sptest.hangs(run, "scene", "y.csv", "--command")
ok(rc == 2 and "kernel's file" in said,
   f"scene X.csv --command: its metadata linked to {kernel} is refused unread "
   f"(exit {rc}: {said[-140:]!r})")
link(kernel, "k.png")
rc, said = sptest.hangs(run, "compare", "a.png", "k.png")
ok(rc == 2 and "kernel's file" in said,
   f"compare: a PNG named on the command line and linked to {kernel} is refused unread "
   f"(exit {rc}: {said[-140:]!r})")
link(kernel, "k.mp4")
rc, said = sptest.hangs(run, "compare", "k.mp4", "k.mp4")
ok(rc == 2 and "kernel's file" in said,
   f"compare: a video linked to {kernel} is refused unread (exit {rc}: {said[-140:]!r})")

# ---- finding 6: a FIFO (or a device) is refused without being opened ---------------------
os.mkfifo(path("fifo"))
nodes = ["fifo"]
if os.geteuid() == 0:
    os.mknod(path("null"), 0o600 | 0o020000, os.makedev(1, 3))  # as /dev/null
    nodes.append("null")
for node in nodes:
    watch = Opens(path(node))
    link(node, "r2.csv-metadata.json")
    rc, said = sptest.hangs(run, "sweep", "--merge", "r1.csv", "r2.csv", "-o", "m.png")
    link(node, "n.png")
    rc2, said2 = sptest.hangs(run, "compare", "a.png", "n.png")
    opens = watch.count()
    ok(rc == 2 and rc2 == 2 and opens == 0 and "not a regular file" in said and
       "not a regular file" in said2,
       f"a shard's metadata and a PNG linked to a {'FIFO' if node == 'fifo' else 'device node'} "
       f"are refused, and it was opened {opens} times (exit {rc}, {rc2}: {said[-100:]!r})")
os.unlink(path("r2.csv-metadata.json"))
with open(path("r2.csv-metadata.json"), "wb") as f:
    f.write(metadata)
r = run("sweep", "--merge", "r1.csv", "r2.csv", "-o", "m.png", "-q")
ok(r.returncode == 0, f"the same shards, their metadata restored, merge ({err(r)[-120:]!r})")

# attack11 #10: out of descriptors is the run's failure (exit 1), not bad
# input (exit 2, which CI scripts take as "the inputs are wrong")
import resource  # noqa: E402


def few_fds(n):
    def limit():
        resource.setrlimit(resource.RLIMIT_NOFILE, (n, n))
    return limit


codes = {}
for n in (5, 6):
    r = run("sweep", "--merge", "r1.csv", "r2.csv", "-o", "fd.svg", "-q", preexec_fn=few_fds(n))
    codes[n] = (r.returncode, err(r)[-90:])
ok(all(c == 1 and "not the file's fault" in e for c, e in codes.values()) and
   not os.path.exists(path("fd.svg")),
   f"sweep --merge out of file descriptors (ulimit -n 5, 6): exit 1, said as the process's limit, "
   f"nothing written ({codes})")

# ---- finding 5: a path flipped between a scene and a FIFO: the FIFO is never opened ------
with open(chaotic) as f:
    scene_text = f.read()
with open(path("real.ini"), "w") as f:
    f.write(scene_text)
link("real.ini", "sc")
link("fifo", "other")
with open(path("r1.csv-metadata.json")) as f:
    text = f.read()
assert chaotic in text
with open(path("r1.csv-metadata.json"), "w") as f:
    f.write(text.replace(chaotic, path("sc")))
watch = Opens(path("fifo"))
stop = threading.Event()


def flip():
    a, b = path("sc").encode(), path("other").encode()
    while not stop.is_set():
        libc.renameat2(AT_FDCWD, a, AT_FDCWD, b, RENAME_EXCHANGE)


flipper = threading.Thread(target=flip)
flipper.start()
codes = set()
start = time.monotonic()
merges = 0
while merges < 60 and time.monotonic() - start < 60:
    codes.add(run("sweep", "--merge", "r1.csv", "r2.csv", "-o", "m.png", "-q").returncode)
    merges += 1
stop.set()
flipper.join()
opens = watch.count()
ok(opens == 0 and codes <= {0, 2},
   f"{merges} merges while the scene's path flips to a FIFO: the FIFO was opened {opens} times "
   f"(exit statuses {sorted(codes)})")

# ---- attack12 #1: compare's memory plan reads each pair's header: through the
# same opener (a folder entry swapped for a link to a FIFO after the walk
# looked is not opened) ----------------------------------------------------
for d in ("e", "a"):
    os.makedirs(path(d))
    for n in ("x", "z1", "z2", "z3"):
        with open(path("a.png"), "rb") as f, open(path(d, f"{n}.png"), "wb") as g:
            g.write(f.read())
link(path("fifo"), "spare")
watch = Opens(path("fifo"))
stop.clear()


def flip_entry():
    a, b = path("a", "x.png").encode(), path("spare").encode()
    while not stop.is_set():
        libc.renameat2(AT_FDCWD, a, AT_FDCWD, b, RENAME_EXCHANGE)


flipper = threading.Thread(target=flip_entry)
flipper.start()
codes = set()
runs = 0
start = time.monotonic()
while runs < 60 and time.monotonic() - start < 60:
    codes.add(run("compare", "e", "a", "--jobs", "2", "-q").returncode)
    runs += 1
stop.set()
flipper.join()
opens = watch.count()
ok(opens == 0 and codes <= {0, 1, 2},
   f"{runs} folder compares (--jobs 2, which reads each pair's header to plan its memory) while "
   f"a/x.png flips with a link to a FIFO: the FIFO was opened {opens} times "
   f"(exit statuses {sorted(codes)})")
done()
