#!/usr/bin/env python3
"""springpend tests (issue 28): the eighteenth attacker's pass
(doc/notes/2026-11-27/attack18.md), findings 2 and 5:
- #2: a changed scene value over 100 bytes is shown cut around its first
  difference; where no cut point lay within the window both values were a
  bare "…", and the cut split a Hangul syllable written as jamo. Each shown
  piece must hold the first difference, be a piece of the whole value, and
  start and end where UAX #29 allows (Hangul L/V/T from the characters'
  Unicode names, here);
- #5: past 16 changed keys the rest were dropped unsaid from JSON, HTML,
  JUnit and the Markdown summary: each now says how many more.
usage: test_attack18_scene_cut.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import os
import shutil
import unicodedata

import sptest
from sptest import done, err, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack18-scene-cut")
default = os.path.join(scenes, "default.ini")
lesson = os.path.join(scenes, "lesson-exchange.ini")
ELL = "…"


def still(name, caption):
    r = run("still", default, "--at", "1", "--size", "320x180", "--set", f"view.caption={caption}",
            "-o", path(name), "-q")
    return r.returncode == 0 or print(f"# still {name}: {err(r)}")


def hangul(c):
    """Hangul_Syllable_Type from the character's name and decomposition."""
    n = unicodedata.name(c, "")
    if n.startswith("HANGUL CHOSEONG"):
        return "L"
    if n.startswith("HANGUL JUNGSEONG"):
        return "V"
    if n.startswith("HANGUL JONGSEONG"):
        return "T"
    if n.startswith("HANGUL SYLLABLE"):
        return "LV" if len(unicodedata.normalize("NFD", c)) == 2 else "LVT"
    return ""


def joined(p, u):
    """UAX #29 GB6-GB8 and GB9 (Extend: marks), GB9c-like after a virama."""
    a, b = hangul(p), hangul(u)
    if a == "L" and b in ("L", "V", "LV", "LVT"):
        return True
    if a in ("LV", "V") and b in ("V", "T"):
        return True
    if a in ("LVT", "T") and b == "T":
        return True
    return unicodedata.category(u) in ("Mn", "Mc", "Me") or unicodedata.combining(p) == 9


def check_piece(case, whole, shown, diff, cut_ok_inside):
    """shown (a report's piece of whole): not empty, a piece of whole with "…"
    exactly where cut, holding the first difference (diff, in code points),
    cut only where UAX #29 allows (unless cut_ok_inside: a cluster longer
    than a report holds)."""
    head, tail = shown.startswith(ELL), shown.endswith(ELL)  # no value here holds "…"
    body = shown[len(ELL) if head else 0:len(shown) - (len(ELL) if tail else 0)]
    at = (len(whole) - len(body) if whole.endswith(body) else -1) if not tail else \
        whole.find(body) if head else (0 if whole.startswith(body) else -1)
    why = []
    if not body:
        why.append("empty")
    if at < 0:
        why.append("not a piece of the whole value")
    else:
        end = at + len(body)
        if shown.startswith(ELL) != (at > 0) or (shown.endswith(ELL) and end == len(whole)):
            why.append("ellipsis not where cut")
        if not (at <= min(diff, len(whole) - 1) < end):
            why.append(f"first difference {diff} not in [{at}, {end})")
        if not cut_ok_inside:
            if at > 0 and joined(whole[at - 1], whole[at]):
                why.append(f"starts inside a character: U+{ord(whole[at]):04X}")
            if end < len(whole) and joined(whole[end - 1], whole[end]):
                why.append(f"ends inside a character: U+{ord(whole[end]):04X}")
    ok(not why, f"{case}: {shown!r}: {'; '.join(why) or 'holds the difference, cut where allowed'}")


def nfd(s):
    return unicodedata.normalize("NFD", s)


cases = [  # name, expected caption, actual caption, a cluster over the room (cut at code points)
    ("conjunct chain", "क्" * 60 + "क", "क्" * 60 + "ख", True),
    ("Hangul jamo", nfd("한국어 문장을 길게 써 봅니다 " * 4 + "끝"), nfd("한국어 문장을 길게 써 봅니다 " * 4 + "꼴"), False),
    ("Hangul jamo, changed early", nfd("끝 " + "한국어 문장을 길게 써 봅니다 " * 4),
     nfd("꼴 " + "한국어 문장을 길게 써 봅니다 " * 4), False),
    ("mark stack", "x" * 20 + "a" + "\u0301" * 70 + "\u0302" + "\u0301" * 10,
     "x" * 20 + "a" + "\u0301" * 70 + "\u0303" + "\u0301" * 10, False),
]
for k, (case, ve, va, inside) in enumerate(cases):
    if not (still(f"e{k}.png", ve) and still(f"a{k}.png", va)):
        ok(False, f"{case}: the stills were made")
        continue
    r = run("compare", path(f"e{k}.png"), path(f"a{k}.png"), "--max-pixels", "100%", "--json")
    try:
        ch = [c for c in json.loads(r.stdout)["results"][0]["scene_changes"]
              if c["key"] == "view.caption"]
    except (ValueError, KeyError, IndexError):
        ch = []
    if not ok(len(ch) == 1, f"{case}: view.caption listed in the JSON ({err(r)[:200]})"):
        continue
    diff = next(i for i in range(min(len(ve), len(va)) + 1) if i == min(len(ve), len(va)) or ve[i] != va[i])
    check_piece(case + " (expected)", ve, ch[0]["expected"], diff, inside)
    check_piece(case + " (actual)", va, ch[0]["actual"], diff, inside)

# ---- 5: past 16 changed keys, every report says how many more --------------------------------
head = open(lesson, encoding="utf-8").read().splitlines()[:34]
for side, mark in (("h1", "A"), ("h2", "B")):
    with open(path(f"{side}.ini"), "w", encoding="utf-8") as f:
        f.write("\n".join(head) + "\n[timeline]\n")
        for i in range(20):
            f.write(f"{i}.5 = caption: " + "& < " * 35 + mark + str(i) + "\n")
    r = run("still", path(f"{side}.ini"), "--at", "1", "--size", "1280x720", "-o", path(f"{side}.png"), "-q")
    ok(r.returncode == 0, f"{side}.png made ({err(r)[:200]})")
changed = 20  # every cue's caption differs in its last characters
for d, f in (("he", "h1.png"), ("ha", "h2.png")):
    shutil.rmtree(path(d), ignore_errors=True)
    os.makedirs(path(d))
    shutil.copy(path(f), path(d, "x.png"))
r = run("compare", path("he"), path("ha"), "--max-pixels", "100%", "--report", path("r.html"),
        "--junit", path("j.xml"), "--summary", path("s.md"), "--json")
try:
    rec = json.loads(r.stdout)["results"][0]
except (ValueError, KeyError, IndexError):
    rec = {}
listed = len(rec.get("scene_changes", []))
ok(listed + rec.get("more_changes", -1000) == changed,
   f"JSON: {listed} listed + more_changes {rec.get('more_changes')} = {changed}")
more = changed - listed
for name in ("s.md", "j.xml", "r.html"):
    text = open(path(name), encoding="utf-8").read() if os.path.exists(path(name)) else ""
    ok(f"and {more} more scene keys" in text, f"{name} says 'and {more} more scene keys'")
r = run("compare", path("he"), path("ha"), "--max-pixels", "100%")
ok(f"and {more} more keys" in r.stdout.decode(), f"text says 'and {more} more keys'")
done()
