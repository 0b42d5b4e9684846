#!/usr/bin/env python3
"""The commands are shells (issue 27): src/cli/ parses argv into options and
hands an engine a desc. Checked here:
1. no function in src/cli/ runs over 100 lines (a parser or a command that
   grows past that is doing an engine's work, or wants splitting);
2. the engines moved out of cli/ stay out: no file in src/cli/ defines the
   compare run's, the sweep merge's or the data export's own functions
   (their names: compare_videos, check_rows, write_samples, ...);
3. the check of 1 can fail: a 101-line function in a fake file is found.
usage: test_cli_shells.py SOURCE_ROOT"""
import os
import re
import sys
import tempfile

root = sys.argv[1]
LIMIT = 100
print("1..3")


def long_functions(path):
    """Every function of the C file at path over LIMIT lines, as
    'FILE:LINE: NAME is N lines' (a function: a line '{' at column 0 after
    its signature, to the next '}' at column 0)."""
    lines = open(path).read().split("\n")
    found = []
    i = 0
    while i < len(lines):
        if lines[i] == "{" and i > 0:
            j = i - 1  # the signature's first line
            while j > 0 and lines[j - 1].strip() and not lines[j - 1].startswith(
                    ("}", "/*", " *", "#")) and not lines[j - 1].endswith(";"):
                j -= 1
            k = i + 1
            while k < len(lines) and lines[k] != "}":
                k += 1
            n = k - j + 1
            name = re.search(r"(\w+)\s*\(", " ".join(lines[j:i]))
            if n > LIMIT:
                found.append(f"{os.path.basename(path)}:{j + 1}: "
                             f"{name.group(1) if name else '?'} is {n} lines")
            i = k
        i += 1
    return found


cli = os.path.join(root, "src", "cli")
sources = sorted(os.path.join(cli, f) for f in os.listdir(cli) if f.endswith(".c"))
bad = [b for s in sources for b in long_functions(s)]
print(f"{'not ' if bad else ''}ok 1 - no function in src/cli/ is over {LIMIT} lines"
      + "".join(f"\n# {b}" for b in bad))

engine = {  # name -> where it lives now
    "compare_videos": "src/compare/compare_run.c", "compare_folders": "src/compare/compare_run.c",
    "apply_update": "src/compare/compare_run.c", "check_rows": "src/sweep/sweep_merge.c",
    "same_sweep": "src/sweep/sweep_merge.c", "read_shard_meta": "src/sweep/sweep_merge.c",
    "write_samples": "src/frame/data_export.c", "write_crossings": "src/frame/data_export.c",
    "write_metadata": "src/frame/data_export.c",
}
inside = []
for s in sources:
    text = open(s).read()
    for name, home in engine.items():
        if re.search(r"^(static\s+)?[\w\s\*]+\b" + name + r"\s*\(", text, re.M):
            inside.append(f"{os.path.relpath(s, root)} defines {name} (its home: {home})")
homes_ok = all(os.path.exists(os.path.join(root, h)) and
               re.search(r"\b" + n + r"\s*\(", open(os.path.join(root, h)).read())
               for n, h in engine.items())
print(f"{'ok' if not inside and homes_ok else 'not ok'} 2 - the compare run, the sweep merge "
      f"and the data export live outside src/cli/ (in compare/, sweep/, frame/)"
      + "".join(f"\n# {b}" for b in inside) + ("" if homes_ok else "\n# an engine's home moved"))

with tempfile.TemporaryDirectory() as t:
    fake = os.path.join(t, "x.c")
    open(fake, "w").write("static int short_one(void)\n{\n    return 0;\n}\n\n"
                          "int long_one(int a,\n             int b)\n{\n"
                          + "    a++;\n" * 97 + "    return a + b;\n}\n")
    found = long_functions(fake)
    print(f"{'ok' if found == ['x.c:6: long_one is 102 lines'] else 'not ok'} 3 - the length "
          f"check finds a function over {LIMIT} lines and passes a short one ({found})")
