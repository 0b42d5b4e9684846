#!/usr/bin/env python3
"""springpend tests (issue 28): what the twelfth attacker's pass found in
the command line's options (doc/notes/2026-11-27/attack12.md):
- attack12 #13: data's scene column refused a leading = + - @ but not a
  tab (a spreadsheet drops a leading tab or carriage return, then reads the
  formula): a leading tab or carriage return is refused too;
- attack12 #16: side by side, scenes that differed in an encoder setting
  the output never reads (crf for a PNG still or a GIF, png_level for an
  MP4) were refused: only the keys the output's encoder reads are compared
  (crf and preset for MP4 and WebM, png_level for PNG), and crf's default
  reads "0 (automatic)";
- attack12 #18: data's --fps and --quality pick frame times, which --every
  and --poincare do not sample: given together they are refused, exit 2,
  no file.
usage: test_attack12_options.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil

import sptest
from sptest import done, err, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack12-options")
default = os.path.join(scenes, "default.ini")
stiff = os.path.join(scenes, "stiff.ini")
chaotic = os.path.join(scenes, "chaotic.ini")

# ---- attack12 #13: a scene column that starts with a tab or CR is refused ------------------
for lead, said in (("\t", "a tab"), ("\r", "a carriage return")):
    name = lead + "=cmd|x.ini"
    shutil.copy(default, path(name))
    out = path("col.csv")
    r = run("data", chaotic, name, "--set", "video.duration=0.1", "-o", out)
    ok(r.returncode == 2 and f"starts with {said}" in err(r)
       and "which a spreadsheet reads as the start of a formula" in err(r)
       and not os.path.exists(out),
       f"data chaotic.ini {name!r}: refused, nothing written (exit {r.returncode}: "
       f"{err(r)[-200:]!r})")
shutil.copy(default, path("x\t=y.ini"))  # a tab inside the name starts nothing
r = run("data", chaotic, "x\t=y.ini", "--set", "video.duration=0.1", "-o", path("col2.csv"))
ok(r.returncode == 0 and os.path.exists(path("col2.csv")),
   f"a tab inside the name (not first): written as before (exit {r.returncode}: "
   f"{err(r)[-160:]!r})")

# ---- attack12 #16: side by side, only the keys the output's encoder reads -----------------
with open(stiff) as f:
    stiff_text = f.read()
for name, extra in (("s51.ini", "crf = 51"), ("p9.ini", "png_level = 9"),
                    ("pv.ini", "preset = veryslow")):
    with open(path(name), "w") as f:
        f.write(stiff_text + f"\n[video]\n{extra}\n")
short = ["--size", "160x90", "--set", "video.duration=0.2", "-q"]
# a key the output does not read: drawn
for cmd, out in ((["still", default, "s51.ini", "--at", "0.1"], "s51.png"),
                 (["still", default, "pv.ini", "--at", "0.1"], "pv.png"),
                 (["still", default, "p9.ini", "--at", "0.1"], "p9.svg"),
                 (["render", default, "p9.ini"], "p9.mp4"),
                 (["render", default, "p9.ini"], "p9.webm"),
                 (["render", default, "s51.ini"], "s51.gif"),
                 (["render", default, "pv.ini"], "pv.gif"),
                 (["render", default, "s51.ini"], os.path.join("fr", "%03d.png"))):
    r = run(*cmd, *short, "-o", out, timeout=180)
    made = os.path.exists(path(out)) or os.path.exists(path("fr", "000.png"))
    ok(r.returncode == 0 and made,
       f"{cmd[0]} default.ini {cmd[2]} -o {out}: the output reads no such key, so it is drawn "
       f"(exit {r.returncode}: {err(r)[-200:]!r})")
# a key it reads: refused, naming it
for cmd, out, said in ((["still", default, "p9.ini", "--at", "0.1"], "q9.png",
                        "video.png_level = 9, but"),
                       (["render", default, "p9.ini"], os.path.join("fq", "%03d.png"),
                        "video.png_level = 9, but"),
                       (["render", default, "s51.ini"], "q51.mp4",
                        "video.crf = 51, but"),
                       (["render", default, "s51.ini"], "q51.webm",
                        "video.crf = 51, but"),
                       (["render", default, "pv.ini"], "qv.mp4",
                        "video.preset = veryslow, but")):
    r = run(*cmd, *short, "-o", out, timeout=180)
    ok(r.returncode == 2 and said in err(r) and not os.path.exists(path(out))
       and not os.path.exists(path("fq", "000.png")),
       f"{cmd[0]} default.ini {cmd[2]} -o {out}: the encoder reads it, so it is refused, "
       f"nothing written (exit {r.returncode}: {err(r)[-200:]!r})")
r = run("render", default, "s51.ini", *short, "-o", "q51b.mp4")
ok("has 0 (automatic);" in err(r) and "has 0;" not in err(r),
   f"crf's default is named '0 (automatic)' (exit {r.returncode}: {err(r)[:200]!r})")

# ---- attack12 #18: data --fps / --quality with --every or --poincare: refused --------------
for opts, said in ((["--fps", "7", "--every", "0.1"], "--fps sets the frame times"),
                   (["--every", "0.1", "--quality", "low"], "--quality sets the frame times"),
                   (["--poincare", "--fps", "7"], "--fps sets the frame times"),
                   (["--quality", "low", "--poincare"], "--quality sets the frame times")):
    out = path("fq.csv")
    r = run("data", chaotic, "--set", "video.duration=2", *opts, "-o", out)
    other = "--every" if "--every" in opts else "--poincare"
    ok(r.returncode == 2 and said in err(r) and f"which {other} replaces" in err(r)
       and not os.path.exists(out),
       f"data {' '.join(opts)}: refused, naming both, nothing written (exit {r.returncode}: "
       f"{err(r)[-200:]!r})")
for opts in (["--fps", "7"], ["--quality", "low"], ["--every", "0.1"], ["--poincare"]):
    out = path("fq.csv")
    r = run("data", chaotic, "--set", "video.duration=2", *opts, "-o", out)
    ok(r.returncode == 0 and os.path.exists(out),
       f"data {' '.join(opts)} alone: written as before (exit {r.returncode}: "
       f"{err(r)[-160:]!r})")
    if os.path.exists(out):
        os.remove(out)

done()
