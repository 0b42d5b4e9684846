#!/usr/bin/env python3
"""springpend tests: `meson install --destdir` into a temporary folder, then
the installed tool, moved elsewhere, runs render (MP4: the FFmpeg module is
found relative to the executable), still and compare; springpend(1) and the
bash completion are installed and agree with --help, and so does each
command's page (springpend-render(1), ...). The shipped scenes and the docs
are installed, and the program names the scenes' folder where it is.
usage: test_install.py BUILD_ROOT PREFIX BINDIR MANDIR DATADIR OUTPUT_DIR (TAP)"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

build, prefix, bindir, mandir, datadir, out = sys.argv[1:7]
work = os.path.abspath(os.path.join(out, "install"))
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
count = failed = 0


def ok(cond, what):
    global count, failed
    count += 1
    failed += not cond
    print(f"{'' if cond else 'not '}ok {count} - {what}".replace("\n", " | "), flush=True)
    return cond


meson = shutil.which("meson")
dest = os.path.join(work, "destdir")
r = subprocess.run([meson, "install", "-C", build, "--destdir", dest, "--no-rebuild", "--quiet"],
                   capture_output=True, text=True)
root = dest + prefix if os.path.isabs(prefix) else os.path.join(dest, prefix)
ok(r.returncode == 0 and os.path.isfile(os.path.join(root, bindir, "springpend")),
   f"meson install --destdir {dest}: {r.stderr.strip()[-300:]}")
# Move the whole tree: nothing may depend on where it was installed.
moved = os.path.join(work, "moved")
shutil.move(root, moved)
shutil.rmtree(dest, ignore_errors=True)
exe = os.path.join(moved, bindir, "springpend")
scene = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scenes", "default.ini")
env = dict(os.environ, PATH=os.path.dirname(exe) + ":" + os.environ["PATH"])


def run(*args):
    return subprocess.run(["springpend", *args], capture_output=True, text=True, cwd=work, env=env)


# The shipped scenes and the documentation are installed (attack14 #6), the
# program names the installed scenes' folder (which exists, moved as it is)
# in --help, the empty-scene message and a bare scene name's hint, and
# springpend(1) names the configured one; the build tree's program names the
# source's scenes/; no executable holds the build folder's path.
source = os.path.realpath(os.path.join(os.path.dirname(scene), ".."))
scenes = os.path.join(moved, datadir, "springpend", "scenes")
shipped = sorted(f for f in os.listdir(os.path.dirname(scene)) if f.endswith(".ini"))
ok(os.path.isdir(scenes) and sorted(os.listdir(scenes)) == shipped
   and all(open(os.path.join(scenes, f), "rb").read() == open(os.path.join(source, "scenes", f), "rb").read()
           for f in shipped),
   f"the {len(shipped)} shipped scenes are installed in DATADIR/springpend/scenes "
   f"({sorted(os.listdir(scenes)) if os.path.isdir(scenes) else 'none'})")
docs = os.path.join(moved, datadir, "doc", "springpend")
guides = sorted(f for f in os.listdir(os.path.join(source, "doc")) if f.endswith(".md"))
ok(os.path.isdir(docs) and sorted(os.listdir(docs)) == sorted(["README.md"] + guides),
   f"README.md and the {len(guides)} doc/*.md (not doc/notes/, doc/pictures/) are installed in "
   f"DATADIR/doc/springpend ({sorted(os.listdir(docs)) if os.path.isdir(docs) else 'none'})")
real = os.path.realpath(scenes)
top = run("--help").stdout
ok(f"\n  {real}/\n" in top and os.path.isfile(os.path.join(real, "default.ini")),
   f"the installed --help names its scenes folder, which holds default.ini "
   f"({[l for l in top.splitlines() if 'scenes' in l]})")
# attack16 #6: the guides are installed flat (no doc/ folder): --help names
# the folder that holds them, and no command's --help or page points to a
# doc/ path an install does not have.
real_docs = os.path.realpath(docs)
ok(f"\n  {real_docs}/\n" in top and os.path.isfile(os.path.join(real_docs, "outputs.md")),
   f"the installed --help names its guides' folder, which holds outputs.md "
   f"({[l for l in top.splitlines() if 'doc' in l]})")
helps = {c: run(c, "--help").stdout for c in ("render", "still", "data", "info", "keys", "scene",
                                               "compare", "sweep", "version")}
pointing = [f"{c}: {l.strip()}" for c, t in helps.items() for l in t.splitlines() if "doc/" in l]
ok(not pointing and "outputs.md" in helps["render"] and "ci.md" in helps["compare"],
   f"no command's --help points to a doc/ path; render's names outputs.md, compare's ci.md "
   f"{pointing[:3]}")
# attack18 #3: where the guides' folder is gone (a system that drops
# /usr/share/doc), --help says they are not installed, naming no folder
shutil.move(docs, docs + ".moved")
gone = run("--help")
ok(gone.returncode == 0 and "are not\ninstalled here: they are doc/*.md in springpend's source" in gone.stdout
   and real_docs not in gone.stdout,
   f"without the guides' folder, --help says they are not installed here "
   f"({[l for l in gone.stdout.splitlines() if 'guides' in l or 'installed' in l]})")
# attack19 #6: a minimal image's dpkg path-exclude keeps the package's
# folder with only its copyright file: the guides are not there, and --help
# says so rather than naming a folder without them
os.makedirs(docs)
with open(os.path.join(docs, "copyright"), "w") as f:
    f.write("springpend: MIT\n")
bare = run("--help")
ok(bare.returncode == 0 and "are not\ninstalled here: they are doc/*.md in springpend's source" in bare.stdout
   and real_docs not in bare.stdout,
   f"attack19 #6: a guides' folder holding only copyright: --help says they are not installed "
   f"here ({[l for l in bare.stdout.splitlines() if 'guides' in l or 'installed' in l or 'doc' in l]})")
shutil.rmtree(docs)
shutil.move(docs + ".moved", docs)
again = run("--help").stdout
ok(f"\n  {real_docs}/\n" in again,
   f"the guides put back: --help names their folder again ({[l for l in again.splitlines() if 'doc' in l]})")
open(os.path.join(work, "empty.ini"), "w").close()
r = run("still", "empty.ini", "-o", "e.png")
named = re.findall(r"start from (\S+\.ini)", r.stderr)
ok(r.returncode == 2 and named == [os.path.join(real, "default.ini")] and os.path.isfile(named[0]),
   f"an empty scene: the message names the installed default.ini ({r.stderr.strip()})")
r = run("still", "chaotic", "-o", "e.png")
ok(r.returncode == 2 and r.stderr.strip().endswith(
   f"the shipped scene of that name is {os.path.join(real, 'chaotic.ini')}"),
   f"a scene named without a folder that is not a file: the message names the shipped one ({r.stderr.strip()})")
built = subprocess.run([os.path.join(build, "springpend"), "--help"], capture_output=True, text=True).stdout
ok(f"\n  {os.path.join(source, 'scenes')}/\n" in built and f"\n  {os.path.join(source, 'doc')}/\n" in built,
   f"the build tree's --help names the source's scenes/ and doc/ "
   f"({[l for l in built.splitlines() if 'scenes' in l]})")
paths = [os.path.realpath(build), os.path.abspath(build), source]
holding = [f"{b} holds {p}" for b in [exe] + [os.path.join(d, f) for d, _, fs in os.walk(moved)
                                              for f in fs if f.endswith(".so")]
           for p in paths if p.encode() in open(b, "rb").read()]
ok(not holding, f"no installed executable or module holds the build or source folder's path "
   f"(a package is the same, built in any folder) {holding[:3]}")
with open(os.path.join(moved, mandir, "man1", "springpend.1")) as f:
    page1 = f.read()
configured = os.path.join(prefix, datadir)  # datadir when absolute
ok(f"{configured}/springpend/scenes/".replace("-", "\\-") in page1 and source not in page1,
   f"springpend(1) names the installed scenes folder {configured}/springpend/scenes/, not the source's "
   f"({[l for l in page1.splitlines() if 'scenes' in l][:3]})")
pages = {f: open(os.path.join(moved, mandir, "man1", f)).read() for f in os.listdir(os.path.join(moved, mandir, "man1"))}
pointing = [f"{f}: {l}" for f, t in pages.items() for l in t.splitlines() if "doc/" in l and "doc/ in the source" not in l
            and f"{configured}/doc/springpend/".replace("-", "\\-") not in l]
ok(len(pages) >= 10 and not pointing and f"{configured}/doc/springpend/".replace("-", "\\-") in page1,
   f"the man pages name the installed guides' folder and no source doc/ path {pointing[:3]}")

r = run("render", scene, "--size", "96x64", "--set", "video.duration=0.3", "-o", "v.mp4", "-q")
ok(r.returncode == 0 and os.path.getsize(os.path.join(work, "v.mp4")) > 0,
   f"the moved install renders an MP4 (FFmpeg module found beside it) ({r.stderr.strip()[-300:]})")
r = run("still", scene, "--size", "96x64", "--at", "1", "-o", "a.png", "-q")
r2 = run("still", scene, "--size", "96x64", "--at", "1", "-o", "b.png", "-q")
ok(r.returncode == 0 and r2.returncode == 0, f"still ({r.stderr.strip()})")
r = run("compare", "a.png", "b.png")
ok(r.returncode == 0 and "identical pixels" in r.stdout, f"compare ({r.stdout.strip()})")
r = run("compare", "v.mp4", "v.mp4")
ok(r.returncode == 0, f"compare of videos through the module ({r.stdout.strip()}{r.stderr.strip()})")

man = os.path.join(moved, mandir, "man1", "springpend.1")
page = subprocess.run(["man", "-l", man], capture_output=True, text=True,
                      env=dict(os.environ, MANWIDTH="100")).stdout if shutil.which("man") else open(man).read()
helps = [run(c, "--help").stdout for c in ("render", "still", "data", "compare")]
missing = [l.strip() for h in helps for l in h.splitlines()
           if l.strip().startswith("--") and l.strip() not in page.replace("\u2010", "-")]
ok(os.path.exists(man) and "springpend compare EXPECTED ACTUAL" in page and not missing,
   f"springpend(1) is installed and holds every option line of --help (missing: {missing[:3]})")
# A page per command, named for what --help lists: each holds its command's
# one-line description and every line of its --help (for keys, of its list),
# and springpend(1) names them all under SEE ALSO.
top = run("--help").stdout
listed = re.findall(r"^  (\w+)\s+(.*)$", top.split("commands:\n", 1)[1].split("\n\n", 1)[0], re.M)


def man_text(path):
    if not shutil.which("man"):
        return open(path).read()
    return subprocess.run(["man", "-l", path], capture_output=True, text=True,
                          env=dict(os.environ, MANWIDTH="200")).stdout.replace("\u2010", "-")


for name, what in listed:
    path = os.path.join(moved, mandir, "man1", f"springpend-{name}.1")
    text = man_text(path) if os.path.exists(path) else ""
    own = run(name, "--help").stdout if name != "keys" else run("keys").stdout
    lost = [l.strip() for l in own.splitlines()   # the usage line as the SYNOPSIS
            if l.strip() and l.strip().replace("usage: ", "", 1) not in text]
    ok(text and f"springpend-{name} - {what.strip()}" in " ".join(text.split()) and not lost,
       f"springpend-{name}(1) is installed with its description and every line of "
       f"'springpend {name}{' --help' * (name != 'keys')}' (missing: {lost[:3]})")
see_also = " ".join(page.split("SEE ALSO", 1)[-1].split())
ok(listed and all(f"springpend-{name}(1)" in see_also for name, _ in listed),
   f"springpend(1)'s SEE ALSO names the {len(listed)} command pages ({see_also[:200]})")

comp = os.path.join(moved, datadir, "bash-completion", "completions", "springpend")


def complete(*words):
    line = " ".join(words)
    script = (f"source {comp}; COMP_WORDS=({line}); COMP_CWORD={len(words) - 1}; "
              "_springpend; printf '%s\\n' \"${COMPREPLY[@]}\"")
    return subprocess.run(["bash", "-c", script], capture_output=True, text=True,
                          cwd=work).stdout.split()


ok(os.path.exists(comp) and complete("springpend", "comp") == ["compare"]
   and complete("springpend", "compare", "--up") == ["--update"]
   and "pendulum.stiffness=" in complete("springpend", "render", "--set", "pendulum.s"),
   f"bash completion: commands, options, scene keys ({complete('springpend', 'render', '--set', 'pendulum.s')})")
# Every option the completion offers is one its command takes: not an option
# its help text names in passing (scene --help explains --state and --csv,
# render --help says --state is still's). Given alone, each is at worst
# missing its value or its scene, never unknown or another command's.
text = open(comp).read() if os.path.exists(comp) else ""
offered = dict(re.findall(r'^ +(\w+)\) opts="([^"]*)"', text, re.M))
wrong = []
for name, opts in offered.items():
    for opt in opts.split():
        r = run(name, opt)
        if "unknown option" in r.stderr or "is for 'springpend" in r.stderr or "Traceback" in r.stderr:
            wrong.append(f"{name} {opt}: {r.stderr.strip()[:80]}")
ok(len(offered) >= 7 and "--help" in offered.get("scene", "") and not wrong,
   f"bash completion offers only options each command takes ({sum(len(o.split()) for o in offered.values())} "
   f"for {len(offered)} commands; refused: {wrong[:6]})")
# doc/ci.md's worked example, followed as written with the installed tool:
# its snapshots.sh, then its compare commands, in a folder of their own.
import re
import xml.etree.ElementTree as ET
from sptest import manual  # noqa: E402  (README.md and doc/*.md)
readme = manual(os.path.join(os.path.dirname(scene), ".."))
script = re.search(r"```sh\n(#!/bin/sh\n# snapshots.sh OUTDIR.*?)```", readme, re.S).group(1)
lines = [l for l in readme.splitlines() if l.startswith("springpend compare snapshots actual")]
ci, add, update = (next(l for l in lines if want in l)
                   for want in ("--junit", "--update=missing", "--update=changed"))
ex = os.path.join(work, "example")
os.makedirs(ex)
os.symlink(os.path.join(os.path.dirname(scene)), os.path.join(ex, "scenes"))
open(os.path.join(ex, "snapshots.sh"), "w").write(script)
sh = lambda cmd: subprocess.run(["sh", "-c", cmd.split("  #")[0]], capture_output=True, text=True,
                                cwd=ex, env=env)
r = sh("sh snapshots.sh actual")
ok(r.returncode == 0 and len(os.listdir(os.path.join(ex, "actual"))) == 8,
   f"doc/ci.md: sh snapshots.sh actual ({r.stderr.strip()})")
r = sh(ci)
ok(r.returncode == 2 and "--update=missing" in r.stdout and os.path.exists(os.path.join(ex, "report.xml")),
   f"doc/ci.md: the first compare reports every baseline missing and how to add them ({r.stdout.strip()[-120:]})")
r = sh(add)
ok(r.returncode == 0 and r.stdout.count("added") == 7
   and len(os.listdir(os.path.join(ex, "snapshots"))) == 7, f"doc/ci.md: {add} ({r.stdout.strip()[-120:]})")
r = sh(ci)
cases = ET.parse(os.path.join(ex, "report.xml")).getroot().findall("./testsuite/testcase")
ok(r.returncode == 0 and "7 passed" in r.stdout and len(cases) == 7
   and os.path.getsize(os.path.join(ex, "report.html")) > 10000,
   f"doc/ci.md: the CI compare passes, report.html and report.xml written ({r.stdout.strip()[-120:]})")
sh("springpend still scenes/default.ini --at 2 --size 640x360 -o actual/default_t3.png -q")
r = sh(ci)
ok(r.returncode == 1 and "FAIL default_t3.png" in r.stdout, "doc/ci.md: a changed picture fails the job")
r = sh(update)
r2 = sh(ci)
ok(r.returncode == 0 and "replaced" in r.stdout and r2.returncode == 0,
   f"doc/ci.md: {update} takes the change, the job passes again ({r.stdout.strip()[-120:]})")

# attack17 #4: a module's path holding a FIFO or a device is not opened
# (dlopen would wait on a FIFO for a writer, or run a device's driver): the
# run says what is there, at once, and loads nothing.
mods = [os.path.join(d, f) for d, _, fs in os.walk(moved) for f in fs if f == "springpend-cairo.so"]
if mods:
    real_mod = mods[0] + ".real"
    os.rename(mods[0], real_mod)
    kinds = [("a FIFO", lambda p: os.mkfifo(p, 0o644))]
    if os.geteuid() == 0:  # /dev/null's numbers, made in the temporary install only
        kinds.append(("a character device", lambda p: os.mknod(p, 0o644 | 0o020000, os.makedev(1, 3))))
    for what, make in kinds:
        make(mods[0])
        try:
            r = subprocess.run(["springpend", "still", scene, "--at", "1", "--size", "96x64", "-o", "m.svg"],
                               capture_output=True, text=True, cwd=work, env=env, timeout=20)
            said, rc = r.stderr.strip(), r.returncode
        except subprocess.TimeoutExpired:
            said, rc = "still running after 20 s", None
        ok(rc == 1 and f"springpend-cairo.so: is {what}, not a module; not loaded" in said
           and not os.path.exists(os.path.join(work, "m.svg")),
           f"attack17 #4: the SVG module's path holding {what}: not opened, said at once, exit 1 "
           f"({rc}: {said[-240:]})")
        os.unlink(mods[0])
    os.rename(real_mod, mods[0])
    r = run("still", scene, "--at", "1", "--size", "96x64", "-o", "m.svg", "-q")
    ok(r.returncode == 0, f"the module put back: the SVG is drawn ({r.stderr.strip()[-200:]})")
else:
    ok(False, "the installed SVG module springpend-cairo.so was not found")

print(f"1..{count}")
sys.exit(1 if failed else 0)
