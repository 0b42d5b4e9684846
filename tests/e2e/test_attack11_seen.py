#!/usr/bin/env python3
"""springpend tests (issue 28): the eleventh attacker's pass
(doc/notes/2026-11-27/attack11.md), what is seen:
- #1: a ZWNJ or ZWJ after a virama was written raw (scene --command,
  compare's notes) where it draws nothing: a virama with no consonant
  before it, a ZWNJ before a vowel letter. The oracle is the picture: a
  still with and without the joiner (decoded by ffmpeg); the record keeps
  it raw exactly when their pixels differ, else writes \\u200c / \\u200d;
- #25: the default output cut the scene file's name at its first dot, so
  chaotic.v2.ini and chaotic.v3.ini both wrote out/chaotic.png: the name
  is the file's name without its last extension;
- #14: 640x240 took 24 px text (the size check's floor), where the colour
  bar's labels overlapped and the energy legend ran over the panel below:
  refused, exit 2, saying the 16 px allowed, nothing written;
- #18: at 640x360 and 24 px the speed marker ("speed x2") was drawn over
  the time ("t = 1234.56 s"): the time's row is the same, pixel for pixel,
  as in the same still without a marker (tests/unit/test_legibility.c checks
  the layout at the largest font size each of 8 frames takes).
usage: test_attack11_seen.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil
import subprocess

import sptest
from sptest import done, ok, skip

exe, src, work, run = sptest.setup("attack11-seen", [])
scenes = os.path.abspath(os.path.join(src, "..", "scenes"))
default = os.path.join(scenes, "default.ini")
command = sptest.scene_command(sptest.runner_bytes(exe, work))

# 1: (title with the joiner, why); the same title without it is the control
ZWNJ, ZWJ = "\u200c", "\u200d"
KA, SSA, VIRAMA, A, NUKTA = "\u0915", "\u0937", "\u094d", "\u0905", "\u093c"
cases = [
    (KA + VIRAMA + ZWNJ + SSA, "ZWNJ in a conjunct (KA VIRAMA ZWNJ SSA)"),
    (KA + NUKTA + VIRAMA + ZWNJ + SSA, "ZWNJ after KA NUKTA VIRAMA, before SSA"),
    (KA + VIRAMA + ZWJ + SSA, "ZWJ in a conjunct: the half form"),
    (KA + VIRAMA + ZWJ + A, "ZWJ before a vowel letter: the half form"),
    (KA + VIRAMA + ZWNJ + A, "ZWNJ before a vowel letter"),
    (" " + VIRAMA + ZWNJ + KA + " x", "ZWNJ after a virama after a space"),
    (" " + VIRAMA + ZWJ + KA + " x", "ZWJ after a virama after a space"),
    ("a" + VIRAMA + ZWNJ + KA, "ZWNJ after a virama after a Latin letter"),
    (VIRAMA + ZWNJ + KA, "ZWNJ after a virama at the start"),
    (A + VIRAMA + ZWJ + KA, "ZWJ after a virama after a vowel letter"),
    ("\u1000\u103a" + ZWNJ + "\u1000", "ZWNJ after Myanmar's asat (a pure killer)"),
    ("\u1780\u17d2" + ZWNJ + "\u1780", "ZWNJ after Khmer's coeng (a stacker)"),
]


def pixels(name):
    """The picture's RGB bytes, decoded by ffmpeg (not by springpend)."""
    return subprocess.run(["ffmpeg", "-v", "error", "-i", os.path.join(work, name), "-f", "rawvideo",
                           "-pix_fmt", "rgb24", "-"], capture_output=True, check=True).stdout


for i, (title, why) in enumerate(cases):
    if not shutil.which("ffmpeg"):
        skip(f"#1: {why}", "ffmpeg missing")
        continue
    bare = title.replace(ZWNJ, "").replace(ZWJ, "")
    pix = []
    for name, t in ((f"j{i}.png", title), (f"n{i}.png", bare)):
        r = run("still", default, "--at", "0", "--size", "640x200", "--set", "view.panels=none",
                "--set", "view.hud=false", "--set", f"view.title={t}", "-o", name, "-q")
        pix.append(pixels(name) if r.returncode == 0 else None)
    if pix[0] is None or pix[1] is None:
        ok(False, f"#1: {why}: the stills")
        continue
    drawn = pix[0] != pix[1]
    joiner = ZWNJ if ZWNJ in title else ZWJ
    said = command(os.path.join(work, f"j{i}.png"))
    raw = f"view.title={title}" in said
    escaped = "view.title=" + title.replace(joiner, "\\u%04x" % ord(joiner)) in said
    ok(raw == drawn and escaped != drawn,
       f"#1: {why}: the joiner {'changes' if drawn else 'changes no'} pixels and the record "
       f"writes it {'raw' if raw else 'escaped' if escaped else '?'} ({said[-60:]!r})")

