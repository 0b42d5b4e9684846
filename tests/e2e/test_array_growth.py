#!/usr/bin/env python3
"""Arrays grow one way (issue 27): the only realloc in src/ is the one in
base/array.c, behind SP_ARRAY_RESERVE / sp_array_reserve (libplacebo's
PL_ARRAY_APPEND is the model), which doubles, checks count * size for
overflow and says SP_E_NOMEM. A realloc or reallocarray call anywhere else
in src/ (comments and strings aside) fails, unless it is in PENDING: sites
left for a file another piece of work was rewriting, reported, not failed.
A listed site that is gone is only noted.
The check runs on a made-up tree first, to show that it can fail.
usage: test_array_growth.py SOURCE_ROOT   (TAP on stdout)"""
import os
import re
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sptest import done, ok  # noqa: E402

HELPER = "base/array.c"
CALL = re.compile(r"\b(realloc|reallocarray)\s*\(")

# file under src/: bare reallocs left there on purpose, and why
PENDING = {}

def code_only(text):
    """text with comments, string and character literals blanked (newlines
    kept, so line numbers stay)."""
    def blank(m):
        return re.sub(r"[^\n]", " ", m.group(0))
    return re.sub(r'/\*.*?\*/|//[^\n]*|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', blank, text,
                  flags=re.S)


def check(root, pending):
    """Bare reallocs outside the helper and not pending, as 'FILE:LINE: ...',
    and the pending ones still there."""
    bad, still = [], []
    src = os.path.join(root, "src")
    for d, _, files in os.walk(src):
        for f in sorted(files):
            if not f.endswith((".c", ".h")):
                continue
            path = os.path.join(d, f)
            rel = os.path.relpath(path, src).replace(os.sep, "/")
            if rel == HELPER:
                continue
            text = code_only(open(path, encoding="utf-8").read())
            for i, line in enumerate(text.split("\n"), 1):
                m = CALL.search(line)
                if not m:
                    continue
                if rel in pending:
                    still.append(f"src/{rel}:{i}: {m.group(1)} ({pending[rel]})")
                else:
                    bad.append(f"src/{rel}:{i}: a bare {m.group(1)}; grow the array with "
                               f"SP_ARRAY_RESERVE (base/array.h), or sp_array_reserve for a "
                               f"buffer with a limit")
    return bad, still


# the check can fail: a made-up tree with a bare realloc, one in a comment
# and a string, and the helper's own
with tempfile.TemporaryDirectory() as tmp:
    os.makedirs(os.path.join(tmp, "src", "frame"))
    os.makedirs(os.path.join(tmp, "src", "base"))
    with open(os.path.join(tmp, "src", "base", "array.c"), "w") as fh:
        fh.write("void *p = realloc(*items, want * size);\n")
    with open(os.path.join(tmp, "src", "frame", "grow.c"), "w") as fh:
        fh.write("/* realloc(x, 2) in a comment */\nconst char *s = \"realloc(\";\n"
                 "int grow(void)\n{\n    p = realloc (p, n * 2);\n    q = reallocarray(q, n, 8);\n}\n")
    bad, _ = check(tmp, {})
    ok(len(bad) == 2 and bad[0].startswith("src/frame/grow.c:5: a bare realloc")
       and bad[1].startswith("src/frame/grow.c:6: a bare reallocarray"),
       f"self-test: bare realloc and reallocarray outside the helper are refused, comments, "
       f"strings and the helper pass {bad}")
    bad, still = check(tmp, {"frame/grow.c": "why"})
    ok(not bad and len(still) == 2, f"self-test: a pending file is reported, not failed {still}")

bad, still = check(sys.argv[1], PENDING)
for s in still:
    print(f"# pending: {s}")
for f in sorted(set(PENDING) - {s.split(":")[0][len("src/"):] for s in still}):
    print(f"# pending {f} holds no realloc any more: take it off PENDING")
for b in bad:
    print(f"# {b}")
ok(not bad, f"no realloc in src/ outside {HELPER} ({len(bad)} found)")
done()
