#!/usr/bin/env python3
"""springpend tests (issue 28): the nineteenth attacker's pass
(doc/notes/2026-11-28/attack19.md), finding 2: a scene value changed only in
its Unicode normal form (é as U+00E9 and as e + U+0301, Hangul syllables and
their jamo) was reported as changed with two values that read the same, in
every report. Each value of such a pair is now followed by its form, and the
JSON says "same_text": true.

The forms are made in the test with Python's unicodedata (independently of
springpend's GLib): NFC against NFD, a mixed text (neither), a long caption
(cut around its first difference), and a real change (no form named).
usage: test_attack19_forms.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import os
import unicodedata

import sptest
from sptest import done, ok

exe, src, work, run = sptest.setup("attack19-forms", [])
scene = os.path.abspath(os.path.join(src, "..", "scenes", "default.ini"))
TEXT = "Café résumé 한국"
NFC, NFD = unicodedata.normalize("NFC", TEXT), unicodedata.normalize("NFD", TEXT)
MIXED = "Cafe\u0301 résumé 한국"  # e + U+0301 in the first word, é whole in the second
assert NFC != NFD and unicodedata.normalize("NFC", MIXED) == NFC != MIXED != NFD


def still(name, key, value, size="160x90"):
    r = run("still", scene, "--at", "1", "--size", size, "--set", f"{key}={value}", "-o",
            name, "-q")
    if r.returncode:
        sptest.diag(r.stderr)
    return r.returncode == 0


def change(a, b):
    """compare's text line and JSON entry for the scene change between a and b."""
    r = run("compare", a, b)
    line = next((l for l in r.stdout.splitlines() if "scene:" in l), "")
    j = run("compare", a, b, "--json")
    try:
        entry = json.loads(j.stdout)["results"][0]["scene_changes"]
    except (ValueError, KeyError, IndexError):
        entry = []
    sptest.diag(line.strip())
    return line, (entry[0] if entry else {})


ok(still("nfc.png", "view.title", NFC) and still("nfd.png", "view.title", NFD) and
   still("mixed.png", "view.title", MIXED) and still("other.png", "view.title", "Cafe resume"),
   "stills titled in NFC, NFD, a mixed form and another text")

line, e = change("nfc.png", "nfd.png")
ok(f"{NFC} (NFC) (expected) vs {NFD} (NFD) (actual)" in line,
   "text: NFC against NFD, each followed by its form")
ok(e.get("same_text") is True and e.get("expected") == f"{NFC} (NFC)" and
   e.get("actual") == f"{NFD} (NFD)", f"JSON: same_text true, the forms named: {e}")

line, e = change("nfc.png", "mixed.png")
ok("(neither NFC nor NFD) (actual)" in line and e.get("same_text") is True,
   "a mixed text is named neither NFC nor NFD")

line, e = change("nfc.png", "other.png")
ok(e.get("same_text") is False and "(NFC)" not in line and "Cafe resume (actual)" in line,
   "another text: no form named, same_text false")

# a long caption, cut around its first difference, still named
long_nfc = "ab " * 60 + NFC + " cd" * 60
ok(still("long-nfc.png", "view.caption", long_nfc, "1920x1080") and
   still("long-nfd.png", "view.caption", unicodedata.normalize("NFD", long_nfc), "1920x1080"),
   "captions of 600+ bytes in NFC and NFD")
line, e = change("long-nfc.png", "long-nfd.png")
ok(e.get("same_text") is True and e.get("cut") is True and e.get("expected", "").endswith("(NFC)")
   and e.get("actual", "").endswith("(NFD)"), "a long pair: cut, and each named by its form")

# the folder reports: JUnit, Markdown summary, HTML
for d, f in (("e", "nfc.png"), ("a", "nfd.png")):
    os.makedirs(os.path.join(work, d), exist_ok=True)
    os.replace(os.path.join(work, f), os.path.join(work, d, "x.png"))
r = run("compare", "e", "a", "--junit", "j.xml", "--summary", "s.md", "--report", "r.html")
texts = {n: open(os.path.join(work, n), encoding="utf-8").read() if os.path.exists(
    os.path.join(work, n)) else "" for n in ("j.xml", "s.md", "r.html")}
for n, t in texts.items():
    ok("(NFC)" in t and "(NFD)" in t, f"{n} names both forms")
done()