# attack13 #22, a decision: the rule is Unicode's, the same on every machine,
# not what the fonts here draw. Noto Sans Devanagari draws KA VIRAMA KA with
# a half KA with or without the ZWJ, yet the ZWJ (which asks for that half
# form) is written raw, and the record, pasted into sh, re-makes the image
# byte for byte: an escaped word would have to be retyped, and a record is
# read back where other fonts may draw the joiner.
if shutil.which("ffmpeg"):
    title = KA + VIRAMA + ZWJ + KA
    for name, t in (("font-same.png", title), ("font-same-bare.png", KA + VIRAMA + KA)):
        r = run("still", default, "--at", "0", "--size", "640x200", "--set", "view.panels=none",
                "--set", "view.hud=false", "--set", f"view.title={t}", "-o", name, "-q")
    same = pixels("font-same.png") == pixels("font-same-bare.png")
    said = command(os.path.join(work, "font-same.png"))
    again = subprocess.run(["sh", "-c", "'" + exe + "'" + said[len("springpend"):] + " -o again.png -q"],
                           cwd=work, capture_output=True, timeout=120) \
        if said.startswith("springpend still") else None
    remade = again is not None and again.returncode == 0 and \
        open(os.path.join(work, "again.png"), "rb").read() == open(os.path.join(work, "font-same.png"), "rb").read()
    ok(f"view.title={title}" in said and remade,
       f"attack13 #22: KA VIRAMA ZWJ KA (drawn {'the same as' if same else 'unlike'} KA VIRAMA KA "
       f"with the fonts here) is written raw and its record re-makes the image byte for byte "
       f"({said[-50:]!r}, re-made: {remade})")
else:
    skip("attack13 #22: a joiner the fonts draw the same, its record", "ffmpeg missing")

# 25: two scenes that differ after the first dot write two files.
for name, from_ in (("chaotic.v2.ini", "default.ini"), ("chaotic.v3.ini", "stiff.ini")):
    shutil.copy(os.path.join(scenes, from_), os.path.join(work, name))
    r = run("still", name, "--at", "1", "--size", "320x180", "-q")
    ok(r.returncode == 0, f"#25: still {name} without -o ({r.stderr.strip()[-200:]})")
out = sorted(os.listdir(os.path.join(work, "out")))
ok(out == ["chaotic.v2.png", "chaotic.v3.png"],
   f"#25: chaotic.v2.ini and chaotic.v3.ini write out/chaotic.v2.png and out/chaotic.v3.png ({out})")
r = run("data", "chaotic.v2.ini", "chaotic.v3.ini", "--every", "1", "-o", "both.csv", "-q")
rows = open(os.path.join(work, "both.csv")).read().splitlines() if r.returncode == 0 else []
ok({row.split(",")[0] for row in rows[1:]} == {"chaotic.v2", "chaotic.v3"},
   f"#25: data names them chaotic.v2 and chaotic.v3 ({r.stderr.strip()[-200:]})")
readme = open(os.path.join(src, "..", "README.md")).read()
ok("name less its last extension (`chaotic.v2.ini`: `out/chaotic.v2.png`)" in readme,
   "#25: the README says the default name is the file's name without its last extension")

# 14: the largest font size 640x240 takes is the one its layout fits.
r = run("still", default, "--at", "0", "--size", "640x240", "--set", "view.font_size=24",
        "--set", "view.theme=light", "-o", "cb.png")
ok(r.returncode == 2 and "cannot fit a 640x240 px frame" in r.stderr
   and "allowed: at most 16 px here" in r.stderr and not os.path.exists(os.path.join(work, "cb.png")),
   f"#14: font_size 24 at 640x240 is refused, 16 px allowed (exit {r.returncode}: {r.stderr.strip()[-160:]})")
r = run("still", default, "--at", "0", "--size", "640x240", "--set", "view.font_size=16", "-o", "cb16.png", "-q")
ok(r.returncode == 0, f"#14: font_size 16 at 640x240 is drawn (exit {r.returncode})")

# 18: the time's row with and without the marker.
text = open(default).read().replace("duration = 10 ", "duration = 2000 ")
for name, extra in (("marker.ini", "\n[timeline]\n1 = speed 2\n"), ("none.ini", "")):
    with open(os.path.join(work, name), "w") as f:
        f.write(text + extra)
rows = {}
for name in ("marker", "none"):
    r = run("still", name + ".ini", "--at", "1234.56", "--size", "640x360", "--set", "view.font_size=24",
            "-o", name + ".png", "-q")
    rows[name] = pixels(name + ".png") if r.returncode == 0 and shutil.which("ffmpeg") else None
if rows["marker"] is None or rows["none"] is None:
    ok(False, "#18: the stills with and without the marker")
else:
    row = lambda img, y: img[y * 640 * 3:(y * 640 + 280) * 3]  # the HUD's column, x < 280
    bg = row(rows["none"], 0)[:3]
    ink = [y for y in range(60) if row(rows["none"], y) != bg * 280]
    top = ink[0] if ink else 0
    end = next((y for y in range(top, 60) if row(rows["none"], y) == bg * 280), 60)  # the time's row
    same = all(row(rows["marker"], y) == row(rows["none"], y) for y in range(top, end))
    ok(ink and same and rows["marker"] != rows["none"],
       f"#18: the time's row (y {top}..{end - 1}) is drawn alike with and without the speed marker, "
       "which is drawn elsewhere")

done()
