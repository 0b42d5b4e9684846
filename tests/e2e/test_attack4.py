#!/usr/bin/env python3
"""springpend tests: the attacker's fourth pass (doc/notes/2026-11-26d/
attack4.md), findings 1, 2, 3 and 5. Each check is a class, run as the
attacker ran it:
- a sweep whose scene's file name holds a character that only a fallback
  font draws (CJK, a mathematical letter) writes its figure (it crashed with
  SIGSEGV and left its .part: a fallback face added while the title was laid
  out was stored past the end of cairo's face array);
- a noncharacter (U+FFFE) in the scene's file name reaches the sweep's
  automatic title escaped, as messages show it (the grid ran, then the
  title was refused and the run crashed);
- a noncharacter or ESC in the command line gives a well-formed SVG (the
  command's metadata held them raw) and a PDF (cairo refused the /Subject as
  not UTF-8, exit 1);
- a font file whose name is not UTF-8 gives a PDF (cairo refused /Keywords);
- compare --approve and --candidates show escapes in file names escaped.
usage: test_attack4.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil
import subprocess
import xml.dom.minidom

import sptest
from sptest import done, err, ok, part_files

exe, src, work, _ = sptest.setup("attack4", ["pdfinfo", "fc-match"])
run = sptest.runner_bytes(exe, work)
scenes = os.path.join(src, "..", "scenes")
chaotic = os.path.join(scenes, "chaotic.ini")
default = os.path.join(scenes, "default.ini")
GRID = ["--vary", "initial.angle=1:179:4", "--measure", "lyapunov", "--time", "2"]
ESC = "\x1b]2;PWN\x07\x1b[31m"


def path(*names):
    return os.path.join(work, *names)


# 1. a scene named in a script that only a fallback font has
for i, name in enumerate(["你好", "\U0001d703x"]):
    for ext in ["png", "svg", "pdf"]:
        d = path(f"f1-{ext}-{i}")
        os.makedirs(d)
        scene = os.path.join(d, name + ".ini")
        shutil.copy(chaotic, scene)
        r = run("sweep", scene, *GRID, "-o", os.path.join(d, "x." + ext))
        ok(r.returncode == 0 and os.path.getsize(os.path.join(d, "x." + ext)) > 0
           and not part_files(d),
           f"sweep of a scene named {name!r} writes its {ext} figure "
           f"(exit {r.returncode}: {err(r)[-200:]})")

# 1b. a noncharacter in the scene's name: shown escaped in the title
d = path("f1b")
os.makedirs(d)
scene = os.path.join(d, "a\ufffe.ini")
shutil.copy(chaotic, scene)
r = run("sweep", scene, *GRID, "-o", os.path.join(d, "x.pdf"))
text = subprocess.run(["pdftotext", os.path.join(d, "x.pdf"), "-"], capture_output=True,
                      text=True).stdout if r.returncode == 0 else ""
ok(r.returncode == 0 and "a\\ufffe" in text and not part_files(d),
   f"U+FFFE in the scene's name is drawn escaped in the sweep's title "
   f"(exit {r.returncode}: {err(r)[-200:]})")

# 2. noncharacters and escapes in the command line: SVG parses, PDF is written
d = path("f2")
os.makedirs(d)
odd = os.path.join(d, "q\ufffe" + ESC + ".ini")
shutil.copy(default, odd)
r = run("still", odd, "--at", "1", "--size", "160x90", "-o", os.path.join(d, "s.svg"))
try:
    xml.dom.minidom.parse(os.path.join(d, "s.svg"))
    parsed = True
except Exception as e:  # noqa: BLE001 (any parse failure is the finding)
    parsed = f"{e}"
ok(r.returncode == 0 and parsed is True,
   f"U+FFFE and ESC in the command line: the SVG is well-formed ({parsed}; {err(r)[-200:]})")
r = run("still", odd, "--at", "1", "--size", "160x90", "-o", os.path.join(d, "s.pdf"))
info = subprocess.run(["pdfinfo", os.path.join(d, "s.pdf")], capture_output=True,
                      text=True).stdout if r.returncode == 0 else ""
ok(r.returncode == 0 and "\\ufffe" in info and "\x1b" not in info,
   f"U+FFFE and ESC in the command line: the PDF is written, its subject escaped "
   f"(exit {r.returncode}: {err(r)[-200:]})")

# 3. a font file whose name is not UTF-8
d = path("f3")
fonts = os.path.join(d, "fonts")
os.makedirs(fonts)
serif = subprocess.run(["fc-match", "-f", "%{file}", "DejaVu Serif"], capture_output=True,
                       text=True).stdout
shutil.copy(serif, os.path.join(fonts.encode(), b"x\xff.ttf"))
conf = os.path.join(d, "fonts.conf")
with open(conf, "w") as f:
    f.write(f'<?xml version="1.0"?><fontconfig><dir>{fonts}</dir>'
            f'<cachedir>{d}/cache</cachedir></fontconfig>\n')
env = dict(os.environ, FONTCONFIG_FILE=conf)
r = run("still", default, "--set", "view.font=DejaVu Serif", "--at", "1", "--size", "320x180",
        "-o", os.path.join(d, "o.pdf"), env=env)
info = subprocess.run(["pdfinfo", os.path.join(d, "o.pdf")], capture_output=True,
                      text=True).stdout if r.returncode == 0 else ""
ok(r.returncode == 0 and "x\\xff.ttf" in info,
   f"a font file named in bytes that are not UTF-8: the PDF is written and names it escaped "
   f"(exit {r.returncode}: {err(r)[-200:]})")

# 5. compare --approve and --candidates show names escaped
d = path("f5")
for sub in ["cand", "base", "exp", "act"]:
    os.makedirs(os.path.join(d, sub))
a = os.path.join(d, "a.png")
b = os.path.join(d, "b.png")
run("still", default, "--at", "1", "--size", "160x90", "-o", a)
run("still", default, "--at", "2", "--size", "160x90", "-o", b)
shutil.copy(a, os.path.join(d, "cand", "x" + ESC + ".png"))
r = run("compare", "--approve", os.path.join(d, "cand"), os.path.join(d, "base"))
ok(r.returncode == 0 and b"\x1b" not in r.stdout and b"\\x1b" in r.stdout,
   f"compare --approve shows ESC in a name escaped ({r.stdout[-200:]!r})")
shutil.copy(a, os.path.join(d, "exp", "a.png"))
shutil.copy(b, os.path.join(d, "act", "a.png"))
cand = os.path.join(d, "c" + ESC + "d")
r = run("compare", os.path.join(d, "exp"), os.path.join(d, "act"), "--candidates", cand)
ok(r.returncode != 0 and b"\x1b" not in r.stdout and b"candidate" in r.stdout,
   f"compare --candidates shows ESC in its folder's name escaped ({r.stdout[-200:]!r})")

done()
