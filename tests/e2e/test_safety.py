#!/usr/bin/env python3
"""springpend tests: nothing clobbered, nothing lost, nothing hangs (issue 9).
Output targets (devices, FIFOs, stdout, links, concurrent runs, a scene named
like a .part, earlier PNG frames, file size limits, a second Ctrl-C during a
GIF's close, folders), input that was silently wrong (CR-only, BOM, denormal
mass, folders and FIFOs as scenes, mistyped options, a still as MP4), runs
that never ended, stdout that could not be written, reproducible video bytes
and the GIF's memory. Device-node cases need root and are skipped without it.
usage: test_safety.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import glob
import os
import pty
import re
import resource
import select
import shutil
import signal
import stat
import subprocess
import threading
import time

from sptest import done, err, ok, part_files, runner_bytes, setup

exe, src, work, _ = setup("safety", [])
default = os.path.join(src, "..", "scenes", "default.ini")
root = os.geteuid() == 0
SMALL = ["--size", "64x48", "--set", "video.duration=0.1"]


run = runner_bytes(exe, work)
parts = part_files


def path(*names):
    return os.path.join(work, *names)


def file_limit(limit, ignore_xfsz):
    """preexec_fn: a file size limit, with SIGXFSZ ignored or at its default."""
    def set_limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN if ignore_xfsz else signal.SIG_DFL)
    return set_limit


# ---- output targets: devices, FIFOs, stdout, links ----

os.makedirs(path("dev"))
null = path("dev", "null")
mp4dev = path("dev", "clip.mp4")
if root:
    os.mknod(null, 0o666 | stat.S_IFCHR, os.makedev(1, 3))
    os.mknod(mp4dev, 0o666 | stat.S_IFCHR, os.makedev(1, 3))
    r = run("render", default, *SMALL, "--format", "raw", "-o", null, "-q")
    ok(r.returncode == 0 and stat.S_ISCHR(os.stat(null).st_mode) and not parts(path("dev")),
       f"raw frames to a device node are written through it; it stays a device "
       f"(exit {r.returncode}: {err(r)!r})")
    r = run("data", default, "-o", null, "-q")
    ok(r.returncode == 0 and stat.S_ISCHR(os.stat(null).st_mode),
       f"data to a device node: written through, still a device (exit {r.returncode})")
    r = run("render", default, *SMALL, "-o", mp4dev, "-q")
    ok(r.returncode == 2 and "not a regular file" in err(r) and
       stat.S_ISCHR(os.stat(mp4dev).st_mode) and not parts(path("dev")),
       f"an MP4 onto a device node is refused (exit 2) and the node stays "
       f"(exit {r.returncode}: {err(r)!r})")
else:
    for what in ("raw to a device node", "data to a device node", "MP4 onto a device node"):
        ok(True, what, skip="mknod needs root")

# A FIFO target: written through to its reader, and still a FIFO afterwards.
fifo = path("dev", "pipe.csv")
os.mkfifo(fifo)
reader = subprocess.Popen(["cat", fifo], stdout=subprocess.PIPE)
r = run("data", default, "--every", "1", "-o", fifo, "-q")
try:
    got = reader.communicate(timeout=10)[0].decode()
except subprocess.TimeoutExpired:
    reader.kill()
    got = "(the reader never got an end of file)"
ok(r.returncode == 0 and got.startswith("t,x,y") and got.count("\n") == 12 and
   stat.S_ISFIFO(os.stat(fifo).st_mode),
   f"data into a FIFO reaches its reader (11 rows), the FIFO stays (exit {r.returncode}, "
   f"{got.count(chr(10))} lines)")

# A still into a FIFO: with a reader, the reader gets the PNG; without one it
# says it waits for a reader (it used to wait without a word), and Ctrl-C
# stops it (130), the FIFO left a FIFO.
pngfifo = path("dev", "still.png")
os.mkfifo(pngfifo)
reader = subprocess.Popen(["cat", pngfifo], stdout=subprocess.PIPE)
r = run("still", default, "--size", "64x48", "-o", pngfifo, "-q")
try:
    got = reader.communicate(timeout=10)[0]
except subprocess.TimeoutExpired:
    reader.kill()
    got = b""
ok(r.returncode == 0 and got.startswith(b"\x89PNG\r\n\x1a\n") and stat.S_ISFIFO(os.stat(pngfifo).st_mode),
   f"still into a FIFO reaches its reader as a PNG ({len(got)} bytes, exit {r.returncode})")
p = subprocess.Popen([exe, "still", default, "--size", "64x48", "-o", pngfifo, "-q"], cwd=work,
                     stderr=subprocess.PIPE)
said = p.stderr.readline().decode() if select.select([p.stderr], [], [], 20)[0] else ""
p.send_signal(signal.SIGINT)
try:
    rest = p.communicate(timeout=20)[1].decode()
except subprocess.TimeoutExpired:
    p.kill()
    rest = p.communicate()[1].decode() + " (still waiting 20 s after SIGINT)"
ok("is a FIFO with no reader yet: waiting" in said and p.returncode == 130 and
   stat.S_ISFIFO(os.stat(pngfifo).st_mode) and not parts(path("dev")),
   f"still into a FIFO without a reader says so, Ctrl-C stops it (exit {p.returncode}): "
   f"{(said + rest).strip()!r}")

# A link to our own stdout (like /dev/stdout) is written through, not replaced.
out_link = path("dev", "stdout.csv")
os.symlink("/proc/self/fd/1", out_link)
r = run("data", default, "--every", "1", "-o", out_link, "-q", text=True)
ok(r.returncode == 0 and r.stdout.startswith("t,x,y") and os.path.islink(out_link),
   f"-o a link to /proc/self/fd/1 writes to stdout and leaves the link (exit {r.returncode}, "
   f"{len(r.stdout)} bytes)")

# A link to a regular file, or to nothing, is refused before any work: an
# output folder can come from a repository, and `render -o l.mp4` with l.mp4
# -> /etc/passwd used to replace /etc/passwd. Nothing is written, the file
# and the link stay as they were.
real = path("real.csv")
open(real, "w").write("old\n")
os.makedirs(path("links"))
for name, to, args in (("link.csv", "../real.csv", ["data", default, "--every", "1"]),
                       ("clip.mp4", "../real.csv", ["render", default, *SMALL]),
                       ("still.png", "../real.csv", ["still", default, "--size", "64x48"]),
                       ("gone.png", "../nothing.png", ["still", default, "--size", "64x48"]),
                       ("map.png", "../real.csv", ["sweep", default, "--vary", "initial.angle=1:2:2",
                                                   "--measure", "lyapunov", "--time", "2"])):
    link = path("links", name)
    os.symlink(to, link)
    r = run(*args, "-o", link, "-q")
    ok(r.returncode == 2 and "is a symbolic link" in err(r) and os.path.islink(link) and
       os.readlink(link) == to and open(real).read() == "old\n" and
       not os.path.exists(path("nothing.png")) and sorted(os.listdir(path("links"))) ==
       sorted(n for n in os.listdir(path("links")) if os.path.islink(path("links", n))),
       f"{args[0]} -o a symlink to {'nothing' if 'nothing' in to else 'a file'}: refused "
       f"(exit {r.returncode}), the link and its target untouched: {err(r)!r}")

# ---- concurrent runs, a scene named like a .part ----

common = ["--every", "0.0005", "--set", "video.duration=15", "-q"]
r_a = run("data", default, *common, "-o", "a.csv")
r_b = run("data", default, *common, "--set", "initial.angle=20", "-o", "b.csv")
want = {open(path("a.csv"), "rb").read(), open(path("b.csv"), "rb").read()}
same = 0
for attempt in range(3):
    ps = [subprocess.Popen([exe, "data", default, *common, *extra, "-o", "same.csv"], cwd=work,
                           stderr=subprocess.PIPE)
          for extra in ([], ["--set", "initial.angle=20"])]
    codes = [p.wait(timeout=60) for p in ps]
    same += codes == [0, 0] and open(path("same.csv"), "rb").read() in want and not parts(work)
ok(r_a.returncode == 0 and len(want) == 2 and same == 3,
   f"two data runs to one target at once: both exit 0, the file is one whole run's "
   f"({same} of 3 tries), no .part left")

scene_part = path("clip.raw.part")
shutil.copy(default, scene_part)
before = open(scene_part).read()
r = run("render", scene_part, *SMALL, "--format", "raw", "-o", path("clip.raw"), "-q")
ok(r.returncode == 0 and os.path.exists(scene_part) and open(scene_part).read() == before,
   f"a scene named clip.raw.part survives a render to -o clip.raw (exit {r.returncode}: "
   f"{err(r)!r})")
if os.path.exists(scene_part):
    os.remove(scene_part)

# ---- failures remove only what the run created ----

os.makedirs(path("seq"))
r = run("render", default, *SMALL, "-o", path("seq", "%03d.png"), "-q")
earlier = {n: open(path("seq", n), "rb").read() for n in sorted(os.listdir(path("seq")))}
r2 = run("render", default, "--size", "640x360", "--set", "video.duration=0.1", "-o",
         path("seq", "%03d.png"), "-q", preexec_fn=file_limit(2000, True))
now = {n: open(path("seq", n), "rb").read() for n in sorted(os.listdir(path("seq")))}
ok(r.returncode == 0 and len(earlier) == 6 and r2.returncode == 1 and now == earlier,
   f"a failed re-render (file size limit) keeps the earlier run's {len(earlier)} frames "
   f"it never rewrote (exit {r2.returncode}; now {len(now)} files)")

r = run("data", default, "--every", "0.001", "-o", path("fsize", "x.csv"),
        preexec_fn=file_limit(4096, False))
ok(r.returncode == 1 and "File too large" in err(r) and not os.path.exists(path("fsize")),
   f"ulimit -f with SIGXFSZ at its default: exit 1 saying 'File too large', no .part, no "
   f"folder (exit {r.returncode}: {err(r)!r})")

r = run("data", default, "--set", "integrator.dt=0.5", "-o", path("new", "deep", "blow.csv"))
ok(r.returncode == 3 and not os.path.exists(path("new")),
   f"a failed run removes the empty folders it created (exit {r.returncode}, "
   f"new/ {'left' if os.path.exists(path('new')) else 'gone'})")

# A second Ctrl-C while the GIF is being written (its close does the work).
gif = path("gif", "long.gif")
p = subprocess.Popen([exe, "render", default, "--size", "480x270", "--set", "video.duration=30",
                      "-o", gif, "-q"], stderr=subprocess.PIPE, text=True)
deadline = time.monotonic() + 60
while not glob.glob(glob.escape(gif) + "*.part") and p.poll() is None and \
        time.monotonic() < deadline:
    time.sleep(0.05)
time.sleep(2.0)
p.send_signal(signal.SIGINT)
time.sleep(0.15)  # the render loop stops within a frame; then close maps every frame
p.send_signal(signal.SIGINT)
e = p.communicate(timeout=60)[1]
ok(p.returncode == 130 and not parts(path("gif")) and "second signal" in e,
   f"a second SIGINT during a GIF's close leaves no .part (exit {p.returncode}, left "
   f"{parts(path('gif'))}: {e.strip()!r})")

# ---- input that was silently wrong ----

def scene(name, data):
    with open(path(name), "wb") as f:
        f.write(data)
    return path(name)


r = run("info", scene("cr.ini", b"[pendulum]\rmass = 2\r[video]\rduration = 3\r"), text=True)
ok(r.returncode == 0 and "m = 2 kg" in r.stdout and "3 s at" in r.stdout,
   f"CR-only line endings: every key read (exit {r.returncode}: {r.stdout[:120]!r})")
r = run("info", scene("bom.ini", b"\xef\xbb\xbf[pendulum]\nmass = 2\n"), text=True)
ok(r.returncode == 0 and "m = 2 kg" in r.stdout,
   f"a UTF-8 BOM is accepted (exit {r.returncode}: {err(r)!r})")
r = run("info", default, "--set", "pendulum.mass=4.9e-324", text=True)
ok(r.returncode == 2 and "mass" in err(r) and not re.search(r"nan|inf", err(r), re.I),
   f"a denormal mass is refused with finite numbers (exit {r.returncode}: {err(r)!r})")
r = run("info", work, text=True)
ok(r.returncode == 2 and "is a folder" in err(r) and "9223372036854775807" not in err(r),
   f"a folder as the scene: exit 2, 'is a folder' ({err(r)!r})")
lonely = path("lonely.ini")
os.mkfifo(lonely)
try:
    r = run("info", lonely, text=True, timeout=30)
    ok(r.returncode == 2 and "FIFO" in err(r),
       f"a FIFO nobody writes to: exit 2 after a bounded wait ({err(r)!r})")
except subprocess.TimeoutExpired:
    ok(False, "a FIFO nobody writes to: springpend hung")
rfd, wfd = os.pipe()
threading.Thread(target=lambda: (os.write(wfd, open(default, "rb").read()), os.close(wfd)),
                 daemon=True).start()
r = subprocess.run([exe, "info", f"/dev/fd/{rfd}"], capture_output=True, text=True,
                   pass_fds=[rfd], timeout=30)
os.close(rfd)
ok(r.returncode == 0 and "omega_spring" in r.stdout,
   f"a pipe as the scene (like <(cat x)) is read as a stream (exit {r.returncode}: {err(r)!r})")

for args, want, what in [
    (["render", default, "--set", "video.duration", "5"], "'='", "--set without '='"),
    (["still", default, "--at"], "'--at' needs a value", "--at without its value"),
    (["still", default, "--size", "99999999999x1"], "99999999999", "--size beyond int"),
]:
    r = run(*args, text=True)
    ok(r.returncode == 2 and want in err(r), f"{what}: exit 2, says {want} ({err(r)!r})")
r = run("info", default, "--set", "video.speed=1e-300", text=True)
ok(r.returncode == 2 and max(map(len, re.findall(r"\d+", err(r)))) < 20,
   f"speed 1e-300: the frame count is printed short ({err(r)[:160]!r})")
r = run("still", default, *SMALL, "-o", path("still.mp4"), text=True)
ok(r.returncode == 2 and ".png" in err(r) and not os.path.exists(path("still.mp4")),
   f"still -o still.mp4 is refused with the still formats ({err(r)!r})")

# ---- runs that never ended ----

for args, what in [
    (["data", default, "--set", "pendulum.stiffness=1e12", "--set", "pendulum.mass=1e-6",
      "--set", "integrator.method=dop853", "-o", path("stiff.csv")], "a stiff adaptive run"),
    (["still", default, "--at", "1e9", "--set", "integrator.method=dop853", "-o",
      path("far.png")], "still --at 1e9 (dop853)"),
]:
    try:
        r = run(*args, text=True, timeout=60)
        ok(r.returncode == 2 and "at most 1e+10" in err(r) and not parts(work),
           f"{what}: refused up front with the estimate ({err(r)!r})")
    except subprocess.TimeoutExpired:
        ok(False, f"{what}: still running after 60 s")

def on_terminal(args, marker):
    """Runs springpend with a terminal as stdout and stderr until it draws
    marker (at most 60 s), then sends SIGINT: (what it drew, exit status)."""
    master, slave = pty.openpty()
    p = subprocess.Popen([exe, *args], stdin=subprocess.DEVNULL, stdout=slave, stderr=slave, cwd=work)
    os.close(slave)
    seen, deadline = b"", time.monotonic() + 60
    while marker not in seen and time.monotonic() < deadline and p.poll() is None:
        if select.select([master], [], [], 0.5)[0]:
            try:
                seen += os.read(master, 4096)
            except OSError:
                break
    p.send_signal(signal.SIGINT)
    p.wait(timeout=30)
    os.close(master)
    return seen, p.returncode


# A long integration draws its progress on a terminal.
seen, _ = on_terminal(["data", default, "--set", "video.duration=1e6", "--fps", "0.01",
                       "-o", path("long.csv")], b"data: t = ")
ok(b"data: t = " in seen and b"ETA" in seen and b"steps" in seen,
   f"a long integration says how long and draws progress on a terminal ({seen[-160:]!r})")

# So does an ensemble's pre-pass of its members (it used to run silent).
seen, code = on_terminal(["still", default, "--set", "ensemble.count=1000", "--set",
                          "video.duration=1000", "--fps", "1", "--size", "64x48", "-o",
                          path("ens.png")], b"ensemble pre-pass: t = ")
ok(b"ensemble pre-pass: t = " in seen and b"ETA" in seen and code == 130 and
   not os.path.exists(path("ens.png")),
   f"an ensemble's pre-pass draws its progress on a terminal, Ctrl-C stops it ({seen[-200:]!r})")

# ---- stdout that cannot be written ----

with open("/dev/full", "w") as full:
    for args in (["data", default, "-o", "-"], ["keys"], ["info", default]):
        r = run(*args, stdout=full, stderr=subprocess.PIPE, capture_output=False, text=True)
        ok(r.returncode == 1 and "No space left on device" in r.stderr,
           f"{' '.join(args[:1])} > /dev/full: exit 1 with a message ({r.stderr.strip()!r})")
p = subprocess.Popen([exe, "data", default, "-o", "-", "--every", "0.001"],
                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=work)
first = p.stdout.readline()
p.stdout.close()
e = p.stderr.read().decode()
p.wait(timeout=30)
ok(first.startswith(b"t,x,y") and p.returncode == 1 and "closed the pipe" in e,
   f"data | head -1: exit 1, says the reader closed the pipe ({p.returncode}: {e.strip()!r})")

# ---- reproducible video bytes, flat GIF memory ----

cpus = sorted(os.sched_getaffinity(0))
for ext in ("mp4", "webm"):
    args = ["render", default, "--size", "320x240", "--set", "video.duration=1", "-q"]
    r1 = run(*args, "-o", path(f"det1.{ext}"))
    # LeakSanitizer's tracer sometimes dies on one pinned CPU ("fatal error"):
    # no leak check for this run in a sanitizer build.
    asan = os.environ.get("ASAN_OPTIONS", "")
    r2 = run(*args, "-o", path(f"det2.{ext}"),
             preexec_fn=lambda: os.sched_setaffinity(0, cpus[:1]),
             env=dict(os.environ, ASAN_OPTIONS=(asan + ":" if asan else "") + "detect_leaks=0"))
    same = r1.returncode == 0 and r2.returncode == 0 and \
        open(path(f"det1.{ext}"), "rb").read() == open(path(f"det2.{ext}"), "rb").read()
    ok(same, f"{ext}: the same bytes on all {len(cpus)} CPUs and on one (exit "
       f"{r1.returncode}, {r2.returncode}: {err(r1)[-200:]!r} {err(r2)[-200:]!r})",
       skip=None if len(cpus) > 1 or ext == "webm" else "one CPU only")


def gif_anon_peak(seconds):
    """Exit status and peak anonymous memory (MiB) of a GIF render: sampled
    from /proc, since ru_maxrss also counts the shared libraries' pages,
    which depend on what else the machine runs."""
    p = subprocess.Popen([exe, "render", default, "--size", "320x240", "--fps", "30",
                          "--set", f"video.duration={seconds}", "-q", "-o",
                          path(f"mem{seconds}.gif")], cwd=work)
    peak = 0
    while p.poll() is None:
        try:
            with open(f"/proc/{p.pid}/status") as f:
                peak = max([peak] + [int(l.split()[1]) for l in f if l.startswith("RssAnon")])
        except OSError:
            pass
        time.sleep(0.02)
    return p.returncode, peak / 1024


# A sanitizer's allocator keeps freed memory in quarantine: nothing to see.
sanitized = b"__asan_init" in open(exe, "rb").read()
(c1, m1), (c2, m2) = ((0, 0), (0, 0)) if sanitized else (gif_anon_peak(2), gif_anon_peak(10))
ok(c1 == 0 and c2 == 0 and m2 - m1 < 25,
   f"GIF memory is flat with length: peak anonymous memory 2 s {m1:.0f} MiB, 10 s "
   f"{m2:.0f} MiB (holding the 240 more frames would take {240 * 320 * 240 * 4 / 2**20:.0f} "
   f"MiB)", skip="a sanitizer build" if sanitized else None)

done()
