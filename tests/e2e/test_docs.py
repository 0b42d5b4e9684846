#!/usr/bin/env python3
"""springpend tests: the manual (README.md and the doc/*.md pages) against the
program it describes. The scene key table (doc/scenes.md) lists exactly the
keys `springpend keys` prints, with the same preset default; the exit
statuses in the README are those of `springpend --help`; every field `info
--json` prints is named in the manual; every script in the tree (the
build's, the benchmarks, plant_bugs.py) answers --help, and says its usage
when called without arguments; every link and picture of the manual resolves, and the README links
every page.
usage: test_docs.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

from sptest import doc_page, doc_pages, done, manual, ok

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
root = os.path.join(src, "..")
with open(os.path.join(root, "README.md"), encoding="utf-8") as f:
    readme = f.read()
text = manual(root)


def run(*args):
    return subprocess.run([exe, *args], capture_output=True, text=True)


# ---- the scene key table against `springpend keys` -------------------------
keys, section = {}, None
for line in run("keys").stdout.splitlines():
    m = re.match(r"  \[(\w+)\]$", line)
    if m:
        section = m.group(1)
        keys[section] = {}
        continue
    m = re.match(r"    (\w+)\s+default (\S+)", line)
    if m and section:
        keys[section][m.group(1)] = m.group(2)
table = {}
for line in doc_page(root, "scenes").split("# Scene files", 1)[1].split("\n\n", 3)[2].splitlines():
    m = re.match(r"\| `\[(\w+)\]` \| (.*) \|$", line)
    if m:
        # the key names: backquoted words before a "(" or "," that are not values
        cells = re.sub(r"\([^()]*(\([^()]*\)[^()]*)*\)", "", m.group(2))
        table[m.group(1)] = set(re.findall(r"`(\w+)`", cells))
# (a row may describe a section of another syntax, as [timeline]'s cues)
ok(keys and set(keys) <= set(table),
   f"doc/scenes.md's key table has a row for each section: {sorted(table)} vs {sorted(keys)}")
for sec in sorted(keys):
    missing, extra = set(keys[sec]) - table.get(sec, set()), table.get(sec, set()) - set(keys[sec])
    ok(not missing and not extra,
       f"[{sec}] in doc/scenes.md's table is what `keys` lists (missing {sorted(missing)}, extra {sorted(extra)})")
preset = keys.get("video", {}).get("preset")
said = re.findall(r"`preset` \(default `?(\w+)`?", text)
ok(preset and said and all(p == preset for p in said),
   f"the manual gives the preset default `keys` gives ({preset}): {said}")

# ---- exit statuses: README against --help -----------------------------------
help_text = run("--help").stdout
block = help_text.split("exit status:", 1)[1] if "exit status:" in help_text else ""
para = readme.split("Exit status:", 1)[1].split("\n\n", 1)[0] if "Exit status:" in readme else ""


def statuses(text):
    """The exit statuses and signals a text names."""
    return set(re.findall(r"\b(\d{1,3})\b", text)) | set(re.findall(r"SIG[A-Z0-9]+", text))


ok(block and para and statuses(block) == statuses(para) and "compare" in block and "compare" in para,
   f"the README's exit statuses are --help's: {sorted(statuses(para))} vs {sorted(statuses(block))}")

# ---- info --json: every field named ------------------------------------------
r = run("info", os.path.join(root, "scenes", "default.ini"), "--json")
fields = list(json.loads(r.stdout)) if r.returncode == 0 else []
info_para = text.split("`springpend info SCENE --json`", 1)[1].split("\n\n", 1)[0]
unnamed = [k for k in fields if f"`{k}`" not in info_para]
ok(fields and not unnamed, f"the manual names every field info --json prints ({len(fields)}; unnamed {unnamed})")

# ---- every script answers --help, and says its usage when called wrongly ----
# (the build's own helpers as well as the benchmarks and tests/plant_bugs.py;
# plant_bugs.py takes no required argument, so it is not run bare: that
# would plant every bug)
scripts = sorted(os.path.relpath(os.path.join(d, n), root)
                 for d in (os.path.join(root, "doc"), os.path.join(root, "shaders"), src,
                           os.path.join(src, "bench"))
                 for n in os.listdir(d) if n.endswith(".py"))
out_dir = tempfile.mkdtemp(prefix="springpend-docs-")  # the scripts' working folder
ok(len(scripts) >= 10, f"the scripts are found ({scripts})")
for script in scripts:
    path = os.path.join(root, script)
    r = subprocess.run([sys.executable, path, "--help"], capture_output=True, text=True,
                       timeout=60, cwd=out_dir)
    ok(r.returncode == 0 and "usage" in r.stdout.lower() and "Traceback" not in r.stderr,
       f"{script} --help prints its usage: exit {r.returncode} {r.stderr.strip()[-200:]}")
    if script.endswith("plant_bugs.py"):
        continue
    r = subprocess.run([sys.executable, path], capture_output=True, text=True, timeout=60,
                       cwd=out_dir)
    ok(r.returncode != 0 and "usage" in r.stderr.lower() and "Traceback" not in r.stderr,
       f"{script} without arguments says its usage, not a traceback: {r.stderr.strip()[-200:]}")
ok(not [n for n in os.listdir(out_dir) if n.startswith("-")],
   "no script wrote a file named after an option")
shutil.rmtree(out_dir)
# ---- the README's install lines and .ci/run's: the same packages -----------
def packages(line):
    return line.split("apt-get install -y --no-install-recommends ", 1)[1].split(" && ")[0].split()


lines = [l for l in readme.splitlines() if l.startswith("apt-get update && apt-get install -y")]
ci = [l for l in open(os.path.join(root, ".ci", "run")).read().splitlines()
      if l.startswith("apt-get update && apt-get install -y")]
ok(len(lines) == 2 and len(ci) == 1 and packages(lines[0]) == packages(lines[1]) == packages(ci[0]),
   f"the README's two install lines and .ci/run's name the same packages "
   f"({[len(packages(l)) for l in lines + ci]} packages; only in .ci/run: "
   f"{sorted(set(packages(ci[0])) - set(packages(lines[0]))) if ci and lines else '?'})")

# ---- the manual's links and pictures resolve --------------------------------
# A page moved or a picture renamed left links that lead nowhere: every
# relative link and image (Markdown or <img src>) of README.md and doc/*.md
# names an existing file (the pictures live in doc/pictures/),
# and an anchor (#name) a heading of the page it points into.
def anchors(path):
    """The anchors of a Markdown page's headings, as GitHub makes them."""
    names, fence = set(), False
    for line in open(path, encoding="utf-8").read().splitlines():
        if line.startswith("```"):
            fence = not fence
        elif not fence and re.match(r"#{1,6} ", line):
            names.add(re.sub(r"[^\w\- ]", "", line.lstrip("#").strip().lower()).replace(" ", "-"))
    return names


pages = doc_pages(root)
for page in pages:
    body = re.sub(r"^```.*?^```", "", open(page, encoding="utf-8").read(), flags=re.S | re.M)
    targets = re.findall(r"\]\(([^)\s]+)\)", body) + re.findall(r'<img src="([^"]+)"', body)
    bad = []
    for target in targets:
        if re.match(r"[a-z]+:", target):
            continue
        path, _, anchor = target.partition("#")
        path = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
        if not os.path.exists(path) or (anchor and anchor not in anchors(path)):
            bad.append(target)
    ok(not bad, f"{os.path.relpath(page, root)}: its {len(targets)} links and pictures "
       f"resolve (not: {bad})")
linked = set(re.findall(r"\]\(doc/([\w-]+\.md)[)#]", readme))
unlinked = [os.path.basename(p) for p in pages[1:] if os.path.basename(p) not in linked]
ok(len(pages) > 1 and not unlinked, f"the README links every doc/ page ({len(pages) - 1}; not {unlinked})")
done()
