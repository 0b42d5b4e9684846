#!/usr/bin/env python3
"""springpend tests: the Debian package (debian/). Builds it from a copy of
the source tree with `dpkg-buildpackage -b -us -uc`, checks it with lintian
(no error or warning), asks apt whether `apt install ./springpend_*.deb`
would install (every dependency resolvable here, simulated), unpacks it and
runs the packaged program from there: a still, an MP4 (the FFmpeg module,
found beside the program as installed), the man page and bash completion;
the shipped scenes and the docs are in it, where --help, the empty-scene
message and springpend(1) say, and no file holds the build folder's path.
Skips (77) without dpkg-buildpackage, debhelper or lintian (Debian:
dpkg-dev debhelper lintian).
usage: test_deb.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import glob
import os
import re
import shutil
import subprocess
import sys

from sptest import done, meson_deb_packages, ok

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
root = os.path.abspath(os.path.join(src, ".."))
work = os.path.abspath(os.path.join(sys.argv[3], "deb"))

missing = [t for t in ("dpkg-buildpackage", "dh", "lintian", "dpkg-deb") if not shutil.which(t)]
if missing:
    print(f"1..0 # SKIP not installed: {' '.join(missing)} (Debian: dpkg-dev debhelper lintian)")
    sys.exit(77)

shutil.rmtree(work, ignore_errors=True)
tree = os.path.join(work, "springpend")
os.makedirs(tree)
# the source tree as committed or about to be: git's files, else all but builds
r = subprocess.run(["git", "-C", root, "ls-files", "-co", "--exclude-standard", "-z"],
                   capture_output=True)
if r.returncode == 0 and r.stdout:
    for name in r.stdout.decode().split("\0"):
        if name and os.path.isfile(os.path.join(root, name)):
            os.makedirs(os.path.dirname(os.path.join(tree, name)), exist_ok=True)
            shutil.copy2(os.path.join(root, name), os.path.join(tree, name))
else:
    shutil.copytree(root, tree, dirs_exist_ok=True,
                    ignore=shutil.ignore_patterns("build*", "obj-*", ".git"))

version = re.search(r"version\s*:\s*'([^']+)'", open(os.path.join(root, "meson.build")).read()).group(1)
changelog = open(os.path.join(root, "debian", "changelog")).readline()
ok(changelog.startswith(f"springpend ({version})"),
   f"debian/changelog's version is meson.build's {version}: {changelog.strip()}")

# every dependency('X') of meson.build, through its .pc file, is a Build-Depends
control = open(os.path.join(root, "debian", "control")).read()
build_deps = set(re.findall(r"[a-z0-9][a-z0-9+.-]+", control.split("Build-Depends:")[1].split("\nStandards")[0]))
pkgs = meson_deb_packages(root) if shutil.which("pkg-config") else {}
missing = {d: p for d, p in pkgs.items() if p and p not in build_deps}
ok(pkgs and not missing and all(pkgs.values()),
   f"debian/control builds on the package of every meson dependency ({len(pkgs)}); missing {missing}")

env = dict(os.environ, DEB_BUILD_OPTIONS=f"parallel={min(os.cpu_count() or 1, 2)}")
b = subprocess.run(["dpkg-buildpackage", "-b", "-us", "-uc"], cwd=tree, env=env,
                   capture_output=True, text=True, timeout=1800)
debs = glob.glob(os.path.join(work, "springpend_*.deb"))
ok(b.returncode == 0 and len(debs) == 1,
   f"dpkg-buildpackage -b -us -uc builds one package (exit {b.returncode}) "
   f"{(b.stdout + b.stderr)[-600:] if b.returncode else os.path.basename(debs[0])}")
if debs:
    deb = debs[0]
    files = subprocess.run(["dpkg-deb", "-c", deb], capture_output=True, text=True).stdout
    want = ["./usr/bin/springpend", "/springpend/springpend-av.so", "/springpend/springpend-cairo.so",
            "/springpend/springpend-plot.so", "./usr/share/man/man1/springpend.1.gz",
            *(f"./usr/share/man/man1/springpend-{c}.1.gz"
              for c in ("render", "still", "data", "info", "keys", "scene", "compare", "sweep")),
            "./usr/share/bash-completion/completions/springpend", "./usr/share/doc/springpend/copyright"]
    ok(all(w in files for w in want), f"the package holds the program, its three modules, the man "
       f"pages (springpend(1) and one per command), bash completion and the copyright ({[w for w in want if w not in files]} missing)")
    li = subprocess.run(["lintian", "--fail-on", "error,warning", deb], capture_output=True, text=True)
    tags = [l for l in li.stdout.splitlines() if re.match(r"^[EW]: ", l)]
    ok(li.returncode == 0 and not tags, f"lintian: no error or warning ({tags or 'clean'})")
    a = subprocess.run(["apt-get", "install", "-s", "--no-install-recommends", deb],
                       capture_output=True, text=True)
    ok(a.returncode == 0 and "Inst springpend" in a.stdout,
       f"apt install ./{os.path.basename(deb)} would install it here (simulated, exit {a.returncode}) "
       f"{a.stderr.strip()[-300:]}")
    unpacked = os.path.join(work, "root")
    subprocess.run(["dpkg-deb", "-x", deb, unpacked], check=True)
    prog = os.path.join(unpacked, "usr", "bin", "springpend")
    scene = os.path.join(root, "scenes", "default.ini")
    v = subprocess.run([prog, "--version"], capture_output=True, text=True)
    s = subprocess.run([prog, "still", scene, "--size", "160x90", "-o", os.path.join(work, "s.png"), "-q"],
                       capture_output=True, text=True)
    m = subprocess.run([prog, "render", scene, "--size", "160x90", "--set", "video.duration=0.5",
                        "-o", os.path.join(work, "v.mp4"), "-q"], capture_output=True, text=True)
    head = open(os.path.join(work, "v.mp4"), "rb").read(12) if m.returncode == 0 else b""
    png = open(os.path.join(work, "s.png"), "rb").read(8) if s.returncode == 0 else b""
    ok(version in v.stdout and png == b"\x89PNG\r\n\x1a\n" and head[4:8] == b"ftyp",
       f"the packaged program runs from where it is unpacked: --version, a still and an MP4 "
       f"(its module beside it) ({v.stdout.strip()!r} {s.stderr.strip()} {m.stderr.strip()})")
    # attack14 #6: the scenes and docs the program and its page send the
    # user to are in the package, where they say; no build path in it
    shipped = sorted(f for f in os.listdir(os.path.join(root, "scenes")) if f.endswith(".ini"))
    guides = sorted(f for f in os.listdir(os.path.join(root, "doc")) if f.endswith(".md"))
    lost = [f for f in shipped if f"./usr/share/springpend/scenes/{f}\n" not in files]
    lost += [f for f in ["README.md"] + guides
             if f"./usr/share/doc/springpend/{f}\n" not in files]  # by the names --help gives (attack18 #3)
    ok(not lost, f"the package holds the {len(shipped)} scenes in /usr/share/springpend/scenes and "
       f"README.md and the {len(guides)} doc/*.md, not gzipped, in /usr/share/doc/springpend (missing: {lost[:4]})")
    scenes = os.path.realpath(os.path.join(unpacked, "usr", "share", "springpend", "scenes"))
    top = subprocess.run([prog, "--help"], capture_output=True, text=True).stdout
    open(os.path.join(work, "empty.ini"), "w").close()
    e = subprocess.run([prog, "still", os.path.join(work, "empty.ini"), "-o", os.path.join(work, "e.png")],
                       capture_output=True, text=True)
    named = re.findall(r"start from (\S+)/default\.ini", e.stderr)
    ok(f"\n  {scenes}/\n" in top and named == [scenes] and os.path.isfile(os.path.join(scenes, "default.ini")),
       f"the packaged program's --help and empty-scene message name its scenes folder, in the package "
       f"({[l for l in top.splitlines() if 'scenes' in l]} {e.stderr.strip()})")
    docs = os.path.realpath(os.path.join(unpacked, "usr", "share", "doc", "springpend"))
    ok(f"\n  {docs}/\n" in top and "doc/" not in subprocess.run([prog, "render", "--help"], capture_output=True,
                                                                   text=True).stdout,
       f"the packaged --help names its guides' folder (attack16 #6), render --help no doc/ path "
       f"({[l for l in top.splitlines() if 'doc' in l]})")
    man = subprocess.run(["zcat", os.path.join(unpacked, "usr/share/man/man1/springpend.1.gz")],
                         capture_output=True, text=True).stdout.replace("\\-", "-")
    ok("/usr/share/springpend/scenes/" in man and "/usr/share/doc/springpend/" in man
       and "see scenes/" not in man and tree not in man,
       f"springpend(1) names /usr/share/springpend/scenes/ and /usr/share/doc/springpend/ "
       f"({[l for l in man.splitlines() if 'scenes' in l][:3]})")
    binaries = [os.path.join(d, f) for d, _, fs in os.walk(unpacked) for f in fs
                if (f == "springpend" and d.endswith("/usr/bin")) or f.endswith(".so")]
    holding = [b for b in binaries if tree.encode() in open(b, "rb").read()]
    ok(len(binaries) == 4 and not holding,
       f"no packaged executable or module holds the build folder's path {tree} (the package is the same "
       f"built in any folder) ({len(binaries)} checked; holding: {holding})")
done()
