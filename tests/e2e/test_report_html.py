#!/usr/bin/env python3
"""springpend tests: compare --report, loaded in headless Chromium (Debian's
chromium): the page's rows in order (errors, failures, passes), images
embedded, the flip control working, a screenshot written.
Skips (77) without chromium.
usage: test_report_html.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR (TAP)"""
import base64
import os
import re
import shutil
import subprocess
import sys
import tempfile

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "report_html"))
chromium = shutil.which("chromium") or shutil.which("chromium-browser")
if not chromium:
    print("1..0 # SKIP chromium is not installed")
    sys.exit(77)
shutil.rmtree(work, ignore_errors=True)
base, act = os.path.join(work, "base"), os.path.join(work, "act")
os.makedirs(base), os.makedirs(act)
count = failed = 0


def ok(cond, what):
    global count, failed
    count += 1
    failed += not cond
    print(f"{'' if cond else 'not '}ok {count} - {what}".replace("\n", " | "), flush=True)
    return cond


default = os.path.join(src, "..", "scenes", "default.ini")
for folder, name, at in ((base, "same", 2), (act, "same", 2), (base, "moved", 2), (act, "moved", 2.2),
                         (act, "new", 1)):
    subprocess.run([exe, "still", default, "--size", "128x96", "--at", str(at), "-q",
                    "-o", os.path.join(folder, name + ".png")], check=True)
report = os.path.join(work, "report.html")
r = subprocess.run([exe, "compare", base, act, "--report", report, "--diff",
                    os.path.join(work, "diffs")], capture_output=True, text=True)
ok(r.returncode == 2 and os.path.exists(report), f"compare --report: written ({r.stdout.strip()})")


def chrome(*args, url):
    with tempfile.TemporaryDirectory() as profile:
        return subprocess.run([chromium, "--headless", "--no-sandbox", "--disable-gpu",
                               "--disable-background-networking", "--disable-component-update",
                               "--disable-sync", "--no-first-run", f"--user-data-dir={profile}",
                               *args, url], capture_output=True, text=True, timeout=60, cwd=work)


url = "file://" + report
dom = chrome("--dump-dom", url=url).stdout
rows = re.findall(r'<tr class="row v-(\w+)"><td class="figures"><div class="name">([^<]+)</div>', dom)
ok(rows == [("error", "new.png"), ("fail", "moved.png"), ("pass", "same.png")],
   f"Chromium shows the rows failures first: {rows}")
ok("1 passed, 1 failed, 1 missing or unreadable" in dom and "no baseline" in dom
   and "--update=missing" in dom, "the summary, the error and how to fix it are on the page")
b64 = lambda p: base64.b64encode(open(p, "rb").read()).decode()
ok(b64(os.path.join(base, "moved.png")) in dom and b64(os.path.join(act, "moved.png")) in dom
   and b64(os.path.join(work, "diffs", "moved.diff.png")) in dom,
   "expected, actual and diff are embedded (self-contained)")
flip = lambda d: re.findall(r'<img class="flipimg" alt="(\w+)" src="data:image/png;base64,([^"]+)"', d)
before, after = flip(dom), flip(chrome("--dump-dom", url=url + "#flip").stdout)
# (same.png's pixels are identical: shown once, with no flip)
ok(len(before) == 1 and len(after) == 1 and before[0][0] == "actual" and after[0][0] == "expected"
   and before[0][1] == b64(os.path.join(act, "moved.png"))
   and after[0][1] == b64(os.path.join(base, "moved.png")),
   f"the flip control swaps actual for expected ({[a for a, _ in before]} -> {[a for a, _ in after]})")
shot = os.path.join(work, "report.png")
chrome(f"--screenshot={shot}", "--window-size=1200,800", url=url)
head = open(shot, "rb").read(24) if os.path.exists(shot) else b""
ok(head[:8] == b"\x89PNG\r\n\x1a\n" and head[16:24] == bytes.fromhex("000004b000000320"),
   f"a 1200x800 screenshot of the report: {shot}")
print(f"1..{count}")
sys.exit(1 if failed else 0)
