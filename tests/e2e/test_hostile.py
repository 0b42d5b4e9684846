#!/usr/bin/env python3
"""springpend tests: hostile inputs on compare's reports and on the process
(issue 28). Each check is a class of attack, run as an attacker would: FIFOs,
devices (mknod, in a temporary folder, never the real /dev) and symbolic
links named *.png; file names and PNG text that XML, JUnit readers and
terminals take for markup; a compressed-text bomb; a run interrupted half
way; a report aimed at a baseline; links that --update would write through;
overlapping masks and a key set twice in compare.ini; stdout on a full
device; the signals that used to leave .part files. Device-node checks need
root and are skipped without it.
usage: test_hostile.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import base64
import json
import os
import re
import resource
import shutil
import signal
import struct
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
import zlib

import sptest
from sptest import done, skip


def ok(cond, what):
    """sptest.ok on one line: messages here quote multi-line output."""
    return sptest.ok(cond, what.replace("\n", " | "))


exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "hostile"))
default = os.path.join(src, "..", "scenes", "default.ini")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
root = os.geteuid() == 0


def run(*args, timeout=60, cwd=None, **kw):
    kw.setdefault("capture_output", True)
    return subprocess.run([exe, *args], cwd=cwd or work, timeout=timeout, **kw)


def path(*names):
    return os.path.join(work, *names)


def fresh(name):
    """An empty folder under work, with base/ and act/ in it."""
    d = path(name)
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(os.path.join(d, "base"))
    os.makedirs(os.path.join(d, "act"))
    return d


def parts(folder):
    return [n for n in os.listdir(folder) if ".part" in n]


def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png(file, w=16, h=12, level=128, extra=b""):
    """An RGB PNG of one grey level, written by hand (independent of springpend)."""
    raw = b"".join(b"\0" + bytes([level]) * 3 * w for _ in range(h))
    with open(file, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + extra + chunk(b"IDAT", zlib.compress(raw, 1)) + chunk(b"IEND", b""))


def itxt(key, text):
    return chunk(b"iTXt", key.encode() + b"\0\0\0\0\0" + text.encode("utf-8"))


def b64(data):
    return base64.b64encode(data).decode()


# ---- the HTML report embeds only images ----
d = fresh("leak")
secret = b"GITHUB_TOKEN=ghp_secretsecretsecret\n"
open(os.path.join(d, "secret.txt"), "wb").write(secret)
open(os.path.join(d, "base", "notes.txt"), "wb").write(secret)
for n in ("out.png", "in.png", "ok.png"):
    png(os.path.join(d, "act", n))
png(os.path.join(d, "base", "ok.png"))
os.symlink("../secret.txt", os.path.join(d, "base", "out.png"))  # out of the folder
os.symlink("notes.txt", os.path.join(d, "base", "in.png"))       # inside, not a PNG
r = run("compare", "base", "act", "--report", "r.html", cwd=d)
html = open(os.path.join(d, "r.html")).read() if os.path.exists(os.path.join(d, "r.html")) else ""
ok(r.returncode == 2 and html and b64(secret) not in html and "GITHUB_TOKEN" not in html
   and b64(secret)[:-4] not in html,
   f"--report embeds no secret behind a *.png link (exit {r.returncode})")
ok("not inside base" in r.stdout.decode() and "not read" in r.stdout.decode(),
   f"a link out of the compared folder is refused, saying so: {r.stdout.decode().strip()[:300]}")
ok(len(re.findall(r'src="data:image/png;base64,', html)) == 2 and "not shown" in html,
   "the PNGs that were read are embedded (ok.png once: its pixels are identical; in.png's "
   "actual), the rest named")

# A compare.ini that links out of the folder is not read: its lines would be
# quoted in messages (a token file's keys in a CI log).
os.unlink(os.path.join(d, "base", "out.png"))
os.symlink("../secret.txt", os.path.join(d, "base", "compare.ini"))
r = run("compare", "base", "act", cwd=d)
ok(r.returncode == 2 and "compare.ini is a link to" in r.stderr.decode()
   and "GITHUB_TOKEN" not in r.stderr.decode() + r.stdout.decode(),
   f"a compare.ini linking out of the folder is refused unread ({r.stderr.decode().strip()})")

# ---- FIFOs and devices named *.png do not hang or fill the report ----
d = fresh("fifo")
png(os.path.join(d, "act", "f.png"))
os.mkfifo(os.path.join(d, "base", "f.png"))
try:
    r = run("compare", "base", "act", "--report", "r.html", timeout=20, cwd=d)
    ok(r.returncode == 2 and os.path.getsize(os.path.join(d, "r.html")) < 100000,
       f"a FIFO named *.png: the report is written, not blocked (exit {r.returncode})")
except subprocess.TimeoutExpired:
    ok(False, "a FIFO named *.png: the report is written, not blocked (hung)")


def limit_fsize(n):
    def f():
        resource.setrlimit(resource.RLIMIT_FSIZE, (n, n))
    return f


if root:
    d = fresh("chardev")
    png(os.path.join(d, "act", "z.png"))
    os.mknod(os.path.join(d, "base", "z.png"), 0o666 | 0o020000, os.makedev(1, 5))  # zero
    t0 = time.monotonic()
    try:
        r = run("compare", "base", "act", "--report", "r.html", timeout=20, cwd=d,
                preexec_fn=limit_fsize(1 << 20))
        ok(r.returncode == 2 and os.path.getsize(os.path.join(d, "r.html")) < 100000
           and not parts(d),
           f"a character device (zero) named *.png, under a 1 MiB file size limit: the "
           f"report is small and whole, no .part (exit {r.returncode}, "
           f"{time.monotonic() - t0:.1f} s)")
    except subprocess.TimeoutExpired:
        ok(False, "a character device named *.png: the report is written (it grew until "
           "killed)")
    for n in parts(d):
        os.unlink(os.path.join(d, n))
else:
    skip("a character device named *.png", "mknod needs root")

# Every write of the report is checked: a file size limit below its size.
d = fresh("fsize")
for n in ("a", "b"):
    png(os.path.join(d, "base", n + ".png"), 256, 256, 10)
    png(os.path.join(d, "act", n + ".png"), 256, 256, 200)
r = run("compare", "base", "act", "--report", "r.html", "--junit", "r.xml", cwd=d,
        preexec_fn=limit_fsize(3000), timeout=20)
e = r.stderr.decode()
ok(r.returncode == 1 and "cannot write the report" in e and not parts(d)
   and not os.path.exists(os.path.join(d, "r.html")),
   f"a report beyond the file size limit: exit 1 with a message, no .part, no report "
   f"({e.strip()[-200:]})")

# ---- JUnit: XML that parses, no injected attachments ----
d = fresh("junit")
evil = ["bad\ufffe\uffffname.png", "a[[ATTACHMENT|secret.txt]]b.png"]
for n in evil + ["prov.png"]:
    png(os.path.join(d, "base", n), level=10, extra=itxt("Software", "springpend \uffff one"))
    png(os.path.join(d, "act", n), level=200, extra=itxt("Software", "springpend \ufffe two"))
r = run("compare", "base", "act", "--junit", "r.xml", "--diff", "diffs", cwd=d)
try:
    tree = ET.parse(os.path.join(d, "r.xml"))
    parsed = True
except (ET.ParseError, FileNotFoundError) as x:
    parsed, why = False, str(x)
ok(r.returncode == 1 and parsed,
   f"U+FFFE and U+FFFF in names and PNG text: the JUnit XML parses (exit {r.returncode}"
   f"{'' if parsed else ', ' + why})")
if parsed:
    texts = "\n".join(t for el in tree.iter() for t in [el.text or ""] + list(el.attrib.values()))
    attached = re.findall(r"\[\[ATTACHMENT\|(.+?)\]\]", texts)
    diffs = {os.path.join("diffs", n) for n in os.listdir(os.path.join(d, "diffs"))}
    ok(attached and set(attached) <= diffs,
       f"only springpend's own diff images are attachments ({attached})")
    ok("springpend \ufffd one" in texts or "\ufffd" in texts,
       "what XML cannot hold is shown as U+FFFD")
else:
    ok(False, "only springpend's own diff images are attachments (no XML)")
    ok(False, "what XML cannot hold is shown as U+FFFD (no XML)")

# ---- escape sequences from names never reach the terminal ----
d = fresh("tty")
esc = "x\x1b]0;pwned\x07\x1b[31mred\x9b2J.png"
png(os.path.join(d, "base", esc), level=10)
png(os.path.join(d, "act", esc), level=200)
forged = "n\nok   forged.png"
png(os.path.join(d, "base", forged), level=10)
png(os.path.join(d, "act", forged), level=200)
os.mkfifo(os.path.join(d, "base", "\x1b[2Jfifo.png"))
png(os.path.join(d, "act", "\x1b[2Jfifo.png"))
r = subprocess.run([exe.encode(), b"compare", b"base", b"act"], capture_output=True, cwd=d,
                   timeout=30)
out = r.stdout + r.stderr
ok(r.returncode == 2 and b"\x1b" not in out and b"\x07" not in out and b"\x9b" not in out
   and b"\\x1b" in r.stdout and b"\\x1b" in r.stderr
   and not any(line.startswith(b"ok   forged") for line in r.stdout.split(b"\n"))
   and b"n\\nok   forged.png" in r.stdout,
   f"names with terminal escapes or a newline are shown, not sent, and forge no line "
   f"(stdout and stderr): {r.stdout[:200]!r}")
r = subprocess.run([exe.encode(), b"compare", b"base", b"act", b"--json"], capture_output=True,
                   cwd=d, timeout=30)
ok(b"\x1b" not in r.stdout and b"\xc2\x9b" not in r.stdout and b"\\u001b" in r.stdout
   and b"\\u009b" in r.stdout and json.loads(r.stdout)["results"],
   "--json escapes C0 and C1 controls (\\u001b, \\u009b): valid JSON, nothing a terminal obeys")

# ---- a video named javascript: is no live link ----
d = fresh("js")
r = run("compare", "javascript:alert(document.domain)//a.mp4", "b.mp4", "--report", "r.html",
        cwd=d)
html = open(os.path.join(d, "r.html")).read() if os.path.exists(os.path.join(d, "r.html")) else ""
hrefs = re.findall(r'href="([^"]*)"', html)
ok(r.returncode == 2 and hrefs and all(h.startswith(("./", "file://")) for h in hrefs)
   and not any(h.lower().startswith("javascript") for h in hrefs),
   f"a video path starting with javascript: is a relative link ({hrefs})")

# ---- an interrupted compare never reads as a pass ----
d = fresh("interrupted")
png(os.path.join(d, "base", "000.png"), 1200, 1200, 90)
shutil.copy(os.path.join(d, "base", "000.png"), os.path.join(d, "act", "000.png"))
N = 300
for i in range(1, N):
    for f in ("base", "act"):
        os.link(os.path.join(d, f, "000.png"), os.path.join(d, f, f"{i:03d}.png"))
p = subprocess.Popen([exe, "compare", "base", "act", "--report", "r.html", "--junit", "r.xml",
                      "--json"], cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
sptest.wait_caught(p, signal.SIGTERM)
time.sleep(0.4)
p.send_signal(signal.SIGTERM)
out, _ = p.communicate(timeout=60)
if p.returncode == 0:
    skip("an interrupted compare's reports", "the run finished before the signal")
else:
    html = open(os.path.join(d, "r.html")).read()
    summary = re.search(r'<p id="summary">([^<]*)', html).group(1)
    rows = len(re.findall(r'<tr class="row v-not-compared">', html))
    ok(p.returncode == 143 and not summary.startswith("ok") and "INTERRUPTED" in summary
       and "SIGTERM" in html and 0 < rows < N,
       f"the HTML says it was interrupted and lists {rows} images never compared ({summary})")
    suite = ET.parse(os.path.join(d, "r.xml")).getroot()
    skipped = suite.findall(".//testcase/skipped")
    ok(int(suite.get("errors")) >= 1 and len(skipped) == rows
       and any("interrupted" in (e.get("message") or "") for e in suite.iter("error")),
       f"the JUnit has an error for the interruption and {len(skipped)} skipped images "
       f"(errors={suite.get('errors')})")
    j = json.loads(out)
    ok(j["pass"] is False and j["interrupted"] is True and j["counts"].get("not_compared") == rows
       and sum(x.get("not_compared", 0) for x in j["results"]) == rows,
       f"the JSON lists them too: {j['counts']}")

# ---- compare --json is JSON for videos without timestamps ----
ffmpeg = shutil.which("ffmpeg")
if ffmpeg:
    d = fresh("nan")
    subprocess.run([ffmpeg, "-v", "error", "-y", "-f", "lavfi", "-i", "testsrc=s=64x48:d=0.3:r=10",
                    "-c:v", "libx264", os.path.join(d, "v.h264")], check=True)
    r = run("compare", "v.h264", "v.h264", "--json", cwd=d)
    try:
        j = json.loads(r.stdout, parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c)))
        fine = j["results"][0]["video"]["expected_fps"] is None
    except ValueError as x:
        fine, j = False, str(x)
    ok(r.returncode == 0 and fine, f"an H.264 stream without timestamps: valid JSON, fps null "
       f"({r.stdout.decode()[-160:]!r})")
else:
    skip("compare --json of a video without timestamps", "no ffmpeg to make one")

# ---- a report never lands on a baseline in folder mode ----
d = fresh("overwrite")
png(os.path.join(d, "base", "a.png"), level=10)
png(os.path.join(d, "act", "a.png"), level=200)
before = open(os.path.join(d, "base", "a.png"), "rb").read()
os.symlink("base/a.png", os.path.join(d, "link.xml"))
refused = []
for opt, target in (("--junit", "base/a.png"), ("--report", "base/a.png"),
                    ("--junit", "act/new.png"), ("--report", "base/compare.ini"),
                    ("--junit", "link.xml")):
    r = run("compare", "base", "act", opt, target, cwd=d)
    refused.append(r.returncode == 2 and "would overwrite an input" in r.stderr.decode())
ok(all(refused) and open(os.path.join(d, "base", "a.png"), "rb").read() == before
   and not os.path.exists(os.path.join(d, "act", "new.png"))
   and not os.path.exists(os.path.join(d, "base", "compare.ini")),
   f"--junit/--report onto a baseline, an actual image, compare.ini or a link to one are "
   f"refused ({refused})")

# ---- --update never writes through a link ----
d = fresh("update")
png(os.path.join(d, "victim.png"), level=1)
png(os.path.join(d, "base", "inner.png"), level=2)
png(os.path.join(d, "base", "c.png"), level=10)
victim = open(os.path.join(d, "victim.png"), "rb").read()
inner = open(os.path.join(d, "base", "inner.png"), "rb").read()
os.symlink("../victim.png", os.path.join(d, "base", "out.png"))
os.symlink("inner.png", os.path.join(d, "base", "in.png"))
for n in ("out.png", "in.png", "c.png"):
    png(os.path.join(d, "act", n), level=200)
png(os.path.join(d, "act", "inner.png"), level=2)
r = run("compare", "base", "act", "--update=all", cwd=d)
new = open(os.path.join(d, "act", "in.png"), "rb").read()
ok(open(os.path.join(d, "victim.png"), "rb").read() == victim
   and open(os.path.join(d, "base", "inner.png"), "rb").read() == inner
   and not os.path.islink(os.path.join(d, "base", "in.png"))
   and open(os.path.join(d, "base", "in.png"), "rb").read() == new
   and os.path.islink(os.path.join(d, "base", "out.png")),
   f"--update=all: a link within the folder is replaced by the file, one out of it refused; "
   f"neither target written (exit {r.returncode})")
os.makedirs(os.path.join(d, "diffs"))
os.symlink("../victim.png", os.path.join(d, "diffs", "c.diff.png"))
png(os.path.join(d, "base", "c.png"), level=10)
r = run("compare", "base", "act", "--diff", "diffs", cwd=d)
ok(open(os.path.join(d, "victim.png"), "rb").read() == victim
   and os.readlink(os.path.join(d, "diffs", "c.diff.png")) == "../victim.png"
   and r.returncode == 2 and "is a symbolic link" in r.stderr.decode(),
   f"folders: a link in the --diff folder is refused before comparing, never written through "
   f"nor replaced (attack17 #14; exit {r.returncode})")
os.symlink(os.path.join(d, "victim.png"), os.path.join(d, "one.png"))
r = run("compare", "one.png", "act/c.png", "--update=changed", cwd=d)
ok(open(os.path.join(d, "victim.png"), "rb").read() == victim
   and not os.path.islink(os.path.join(d, "one.png")) and r.returncode == 0,
   f"two files: --update replaces the linked baseline, not the file it points at "
   f"(exit {r.returncode})")

# ---- masks: each pixel counted once ----
d = fresh("masks")
png(os.path.join(d, "base", "m.png"), 40, 30, 10)
png(os.path.join(d, "act", "m.png"), 40, 30, 200)
masks = [(0, 0, 10, 10), (5, 5, 10, 10), (30, 20, 20, 20)]
star = [(8, 8, 4, 4)]
open(os.path.join(d, "base", "compare.ini"), "w").write(
    "[*]\n" + "".join(f"mask = {x}, {y}, {w}, {h}\n" for x, y, w, h in star)
    + "[m.png]\n" + "".join(f"mask = {x}, {y}, {w}, {h}\n" for x, y, w, h in masks))
covered = {(x, y) for mx, my, mw, mh in masks + star for x in range(mx, min(mx + mw, 40))
           for y in range(my, min(my + mh, 30))}
r = run("compare", "base", "act", "--json", cwd=d)
got = json.loads(r.stdout)["results"][0]["measured"].get("masked_pixels")
ok(got == len(covered), f"overlapping masks: masked_pixels {got}, expected {len(covered)}")

# ---- compare.ini: its messages are printable, a key set twice is refused ----
open(os.path.join(d, "base", "compare.ini"), "w").write("[m.png]\n\x1b]0;pwned\x07evil = 1\n")
r = run("compare", "base", "act", cwd=d)
ok(r.returncode == 2 and b"\x1b" not in r.stderr and b"\\x1b]0;pwned\\x07evil" in r.stderr,
   f"compare.ini: a key with terminal escapes is shown, not sent ({r.stderr!r})")

open(os.path.join(d, "base", "compare.ini"), "w").write("[m.png]\ntol = 2\nmax_diff = 4\n"
                                                        "# a comment\nmax-diff = 90\n")
r = run("compare", "base", "act", cwd=d)
ok(r.returncode == 2 and "compare.ini:5:" in r.stderr.decode() and "line 3" in r.stderr.decode(),
   f"compare.ini: a key set twice is refused with FILE:LINE ({r.stderr.decode().strip()})")

# ---- --help and --version check stdout ----
if root:
    full = path("full")
    os.mknod(full, 0o666 | 0o020000, os.makedev(1, 7))
    for opt in ("--help", "--version"):
        with open(full, "w") as f:
            r = subprocess.run([exe, opt], stdout=f, stderr=subprocess.PIPE, timeout=10)
        ok(r.returncode == 1 and b"cannot write" in r.stderr,
           f"springpend {opt} > a full device: exit 1 with a message ({r.returncode})")
    os.unlink(full)
else:
    skip("--help > a full device", "mknod needs root")

# ---- every signal that would kill the process stops a run cleanly ----
# (attack9 #10: also SIGPROF, SIGIO, SIGSTKFLT and the real-time signals,
# which schedulers send as custom stop signals; a signal the run inherited
# as ignored, as nohup's SIGHUP, stays ignored)
def long_data(d, **kw):
    """A `data` run that takes minutes, started once its .part exists."""
    p = subprocess.Popen([exe, "data", default, "--set", "integrator.method=rk4", "--set",
                          "integrator.dt=1e-6", "--set", "video.duration=1000", "--every", "100",
                          "-o", "d.csv"], cwd=d, stdout=subprocess.PIPE, stderr=subprocess.PIPE, **kw)
    for _ in range(100):  # until its .part exists
        if parts(d):
            break
        time.sleep(0.05)
    return p, bool(parts(d))


stops = [signal.SIGQUIT, signal.SIGUSR1, signal.SIGUSR2, signal.SIGALRM, signal.SIGVTALRM,
         signal.SIGXCPU, signal.SIGPWR, signal.SIGPROF, signal.SIGIO]
stops += [signal.SIGSTKFLT] if hasattr(signal, "SIGSTKFLT") else []
stops += [signal.SIGRTMIN, signal.SIGRTMIN + 5, signal.SIGRTMAX]
for sig in stops:
    name = signal.Signals(sig).name if sig in signal.Signals.__members__.values() else f"signal {int(sig)}"
    d = fresh("sig" + str(int(sig)))
    p, had_part = long_data(d)
    p.send_signal(sig)
    _, e = p.communicate(timeout=60)
    ok(had_part and p.returncode == 128 + sig and not parts(d),
       f"{name}: exit {p.returncode} (128 + {int(sig)} expected), no .part left "
       f"({parts(d)})")

d = fresh("nohup")
p, had_part = long_data(d, preexec_fn=lambda: signal.signal(signal.SIGHUP, signal.SIG_IGN))
p.send_signal(signal.SIGHUP)
time.sleep(1)
alive = p.poll() is None
p.send_signal(signal.SIGTERM)
p.communicate(timeout=60)
ok(had_part and alive and p.returncode == 128 + signal.SIGTERM and not parts(d),
   f"started with SIGHUP ignored (nohup): a SIGHUP leaves the run going ({alive}), a SIGTERM "
   f"then stops it: exit {p.returncode}, no .part left ({parts(d)})")

# ---- modules come only from the build tree or the installed layout ----
cc = shutil.which("cc") or shutil.which("gcc")
if cc:
    d = path("modules")
    os.makedirs(os.path.join(d, "x", "tools"))
    tool = os.path.join(d, "x", "tools", "springpend")
    shutil.copy(exe, tool)
    marker = os.path.join(d, "LOADED")

    def plant(where, version):
        c = os.path.join(d, "evil.c")
        open(c, "w").write('#include <stdio.h>\n__attribute__((constructor)) static void pwn(void)'
                           f' {{ FILE *f = fopen("{marker}", "w"); if (f) fclose(f); }}\n'
                           f'const char sp_module_version[] = "{version}";\n')
        os.makedirs(os.path.dirname(where), exist_ok=True)
        subprocess.run([cc, "-shared", "-fPIC", "-o", where, c], check=True)

    plant(os.path.join(d, "x", "springpend-cairo.so"), "0.1.0")
    r = subprocess.run([tool, "still", default, "--size", "64x48", "-q", "-o", "a.svg"],
                       capture_output=True, text=True, cwd=d, timeout=60)
    ok(r.returncode != 0 and not os.path.exists(marker) and "cannot load" in r.stderr,
       f"a copy at x/tools/springpend never loads x/springpend-cairo.so ({r.stderr.strip()[:200]})")
    m = re.search(r"\((/\S+?/springpend-cairo\.so):", r.stderr)
    if m and m.group(1).startswith(os.path.dirname(tool)):
        installed = os.path.normpath(m.group(1))
        plant(installed, "0.0.1")
        r = subprocess.run([tool, "still", default, "--size", "64x48", "-q", "-o", "a.svg"],
                           capture_output=True, text=True, cwd=d, timeout=60)
        ok(r.returncode != 0 and "built for springpend 0.0.1" in r.stderr,
           f"a module of another version is refused ({r.stderr.strip()[-160:]})")
        if os.path.exists(marker):
            os.unlink(marker)
        plant(installed, "0.1.0")
        # the same version number from another build: its structures and
        # signatures may differ (sp_sweep_plot gained an argument in one
        # round); only the interface id of this build's headers loads
        r = subprocess.run([tool, "still", default, "--size", "64x48", "-q", "-o", "a.svg"],
                           capture_output=True, text=True, cwd=d, timeout=60)
        ok(r.returncode != 0 and "another build" in r.stderr and not os.path.exists(os.path.join(d, "a.svg")),
           f"a module of the same version from another build is refused ({r.stderr.strip()[-200:]})")
        if os.path.exists(marker):
            os.unlink(marker)
        os.chmod(os.path.dirname(installed), 0o777)
        r = subprocess.run([tool, "still", default, "--size", "64x48", "-q", "-o", "a.svg"],
                           capture_output=True, text=True, cwd=d, timeout=60)
        ok(r.returncode != 0 and not os.path.exists(marker) and "writable by anyone" in r.stderr,
           f"a module in a folder anyone may write is refused ({r.stderr.strip()[-160:]})")
    else:
        ok(False, f"the message names the installed module path ({r.stderr.strip()})")
else:
    skip("modules from the binary's parent folder", "no C compiler to build one")

# ---- compressed text chunks are no bomb ----
d = fresh("bomb")
bomb = zlib.compress(b"a" * 7_900_000, 9)
png(os.path.join(d, "base", "b.png"), level=10,
    extra=b"".join(chunk(b"zTXt", b"Software\0\0" + bomb) for _ in range(48)))
png(os.path.join(d, "act", "b.png"), level=200, extra=itxt("Software", "springpend"))
size = os.path.getsize(os.path.join(d, "base", "b.png"))
p = subprocess.Popen([exe, "compare", "base/b.png", "act/b.png"], cwd=d,
                     stdout=subprocess.PIPE, stderr=subprocess.PIPE)
_, status, usage = os.wait4(p.pid, 0)
err = p.stderr.read().decode()
ok(os.waitstatus_to_exitcode(status) == 1 and usage.ru_maxrss < 150_000
   and "text chunks not read" in err,
   f"a {size // 1024} KiB PNG of 48 zTXt chunks (379 MB inflated): peak {usage.ru_maxrss // 1024}"
   f" MiB (< 150), said: {err.strip()[:120]}")
# a --set argument is echoed in the scene's messages: its control bytes shown, never sent
r = run("still", default, "--set", "view.caption=a\x1b]0;pwned\x07b", "-o", path("esc.png"))
r2 = run("still", default, "--set", "vi\x1bew", "-o", path("esc.png"))
ok(r.returncode == 2 and r2.returncode == 2 and b"\x1b" not in r.stderr + r2.stderr
   and b"\x07" not in r.stderr and b"\\x1b" in r.stderr and not os.path.exists(path("esc.png")),
   f"--set with ESC/BEL: refused, shown escaped: {(r.stderr + r2.stderr)[:160]!r}")
# a newline in a --set key or value starts no line of its own: each message is
# one line, the newline shown as \n (a value could forge "wrote out.png")
for arg in ("view.caption=a\nwrote out.png", "view.fps\nwrote=3", "video.fps=3\nwrote out.png",
            "nodot\nwrote out.png"):
    r = run("still", default, "--set", arg, "-o", path("nl.png"))
    lines = r.stderr.splitlines()
    ok(r.returncode == 2 and len(lines) == 1 and b"\\n" in r.stderr and
       not any(l.startswith(b"wrote") for l in lines) and not os.path.exists(path("nl.png")),
       f"--set {arg!r}: refused in one line, the newline shown as \\n: {r.stderr!r}")
done()
