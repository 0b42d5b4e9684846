#!/usr/bin/env python3
"""springpend tests (issue 28): the twelfth attacker's pass
(doc/notes/2026-11-27/attack12.md), what is seen:
- #17: a ZWNJ or ZWJ between consonant + virama and a consonant was written
  raw (scene --command, compare's notes, file names) in the scripts whose
  virama joins only a few consonants (Tamil, Gurmukhi, Sinhala), where it
  draws nothing. The oracle is the picture: a still with and without the
  joiner (decoded by ffmpeg, not by springpend); the record keeps the
  joiner raw exactly when their pixels differ, else writes \\u200c / \\u200d.
  Controls where it draws: Tamil KSSA and SRI, Gurmukhi's subjoined HA and
  post-base YA, Sinhala's yansaya, rakaransaya, repaya and a touching
  letter, Malayalam and Devanagari conjuncts (tests/unit/
  test_joiner_shaping.c checks every pair of the three scripts by shaping).
usage: test_attack12_seen.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil
import subprocess

import sptest
from sptest import done, ok, skip

exe, src, work, run = sptest.setup("attack12-seen", [])
scenes = os.path.abspath(os.path.join(src, "..", "scenes"))
default = os.path.join(scenes, "default.ini")
command = sptest.scene_command(sptest.runner_bytes(exe, work))

ZWNJ, ZWJ = "\u200c", "\u200d"
TA_KA, TA_NA, TA_RA, TA_SA, TA_SSA, TA_II, PULLI = "\u0b95", "\u0ba8", "\u0bb0", "\u0bb8", "\u0bb7", "\u0bc0", "\u0bcd"
GU_KA, GU_HA, GU_YA, GU_V = "\u0a15", "\u0a39", "\u0a2f", "\u0a4d"
SI_KA, SI_YA, SI_RA, SI_SSA, SI_VA, AL = "\u0d9a", "\u0dba", "\u0dbb", "\u0dc2", "\u0dc0", "\u0dca"
# (title with the joiner, why); the same title without it is the control
cases = [
    (TA_KA + PULLI + ZWNJ + TA_KA, "Tamil KA PULLI ZWNJ KA (the pulli shown either way)"),
    (TA_NA + PULLI + ZWNJ + TA_RA, "Tamil NA PULLI ZWNJ RA"),
    (TA_KA + PULLI + ZWJ + TA_KA, "Tamil KA PULLI ZWJ KA"),
    (TA_SA + PULLI + ZWNJ + TA_RA, "Tamil SA PULLI ZWNJ RA (SRI needs the II)"),
    (TA_KA + PULLI + ZWNJ + TA_SSA, "Tamil KA PULLI ZWNJ SSA (breaks KSSA)"),
    (TA_KA + PULLI + ZWJ + TA_SSA, "Tamil KA PULLI ZWJ SSA (breaks KSSA)"),
    (TA_SA + PULLI + ZWNJ + TA_RA + TA_II, "Tamil SA PULLI ZWNJ RA II (breaks SRI)"),
    (GU_KA + GU_V + ZWNJ + GU_KA, "Gurmukhi KA VIRAMA ZWNJ KA"),
    (GU_KA + GU_V + ZWJ + GU_KA, "Gurmukhi KA VIRAMA ZWJ KA"),
    (GU_KA + GU_V + ZWNJ + GU_HA, "Gurmukhi KA VIRAMA ZWNJ HA (breaks the subjoined HA)"),
    (GU_KA + GU_V + ZWJ + GU_YA, "Gurmukhi KA VIRAMA ZWJ YA (breaks the post-base YA)"),
    (SI_KA + AL + ZWNJ + SI_KA, "Sinhala KA AL-LAKUNA ZWNJ KA"),
    (SI_KA + AL + ZWNJ + SI_YA, "Sinhala KA AL-LAKUNA ZWNJ YA (only a ZWJ joins)"),
    (SI_KA + AL + ZWJ + SI_KA, "Sinhala KA AL-LAKUNA ZWJ KA (no touching KA+KA)"),
    (SI_KA + AL + ZWJ + SI_YA, "Sinhala KA AL-LAKUNA ZWJ YA (yansaya)"),
    (SI_KA + AL + ZWJ + SI_RA, "Sinhala KA AL-LAKUNA ZWJ RA (rakaransaya)"),
    (SI_RA + AL + ZWJ + SI_KA, "Sinhala RA AL-LAKUNA ZWJ KA (repaya)"),
    (SI_KA + AL + ZWJ + SI_VA, "Sinhala KA AL-LAKUNA ZWJ VA (a touching letter)"),
    ("\u0d15\u0d4d" + ZWNJ + "\u0d15", "Malayalam KA VIRAMA ZWNJ KA (breaks the conjunct)"),
    ("\u0915\u094d" + ZWNJ + "\u0915", "Devanagari KA VIRAMA ZWNJ KA (breaks the conjunct)"),
]


def pixels(name):
    """The picture's RGB bytes, decoded by ffmpeg (not by springpend)."""
    return subprocess.run(["ffmpeg", "-v", "error", "-i", os.path.join(work, name), "-f", "rawvideo",
                           "-pix_fmt", "rgb24", "-"], capture_output=True, check=True).stdout


for i, (title, why) in enumerate(cases):
    if not shutil.which("ffmpeg"):
        skip(f"#17: {why}", "ffmpeg missing")
        continue
    bare = title.replace(ZWNJ, "").replace(ZWJ, "")
    pix = []
    for name, t in ((f"j{i}.png", title), (f"n{i}.png", bare)):
        r = run("still", default, "--at", "0", "--size", "640x200", "--set", "view.panels=none",
                "--set", "view.hud=false", "--set", f"view.title={t}", "-o", name, "-q")
        pix.append(pixels(name) if r.returncode == 0 else None)
    if pix[0] is None or pix[1] is None:
        ok(False, f"#17: {why}: the stills")
        continue
    drawn = pix[0] != pix[1]
    joiner = ZWNJ if ZWNJ in title else ZWJ
    said = command(os.path.join(work, f"j{i}.png"))
    raw = f"view.title={title}" in said
    escaped = "view.title=" + title.replace(joiner, "\\u%04x" % ord(joiner)) in said
    ok(raw == drawn and escaped != drawn,
       f"#17: {why}: the joiner {'changes' if drawn else 'changes no'} pixels and the record "
       f"writes it {'raw' if raw else 'escaped' if escaped else '?'} ({said[-60:]!r})")

done()
