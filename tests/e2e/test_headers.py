#!/usr/bin/env python3
"""include/springpend/ is the folder of module contracts: each header compiles
on its own (its own includes suffice), twice in one file (its guard works),
with only include/ on the path (no contract reaches into src/'s private
headers), warnings as errors.
The folders of src/ are walls: only include/ and src/ are on the include
path, so a file reaches a private header of its own folder by its bare name
and another folder's only by a path from src/ ("frame/canvas.h"); such a
header must say, in its opening comment, that it is shared with the
including folder ("Shared with: cli, pipeline." or "Shared with: every
folder."). tests/ may open any box.
Signals have one owner: only main.c (which hands each command its flag as a
cancel pointer) and the pipeline (which holds the handlers while it
renders) include base/signals.h; the code below is handed a cancel flag.
usage: test_headers.py SOURCE_ROOT CC [CC_ARGS...]"""
import os
import re
import subprocess
import sys

root, cc = sys.argv[1], sys.argv[2:]
inc = os.path.join(root, "include")
headers = sorted(h for h in os.listdir(os.path.join(inc, "springpend")) if h.endswith(".h"))
print(f"1..{len(headers) + 5}")
n = 0


def shared_with(header):
    """The folders a private header says it is shared with ({"*"}: every
    folder), from its opening comment."""
    try:
        head = open(header).read().split("*/", 1)[0]
    except OSError:
        return set()
    head = re.sub(r"\([^)]*\)", "", " ".join(head.replace("*", " ").split()))  # no (why)
    m = re.search(r"Shared with:\s*([^.]*)\.", head)
    if not m:
        return set()
    if m.group(1).strip() == "every folder":
        return {"*"}
    return {w.strip().rstrip("/") for w in m.group(1).split(",")}


def crossings(src):
    """Every include under src that crosses a folder without the header's
    leave, or reaches out with .., as 'FILE:LINE: what'."""
    bad = []
    for d, _, files in os.walk(src):
        folder = os.path.relpath(d, src)
        for f in sorted(files):
            if not f.endswith((".c", ".h")):
                continue
            path = os.path.join(d, f)
            for i, line in enumerate(open(path), 1):
                m = re.match(r'\s*#\s*include\s*"([^"]+)"', line)
                if not m or m.group(1).startswith("springpend/"):
                    continue
                name = m.group(1)
                where = f"src/{folder}/{f}:{i}"
                if ".." in name.split("/"):
                    bad.append(f"{where}: {name} reaches out with ..")
                elif "/" not in name:
                    if not os.path.exists(os.path.join(d, name)) and any(
                            os.path.exists(os.path.join(src, o, name)) for o in os.listdir(src)):
                        bad.append(f"{where}: {name} is another folder's: name its folder")
                else:
                    owner = name.split("/")[0]
                    if owner == folder:
                        bad.append(f"{where}: {name} is its own folder's: include it bare")
                    elif not os.path.exists(os.path.join(src, name)):
                        continue  # a generated header
                    elif not shared_with(os.path.join(src, name)) & {"*", folder}:
                        bad.append(f"{where}: {name} is private to {owner}/ (its opening "
                                   f"comment does not say 'Shared with: {folder}')")
    return bad


for h in headers:
    src = f'#include "springpend/{h}"\n#include "springpend/{h}"\n'
    r = subprocess.run(cc + ["-std=gnu11", "-Wall", "-Wextra", "-Werror", "-fsyntax-only",
                             "-I", inc, "-x", "c", "-"],
                       input=src, capture_output=True, text=True)
    n += 1
    ok = r.returncode == 0
    print(f"{'ok' if ok else 'not ok'} {n} - springpend/{h} compiles alone and twice"
          + ("" if ok else "\n# " + r.stderr.strip().replace("\n", "\n# ")))
bad = crossings(os.path.join(root, "src"))
n += 1
print(f"{'not ' if bad else ''}ok {n} - no include crosses a folder of src/ but to a header "
      "shared with it" + "".join(f"\n# {b}" for b in bad))
# the signal handlers have one owner: main.c and the pipeline
owners = {"src/cli/main.c", "src/pipeline/pipeline.c", "src/base/signals.c", "src/base/signals.h"}
signals = []
for d, _, files in os.walk(os.path.join(root, "src")):
    for f in sorted(files):
        path = os.path.join(d, f)
        rel = os.path.relpath(path, root)
        if f.endswith((".c", ".h")) and rel not in owners and re.search(
                r'^\s*#\s*include\s*"(base/)?signals\.h"', open(path).read(), re.M):
            signals.append(rel)
n += 1
print(f"{'not ' if signals else ''}ok {n} - only main.c and the pipeline include base/signals.h "
      f"(the rest are handed a cancel flag){''.join(chr(10) + '# ' + s for s in signals)}")
# ... and the check can fail: a crossing without leave, one with .., and a shared one
import tempfile  # noqa: E402
with tempfile.TemporaryDirectory() as t:
    for d in ("a", "b"):
        os.makedirs(os.path.join(t, d))
    open(os.path.join(t, "a", "p.h"), "w").write("/* private to a */\n")
    open(os.path.join(t, "a", "s.h"), "w").write("/* shared.\n * Shared with: c (why, x.c), b\n * (why). */\n")
    open(os.path.join(t, "b", "x.c"), "w").write(
        '#include "a/p.h"\n#include "../a/s.h"\n#include "a/s.h"\n#include "s.h"\n')
    found = crossings(t)
    n += 1
    print(f"{'ok' if [f.split(': ')[0] for f in found] == ['src/b/x.c:' + str(i) for i in (1, 2, 4)] else 'not ok'}"
          f" {n} - the check refuses a private header from another folder, by path or bare, "
          f"and a .. path, and passes a shared one ({found})")
# the include path itself is the wall: only include/ and src/ on it
meson = open(os.path.join(root, "meson.build")).read()
paths = re.findall(r"include_directories\(([^)]*)\)", meson)
n += 1
print(f"{'ok' if paths and all(set(re.findall(r'[a-z/]+', p)) == {'include', 'src'} for p in paths) else 'not ok'}"
      f" {n} - meson.build puts only include/ and src/ on the include path ({paths})")
# the test itself must be able to fail: a header that needs what it does not include
r = subprocess.run(cc + ["-std=gnu11", "-Werror", "-fsyntax-only", "-x", "c", "-"],
                   input="void f(size_t n);\n", capture_output=True, text=True)
n += 1
print(f"{'ok' if r.returncode != 0 else 'not ok'} {n} - the check fails on a header missing an include")
