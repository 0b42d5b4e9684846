#!/usr/bin/env python3
"""springpend tests (issue 28): the seventeenth attacker's pass
(doc/notes/2026-11-27/attack17.md), the lead's findings:
- #9: a text refused because ' #' or ' ;' would start a comment was told to
  write a fixed sample ("Run #3", and for a pause note "pause 3"): the
  remedy now quotes the user's own text and cue, and says a tab where the
  blank is one. Each remedy, written back into the scene, is read and draws
  the text that --set (which takes text whole) draws.
usage: test_attack17_lead.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import re

import sptest
from sptest import done, err, ok

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack17-lead")
lesson = os.path.join(scenes, "lesson-exchange.ini")
head = re.split(r"^\[timeline\]", open(lesson).read(), flags=re.M)[0]

# ---- 9: the remedy quotes what was written -----------------------------------------------------
for key, text in (("title", "a ; b"), ("title", "Run\t#3"), ("caption", "Étape #2 ; fin"),
                  ("title", "x #1 \"quoted\"")):
    scene = path("t.ini")
    base = "[pendulum]\nmass = 1.5\n[view]\n"
    open(scene, "w").write(f"{base}{key} = {text}\n")
    r = run("info", scene)
    said = err(r)
    blank = "a tab then '#'" if "\t#" in text else "' " + ("#" if " #" in text.split(";")[0] else ";") + "'"
    m = re.search(rf'\({key} = (".*")\)(?:, a tab written as a space)?; a comment may follow', said)
    shown = text.replace("\t", " ")  # a tab is not text: the remedy writes a space
    ok(r.returncode == 2 and blank in said and m and m.group(1) == f'"{shown}"'
       and ("a tab written as a space" in said) == ("\t" in text),
       f"9: {key} = {text!r}: refused, the blank named ({blank}), the remedy quotes the text itself "
       f"(exit {r.returncode}: {said[:200]})")
    if not m:
        continue
    open(scene, "w").write(f"{base}{key} = {m.group(1)}\n")
    a = run("still", scene, "--at", "1", "--size", "320x180", "-o", path("quoted.png"), "-q")
    open(path("plain.ini"), "w").write(base)
    b = run("still", path("plain.ini"), "--set", f"view.{key}={shown}", "--at", "1", "--size", "320x180",
            "-o", path("set.png"), "-q")
    c = run("compare", path("set.png"), path("quoted.png"), "--max-pixels", "0", "--max-diff", "0")
    ok(a.returncode == 0 and b.returncode == 0 and c.returncode == 0,
       f"9: the remedy written back draws what --set view.{key}=TEXT draws ({err(a)[:120]} {err(b)[:120]} "
       f"{c.stdout.strip()[:120]})")

for cue, want_head, want_text in (("pause 2: note ; x", "pause 2", "note ; x"),
                                  ("pause  2.5 : take #5", "pause  2.5 ", "take #5"),
                                  ("caption: Energie ; Schwung", "caption", "Energie ; Schwung")):
    scene = path("tl.ini")
    open(scene, "w").write(head + "[timeline]\n5 = " + cue + "\n")
    r = run("info", scene)
    m = re.search(r'in double quotes \((.*?): (".*")\)(?:, a tab written as a space)?; a comment', err(r))
    ok(r.returncode == 2 and m and m.group(1) == want_head and m.group(2) == f'"{want_text}"',
       f"9: [timeline] 5 = {cue}: refused, the remedy is the cue as written with its text quoted "
       f"(exit {r.returncode}: {err(r)[:220]})")
    if m:
        open(scene, "w").write(head + "[timeline]\n5 = " + f"{m.group(1)}: {m.group(2)}\n")
        r = run("info", scene)
        ok(r.returncode == 0, f"9: the remedy written back is read ({err(r)[:200]})")

done()
