#!/usr/bin/env python3
"""springpend tests (issue 28): the recorded command line, after the
attacker's seventh pass (doc/notes/2026-11-27/attack7.md), each check run
as the attacker ran it:
- finding 9: a merged sweep figure drawn with --size/--dpi recorded a
  command without them; now the merge records the one-piece run's command
  with the figure options it drew at, and the two figures are the same bytes;
- finding 19: a shard's prov:wasGeneratedBy was never checked; a command
  that says another grid, T or measure than the shard holds is refused,
  naming the difference;
- findings 2, 7, 12: the record read raw words: -qo FILE, words after
  '--', option values that look like options (--state -q), abbreviations
  (--sha, --cs); --state FILE was recorded. Now the words as getopt_long
  parsed them are recorded, --state FILE left out as -o is;
- findings 1, 13: a record cut after 4096 words, and records longer than
  springpend's own reader takes: a command line that cannot be recorded
  whole is refused up front (exit 2, its length and the limit);
- finding 23: a CSV's prov:wasGeneratedBy turned a byte that is not UTF-8
  into U+FFFD; it is now shown escaped (a backslash, x, two hex digits),
  as every other record shows it;
- finding 24: an SVG's record was taken from the last metadata element
  anywhere, a comment after </svg> too; one element, inside the root, or
  refused ("is there twice");
- finding 25: an MP4/WebM piece (--frames, --shard) recorded the whole
  render's command; a video piece records its part, and its record re-makes
  it byte for byte (PNG frames still record the whole run's);
- finding 18: invisible characters (Cf, Zl, Zp: U+200B, U+FEFF, U+00AD,
  U+E0041, U+2028) reached the terminal raw in records and messages; they
  are shown escaped, from HarfBuzz's general category.
- the eighth pass (doc/notes/2026-11-27/attack8.md), finding 9: with
  POSIXLY_CORRECT set, the merge read its shards' commands stopping at the
  scene, and refused springpend's own shards.
usage: test_attack7_record.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import os
import shutil

import sptest
from sptest import done, err, ok

exe, src, work, _ = sptest.setup("attack7-record", [])
run = sptest.runner_bytes(exe, work)
scenes = os.path.join(src, "..", "scenes")
chaotic = os.path.join(scenes, "chaotic.ini")
default = os.path.join(scenes, "default.ini")


def path(*names):
    return os.path.join(work, *names)


command = sptest.scene_command(run)  # what `scene NAME --command` prints


same_bytes = sptest.same_bytes_in(work)


# ---- finding 9: a merged figure at a printed size records its size -------------
grid = ["--vary", "initial.angle=1:179:16", "--measure", "lyapunov", "--time", "2"]
r = run("sweep", chaotic, *grid, "--size", "3in", "--dpi", "200", "-o", "one.png", "-q")
assert r.returncode == 0, err(r)
for i in (1, 2):
    r = run("sweep", chaotic, *grid, "--shard", f"{i}/2", "--csv", f"r{i}.csv", "-q")
    assert r.returncode == 0, err(r)
r = run("sweep", "--merge", "r1.csv", "r2.csv", "-o", "rm.png", "--size", "3in", "--dpi", "200",
        "-q")
ok(r.returncode == 0 and same_bytes("one.png", "rm.png"),
   f"sweep ... --size 3in --dpi 200 and the merge of its shards drawn with --size 3in --dpi 200: "
   f"the same bytes (records {command('one.png')!r} and {command('rm.png')!r})")
ok(command("rm.png").endswith("--time 2 --size 3in --dpi 200"),
   f"the merged figure records the figure options the merge drew at: {command('rm.png')!r}")
r = run("sweep", "--merge", "r1.csv", "r2.csv", "-o", "rm.svg", "--size", "3in", "-q")
c = command("rm.svg")
ok(r.returncode == 0 and c.endswith("--time 2 --size 3in") and "--shard" not in c and
   "--csv" not in c, f"a merged SVG at --size 3in records it, and no --shard/--csv: {c!r}")

# attack8.md finding 9: POSIXLY_CORRECT stopped the re-parse of a shard's
# command at its scene, so the merge refused springpend's own shards
env = dict(os.environ, POSIXLY_CORRECT="1")
r = run("sweep", "--merge", "-o", "rp.png", "--size", "3in", "--dpi", "200", "-q", "r1.csv", "r2.csv",
        env=env)
ok(r.returncode == 0 and same_bytes("one.png", "rp.png"),
   f"with POSIXLY_CORRECT set, the merge reads its shards' commands as springpend ran them: "
   f"the one-piece figure's bytes (exit {r.returncode}: {err(r)})")

# ---- finding 19: a shard's command is checked against the shard ----------------
def forged(name, change):
    """Copies of r1/r2 named NAME1/NAME2 whose prov:wasGeneratedBy is change(it)."""
    for i in (1, 2):
        shutil.copy(path(f"r{i}.csv"), path(f"{name}{i}.csv"))
        with open(path(f"r{i}.csv-metadata.json")) as f:
            m = json.load(f)
        m["prov:wasGeneratedBy"] = change(m["prov:wasGeneratedBy"])
        m["url"] = f"{name}{i}.csv"
        with open(path(f"{name}{i}.csv-metadata.json"), "w") as f:
            json.dump(m, f)


for name, change, said in [
        ("t", lambda c: c.replace("--time 2", "--time 200"), b"--time 200"),
        ("g", lambda c: c.replace("initial.angle=1:179:16", "initial.angle=5:6:2"),
         b"--vary initial.angle=5:6:2"),
        ("u", lambda c: c.replace("lyapunov", "spectrum"), b"--measure spectrum"),
        ("s", lambda c: c.replace("--shard 1/2", "--shard 2/2"), b"--shard 2/2"),
        ("o", lambda c: c.replace(" --shard", " --set pendulum.mass=2 --shard"),
         b"--set"),
        ("c", lambda c: "springpend still " + default, b"'springpend still'")]:
    forged(name, change)
    r = run("sweep", "--merge", f"{name}1.csv", f"{name}2.csv", "-o", f"{name}m.png")
    ok(r.returncode == 2 and said in r.stderr and b"prov:wasGeneratedBy" in r.stderr and
       not os.path.exists(path(f"{name}m.png")),
       f"a shard whose prov:wasGeneratedBy says {said.decode()}: refused, naming it "
       f"(exit {r.returncode}: {err(r)[-200:]!r})")
forged("n", lambda c: "rm -rf /")
r = run("sweep", "--merge", "n1.csv", "n2.csv", "-o", "nm.png")
ok(r.returncode == 0 and b"not a command line springpend writes" in r.stderr and
   "carries no command" in command("nm.png"),
   f"a prov:wasGeneratedBy that is no springpend command: merged, recording none, and said "
   f"(exit {r.returncode}: {err(r)[-160:]!r})")

# ---- findings 2, 7, 12: the words as getopt_long parsed them --------------------
still = [default, "--at", "1", "--size", "320x180"]
plain = "springpend still " + " ".join(still)
r = run("still", *still, "-q", "-o", "p.png")
assert r.returncode == 0, err(r)
for out, args in (("a.png", ["-qo", "a.png"]), ("b.png", ["-qob.png"]),
                  ("c.png", ["--ou", "c.png", "--qui"]), ("d.png", ["--output=d.png", "-q"]),
                  ("f.png", ["--state", "st.json", "-qo", "f.png"]),
                  ("g.png", ["--st=st2.json", "--ou=g.png", "-q"])):
    r = run("still", *still, *args)
    ok(r.returncode == 0 and command(out) == plain and same_bytes("p.png", out),
       f"still ... {' '.join(args)}: records {command(out)!r} and has -q -o p.png's bytes")
r = run("still", *still[1:], "-q", "-o", "sq.png", "--state", "-q", default)
c = command("sq.png")
ok(r.returncode == 0 and "--state" not in c and c.endswith(default),
   f"--state -q (a state file named -q): the value is no option, and --state FILE is "
   f"not recorded: {c!r}")
for name in ("-ofoo.ini", "--csv", "-q"):
    shutil.copy(default, path(name))
    r = run("still", *still[1:], "-q", "-o", "dd.png", "--", name)
    c = command("dd.png")
    ok(r.returncode == 0 and c.endswith(f"-- {name}"),
       f"a scene named {name} after '--' is recorded: {c!r}")
r = run("still", *still, "--se=view.hud=true", "-o", "h.png", "-q")
c = command("h.png")
ok(r.returncode == 0 and c == plain + " --set view.hud=true",
   f"--se=view.hud=true recorded as --set view.hud=true: {c!r}")
for i in (1, 2):
    r = run("sweep", chaotic, *grid, "--sha", f"{i}/2", "--cs", f"a{i}.csv", "-q")
    assert r.returncode == 0, err(r)
r = run("sweep", "--merge", "a1.csv", "a2.csv", "-o", "am.png", "-q")
r1 = run("sweep", chaotic, *grid, "-o", "aone.png", "-q")
ok(r.returncode == 0 and r1.returncode == 0 and same_bytes("am.png", "aone.png"),
   f"shards run with --sha/--cs merge into the one-piece figure's bytes "
   f"(records {command('am.png')!r})")

# ---- findings 1 and 13: a record cut, or longer than its reader takes -----------
r = run("still", *still, *(["-q"] * 4100), "--set", "view.hud=true", "-o", "long.png")
ok(r.returncode == 0 and command("long.png") == plain + " --set view.hud=true",
   f"4100 words: recorded whole ({command('long.png')[-40:]!r})")
z = "0" * 120000
for out in ("lg.png", "lg.svg"):
    size = "320x180" if out.endswith(".png") else "3in"
    r = run("still", default, "--at", "1." + z, "--size", size, "--set", "video.duration=10." + z,
            "--set", "initial.angle=10." + z, "-o", out)
    ok(r.returncode == 2 and b"at most 262143" in r.stderr and not os.path.exists(path(out)),
       f"a command line of 360 kB ({out}): refused up front, its length and the limit said "
       f"(exit {r.returncode}: {err(r)[:160]!r})")

# ---- finding 23: a CSV's record shows a byte that is not UTF-8 as \xNN -------
bad = os.fsencode(path("d")) + b"\xff.ini"
shutil.copy(default, bad)
r = run(b"data", b"d\xff.ini", b"--set", b"video.duration=0.1", b"-o", b"dx.csv")
with open(path("dx.csv-metadata.json"), encoding="utf-8") as f:
    rec = json.load(f).get("prov:wasGeneratedBy", "") if r.returncode == 0 else ""
r2 = run(b"still", b"d\xff.ini", b"--at", b"1", b"--size", b"320x180", b"-o", b"dx.png")
ok(r.returncode == 0 and "'d\\xff.ini'" in rec and "\ufffd" not in rec and
   r2.returncode == 0 and command("dx.png").split()[2] == rec.split()[2],
   f"a CSV records a scene named d<0xff>.ini as the PNG does ('d\\xff.ini'): {rec!r}")

# ---- finding 24: one SVG record, inside the root element -------------------------
# 5 in: default.ini's four panels need more than 3 in (refused there: attack13 #19)
r = run("still", default, "--at", "1", "--size", "5in", "-o", "v.svg", "-q")
assert r.returncode == 0, err(r)
with open(path("v.svg")) as f:
    svg = f.read()
tag = '<metadata id="springpend.command">'
at = svg.index(tag)
rec = svg[at:svg.index("</metadata>", at) + len("</metadata>")]
evil = rec.replace("springpend still", "springpend still evil.ini")
stag = '<metadata id="springpend.scene-file">'
sat = svg.index(stag)
srec = svg[sat:svg.index("</metadata>", sat) + len("</metadata>")]
for name, text, what in [
        ("v6.svg", svg + f"<!-- {evil} -->\n", "command"),
        ("v7.svg", svg[:at] + svg[at + len(rec):] + f"<!-- {evil} -->\n", "command"),
        ("v8.svg", svg.replace("</svg>", evil + "\n</svg>"), "command"),
        ("v9.svg", svg + "<!-- " + srec.replace("stiffness = ", "stiffness = 3") + " -->\n",
         "scene")]:
    with open(path(name), "w") as f:
        f.write(text)
    r = run("scene", name, *(["--command"] if what == "command" else []))
    ok(r.returncode == 2 and not r.stdout and (b"twice" in r.stderr or b"root element" in r.stderr),
       f"{name}: a second or misplaced {what} record (a comment after </svg>, or twice inside): "
       f"refused (exit {r.returncode}: {err(r)[:160]!r})")
ok(command("v.svg") == f"springpend still {default} --at 1 --size 5in",
   f"the SVG as written still reads: {command('v.svg')!r}")

# ---- finding 25: a video piece records its part ----------------------------------
video = [default, "--size", "320x180", "--fps", "10", "--set", "video.duration=1"]
whole = "springpend render " + " ".join(video)
for out, part in (("fr.mp4", ["--frames", "2:5"]), ("sh.webm", ["--shard", "2/4"])):
    r = run("render", *video, *part, "-o", out, "-q")
    c = command(out)
    r2 = run("render", *c.split()[2:], "-o", "again-" + out, "-q")
    ok(r.returncode == 0 and c == whole + " " + " ".join(part) and r2.returncode == 0 and
       same_bytes(out, "again-" + out),
       f"a {out[-4:]} piece ({' '.join(part)}) records its part, and its record re-makes it "
       f"byte for byte: {c!r}")
r = run("render", *video, "--frames", "2:5", "-o", "fr/%03d.png", "-q")
ok(r.returncode == 0 and command(os.path.join("fr", "003.png")) == whole,
   f"a PNG frame of --frames 2:5 still records the whole run (it is the whole run's frame): "
   f"{command(os.path.join('fr', '003.png'))!r}")

# ---- finding 18: invisible characters are shown escaped --------------------------
for ch, shown in (("\u200b", "\\u200b"), ("\ufeff", "\\ufeff"), ("\u00ad", "\\u00ad"),
                  ("\U000e0041", "\\U000e0041"), ("\u2028", "\\u2028"), ("\u2029", "\\u2029")):
    name = f"a{ch}b.ini"
    shutil.copy(default, path(name))
    r = run("still", name, "--at", "1", "--size", "320x180", "-o", f"inv{ch}.png")
    c = command(f"inv{ch}.png")
    ok(r.returncode == 0 and f"'a{shown}b.ini'" in c and ch not in c and
       shown.encode() in r.stderr and ch.encode() not in r.stderr,
       f"U+{ord(ch):04X} in a scene's and an output's name: recorded and said as {shown} "
       f"({c!r}; {err(r)!r})")

done()
