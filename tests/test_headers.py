#!/usr/bin/env python3
"""include/springpend/ is the folder of module contracts: each header compiles
on its own (its own includes suffice), twice in one file (its guard works),
with only include/ on the path (no contract reaches into src/'s private
headers), warnings as errors.
usage: test_headers.py SOURCE_ROOT CC [CC_ARGS...]"""
import os
import subprocess
import sys

root, cc = sys.argv[1], sys.argv[2:]
inc = os.path.join(root, "include")
headers = sorted(h for h in os.listdir(os.path.join(inc, "springpend")) if h.endswith(".h"))
print(f"1..{len(headers) + 1}")
n = 0
for h in headers:
    src = f'#include "springpend/{h}"\n#include "springpend/{h}"\n'
    r = subprocess.run(cc + ["-std=gnu11", "-Wall", "-Wextra", "-Werror", "-fsyntax-only",
                             "-I", inc, "-x", "c", "-"],
                       input=src, capture_output=True, text=True)
    n += 1
    ok = r.returncode == 0
    print(f"{'ok' if ok else 'not ok'} {n} - springpend/{h} compiles alone and twice"
          + ("" if ok else "\n# " + r.stderr.strip().replace("\n", "\n# ")))
# the test itself must be able to fail: a header that needs what it does not include
r = subprocess.run(cc + ["-std=gnu11", "-Werror", "-fsyntax-only", "-x", "c", "-"],
                   input="void f(size_t n);\n", capture_output=True, text=True)
n += 1
print(f"{'ok' if r.returncode != 0 else 'not ok'} {n} - the check fails on a header missing an include")
