#!/usr/bin/env python3
"""springpend tests (issue 28): records and shown names after the
attacker's eighth pass (doc/notes/2026-11-27/attack8.md), each check run as
the attacker ran it:
- finding 10: a shard's prov:wasGeneratedBy naming another scene file than
  the scene the shard holds (dc:source) was merged, and the merged figure
  recorded that scene; now refused (exit 2, naming the file), while the
  shards' own command merges;
- finding 11: characters that show nothing but are not Cf (U+034F, U+FE0F,
  U+3164, U+115F, U+2800, U+2065) were recorded raw; the Markdown, JUnit
  and HTML reports of compare wrote U+200B raw. Now the shown form escapes
  Unicode's Default_Ignorable_Code_Point set, U+2800 and unassigned code
  points everywhere;
- finding 12: a backslash was not escaped, so a typed "\\u200c" and U+200C
  showed alike (records, compare's scene diff). Now a backslash shows as
  \\\\, and the recorded command still reads back in a POSIX shell into
  the words given (a title with a backslash and a quote re-makes the same
  bytes).
  fix28, finding 12's rest: `scene --command` names on stderr each word that
  holds an escaped character (it must be retyped), and a ZWNJ or ZWJ that
  joins letters by RFC 5892's contextual rule (Persian's ZWNJ between
  joining letters, a ZWJ after a virama) is written as it is, so that a
  Persian or Devanagari title's record re-makes its image; between Latin
  letters or in an emoji sequence they stay escaped.
usage: test_attack8_record.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil
import subprocess

import sptest
from sptest import done, err, ok

exe, src, work, _ = sptest.setup("attack8-record", [])
run = sptest.runner_bytes(exe, work)
scenes = os.path.join(src, "..", "scenes")
chaotic = os.path.abspath(os.path.join(scenes, "chaotic.ini"))
damped = os.path.abspath(os.path.join(scenes, "damped.ini"))
default = os.path.abspath(os.path.join(scenes, "default.ini"))


def path(*names):
    return os.path.join(work, *names)


command = sptest.scene_command(run)  # what `scene NAME --command` prints


def rerun(line, out):
    """The recorded line run by a POSIX shell (springpend as exe), -o out."""
    assert line.startswith("springpend ")
    sh = "'" + exe.replace("'", "'\\''") + "'" + line[len("springpend"):] + f" -o {out} -q"
    return subprocess.run(["sh", "-c", sh], cwd=work, capture_output=True, timeout=60)


def read(name):
    with open(path(name), "rb") as f:
        return f.read()


# ---- finding 10: the scene a shard's command names ----
sweep = ["--vary", "initial.angle=0.1:1:4", "--measure", "lyapunov", "--time", "2"]
for i in (1, 2):
    r = run("sweep", chaotic, *sweep, "--shard", f"{i}/2", "--csv", f"r{i}.csv", "-q")
    ok(r.returncode == 0, f"finding 10: shard {i}/2 of chaotic.ini written ({err(r)[:200]})")
r = run("sweep", "--merge", "r1.csv", "r2.csv", "-o", "m.png", "-q")
ok(r.returncode == 0 and os.path.exists(path("m.png")),
   f"finding 10: the shards as written merge ({err(r)[:200]})")
meta = read("r1.csv-metadata.json").decode()
ok(chaotic in meta, "finding 10: the shard's command names chaotic.ini")
with open(path("r1.csv-metadata.json"), "w") as f:
    f.write(meta.replace(chaotic, damped))
r = run("sweep", "--merge", "r1.csv", "r2.csv", "-o", "m2.png", "-q")
e = err(r)
ok(r.returncode == 2 and not os.path.exists(path("m2.png")) and "damped.ini" in e and
   "dc:source" in e and "prov:wasGeneratedBy" in e,
   f"finding 10: a command naming damped.ini for chaotic's shard is refused, naming it "
   f"(exit {r.returncode}: {e[:300]})")

# ---- finding 11: invisible characters that are not Cf ----
for c in ("\u034f", "\ufe0f", "\u3164", "\u115f", "\u2800", "\u2065", "\U000e0100"):
    name = f"d{c}.ini"
    shutil.copy(default, path(name))
    r = run("still", name, "--at", "1", "--size", "320x180", "-o", "inv.png", "-q")
    line = command("inv.png")
    want = f"\\u{ord(c):04x}" if ord(c) <= 0xffff else f"\\U{ord(c):08x}"
    ok(r.returncode == 0 and c not in line and f"still 'd{want}.ini'" in line,
       f"finding 11: U+{ord(c):04X} in a scene's name is recorded as {want} ({line[:120]!r})")
    r = run("still", name + "x")
    ok(c not in err(r) and want in err(r),
       f"finding 11: U+{ord(c):04X} in a message is shown as {want} ({err(r)[:120]!r})")
    os.remove(path(name))

os.makedirs(path("zr", "e"), exist_ok=True)
os.makedirs(path("zr", "a"), exist_ok=True)
r = run("still", default, "--at", "1", "--size", "320x180", "-o", "a.png", "-q")
shutil.copy(path("a.png"), path("zr", "e", "x.png"))
shutil.copy(path("a.png"), path("zr", "a", "x\u200b\u034f.png"))
r = run("compare", "zr/e", "zr/a", "--summary", "zr.md", "--junit", "zr.xml",
        "--report", "zr.html")
for rep, shown in (("zr.md", "\\\\u200b\\\\u034f"), ("zr.xml", "\\u200b\\u034f"),
                   ("zr.html", "\\u200b\\u034f")):
    text = read(rep).decode() if os.path.exists(path(rep)) else ""
    ok(text and "\u200b" not in text and "\u034f" not in text and shown in text,
       f"finding 11: compare's {rep} shows the name's U+200B and U+034F escaped "
       f"as {shown}")

# ---- finding 12: a backslash shown as \\ ----
t_real = "view.title=a\\b'c\u200cd"       # a backslash, a quote and U+200C
t_typed = "view.title=a\\b'c\\u200cd"     # ... and the six characters \u200c
for t, out in ((t_real, "fa.png"), (t_typed, "fb.png")):
    r = run("still", default, "--at", "1", "--size", "320x180", "--set", t, "-o", out, "-q")
    ok(r.returncode == 0, f"finding 12: a still titled {t!r} ({err(r)[:200]})")
la, lb = command("fa.png"), command("fb.png")
ok(la != lb and "\u200c" not in la,
   f"finding 12: U+200C and a typed \\u200c record different lines ({la[-40:]!r} vs {lb[-40:]!r})")
r = rerun(lb, "fb2.png")
ok(r.returncode == 0 and read("fb.png") == read("fb2.png"),
   f"finding 12: the typed title's record (a backslash, a quote) re-makes the same bytes in "
   f"sh ({err(r)[:200]})")
r = run("compare", "fa.png", "fb.png")
lines = [x for x in r.stdout.decode().splitlines() if "view.title" in x]
ok(len(lines) == 1 and "a\\\\b'c\\u200cd (expected) vs a\\\\b'c\\\\u200cd (actual)" in lines[0],
   f"finding 12: compare tells U+200C from a typed \\u200c ({lines[:1]!r})")
r = run("still", "no\\such.ini")
ok("no\\\\such.ini" in err(r), f"finding 12: a backslash in a message shows as \\\\ ({err(r)[:100]!r})")

# ---- finding 12's rest (fix28): joiners that join are kept; words to retype named ----
# RFC 5892 A.1/A.2 by hand: MEEM, FARSI YEH (dual-joining) ZWNJ KHAH (dual-joining);
# KA, VIRAMA (combining class 9) ZWJ SSA; Latin letters and an emoji ZWJ sequence join nothing
persian = "view.title=\u0645\u06cc\u200c\u062e\u0648\u0627\u0647\u0645"
conjunct = "view.title=\u0915\u094d\u200d\u0937 \u0915\u094d\u200c\u0937"
for t, out in ((persian, "fp.png"), (conjunct, "fd.png")):
    r = run("still", default, "--at", "1", "--size", "320x180", "--set", t, "-o", out, "-q")
    line = command(out)
    said = err(run("scene", out, "--command"))
    r2 = rerun(line, "re-" + out) if line.startswith("springpend ") else None
    ok(r.returncode == 0 and t in line and "\\u200" not in line and not said
       and r2 is not None and r2.returncode == 0 and read(out) == read("re-" + out),
       f"fix28: {t[11:]!r}: its joiners recorded as they are, no word to retype, and the "
       f"record re-makes the same bytes ({line[-60:]!r}; {said[:200]!r})")
# (ALEF is right-joining: a ZWNJ after it has no join to break; RFC 5892 wants L or D)
latin = "view.title=a\u200cb x\u200dy \u0627\u200c\u0628"
r = run("still", default, "--at", "1", "--size", "320x180", "--set", latin, "-o", "fl.png", "-q")
line, said = command("fl.png"), err(run("scene", "fl.png", "--command"))
shown = "view.title=a\\u200cb x\\u200dy \u0627\\u200c\u0628"
ok(r.returncode == 0 and shown in line
   and f"word 9 of that command, {shown}, holds U+200C, U+200D:" in said
   and "retype that word" in said,
   f"fix28: ZWNJ between Latin letters or after ALEF and ZWJ between Latin letters stay "
   f"escaped, and scene --command names word 9 and both characters on stderr ({line[-50:]!r}; "
   f"{err(r)[:100]} {said[:300]!r})")
shutil.copy(default, path("d\xff.ini".encode("latin-1").decode("utf-8", "surrogateescape")))
r = run("still", b"d\xff.ini", "--at", "1", "--size", "160x90", "-o", "fx.png", "-q")
said = err(run("scene", "fx.png", "--command"))
ok(r.returncode == 0 and "word 3 of that command, d\\xff.ini, holds the byte 0xff (not UTF-8)"
   in said, f"fix28: a scene name with a byte that is not UTF-8: word 3 named ({said[:200]!r})")
# compare's reports show a Persian name as it is, a Latin one's ZWNJ escaped
os.makedirs(path("zp", "e"), exist_ok=True)
os.makedirs(path("zp", "a"), exist_ok=True)
shutil.copy(read_path := path("fp.png"), path("zp", "a", "\u0645\u06cc\u200c\u062e.png"))
shutil.copy(read_path, path("zp", "a", "a\u200cb.png"))
r = run("compare", "zp/e", "zp/a", "--summary", "zp.md", "--junit", "zp.xml", "--report", "zp.html")
out = r.stdout.decode()
for text, what in [(out, "stdout")] + [(read(n).decode() if os.path.exists(path(n)) else "", n)
                                        for n in ("zp.md", "zp.xml", "zp.html")]:
    escaped = "a\\\\u200cb" if what.endswith(".md") else "a\\u200cb"  # Markdown's \\ shows \
    ok("\u0645\u06cc\u200c\u062e.png" in text and "a\u200cb" not in text and escaped in text,
       f"fix28: compare's {what} shows a Persian name's ZWNJ as it is and a Latin one's escaped")
done()
