#!/usr/bin/env python3
"""springpend tests: compare's updates, counts and reports as a CI engineer
meets them (issue 24): --update=changed --report shows the baseline that was
replaced and says so; --update=all leaves baselines whose pixels are
unchanged; provenance notes whole and on passes too; empty folders and
missing baselines counted honestly; JSON counts beside updated results; the
--update hint once; JUnit times and suite names; the command line tightening
compare.ini; the frame counts of videos of different lengths.
usage: test_compare_update.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR (TAP)"""
import base64
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET
import zlib

from sptest import done, ok, skip

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "compare_update"))
default = os.path.join(src, "..", "scenes", "default.ini")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def run(*args):
    return subprocess.run([exe, *args], capture_output=True, text=True, cwd=work, timeout=120)


def W(*p):
    return os.path.join(work, *p)


def chunks(data):
    """The chunks of PNG bytes, as (type, payload)."""
    i, out = 8, []
    while i < len(data):
        n, kind = struct.unpack(">I4s", data[i:i + 8])
        out.append((kind, data[i + 8:i + 8 + n]))
        i += 12 + n
    return out


def write_chunks(path, cs):
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        for kind, body in cs:
            f.write(struct.pack(">I", len(body)) + kind + body
                    + struct.pack(">I", zlib.crc32(kind + body)))


def retext(src_path, dst, key, value):
    """A copy of src_path with tEXt chunk key set to value: the same pixels,
    other metadata (what another Mesa would write)."""
    cs = chunks(open(src_path, "rb").read())
    cs = [(k, b) for k, b in cs if not (k == b"tEXt" and b.split(b"\0")[0] == key.encode())]
    cs.insert(1, (b"tEXt", key.encode() + b"\0" + value.encode()))
    write_chunks(dst, cs)


def text_chunk(path, key):
    for k, b in chunks(open(path, "rb").read()):
        if k == b"tEXt" and b.split(b"\0")[0] == key.encode():
            return b.split(b"\0", 1)[1].decode()
    return None


for name, extra in (("a", ["--at", "3"]), ("moved", ["--at", "3.05"])):
    run("still", default, "--size", "160x120", *extra, "-o", f"{name}.png", "-q")


def folders(tag, pairs):
    """base/ and act/ folders under tag from {name: (baseline, actual)}."""
    b, a = W(tag, "base"), W(tag, "act")
    os.makedirs(b), os.makedirs(a)
    for n, (e, x) in pairs.items():
        if e:
            shutil.copy(W(e), os.path.join(b, n))
        if x:
            shutil.copy(W(x), os.path.join(a, n))
    return b, a


# --update=changed --report: the report shows the baseline as it was and
# says it was replaced; JUnit and the summary say so too.
b, a = folders("changed", {"one.png": ("a.png", "a.png"), "two.png": ("a.png", "moved.png")})
old = open(os.path.join(b, "two.png"), "rb").read()
new = open(W("moved.png"), "rb").read()
r = run("compare", b, a, "--update=changed", "--report", W("changed", "r.html"),
        "--junit", W("changed", "r.xml"))
html = open(W("changed", "r.html")).read()
row = html[html.index("two.png"):]
row = row[:row.index("</tr>")]
ok(r.returncode == 0 and base64.b64encode(old).decode() in row
   and base64.b64encode(new).decode() in row
   and row.index(base64.b64encode(old).decode()) < row.index(base64.b64encode(new).decode()),
   "--update=changed --report: the expected column holds the baseline as it was, the actual "
   "column the new image")
ok("replaced" in row, "the report's row says the baseline was replaced")
case = [c for c in ET.parse(W("changed", "r.xml")).getroot().iter("testcase")
        if c.get("name") == "two.png"][0]
ok("replaced" in (case.findtext("system-out") or ""),
   f"JUnit says replaced ({(case.findtext('system-out') or '')[:80]})")
last = r.stdout.strip().splitlines()[-1]
ok(not last.startswith("ok") and "1 updated" in last and "1 failed" in last,
   f"the summary does not say ok after replacing a failing baseline ({last})")

# JSON after an update: the counts agree with the results.
b, a = folders("json", {"one.png": ("a.png", "a.png"), "two.png": ("a.png", "moved.png")})
r = run("compare", b, a, "--update=changed", "--json")
j = json.loads(r.stdout)
verdicts = [x["verdict"] for x in j["results"]]
ok(j["counts"]["failed"] == verdicts.count("fail") == 1 and j["counts"]["updated"] == 1
   and j["pass"] is True and j["counts"]["unresolved"] == 0 and r.returncode == 0,
   f"JSON after --update=changed: failed {j['counts']['failed']} beside {verdicts.count('fail')} "
   f"results marked fail, updated {j['counts']['updated']}, pass {j['pass']}")

# --update=all never rewrites a baseline whose pixels are unchanged (only
# the renderer in its metadata differs); one whose pixels moved within the
# tolerance is replaced.
b, a = folders("all", {"same.png": ("a.png", None), "near.png": ("a.png", None)})
retext(W("a.png"), os.path.join(a, "same.png"), "Source", "llvmpipe (LLVM 19.1.7, 128 bits)")
raw = bytearray(open(W("a.png"), "rb").read())
# near.png: the same picture with one pixel one level off, re-encoded here
# (independently of springpend): the pixels differ, within tolerance.
cs = chunks(bytes(raw))
ihdr = struct.unpack(">IIBBBBB", [c for k, c in cs if k == b"IHDR"][0])
rows = bytearray(zlib.decompress(b"".join(c for k, c in cs if k == b"IDAT")))
bpp = {2: 3, 6: 4}[ihdr[3]]
stride = ihdr[0] * bpp + 1
# undo filters row by row
prev = bytearray(stride - 1)
plain = bytearray()
for y in range(ihdr[1]):
    f, line = rows[y * stride], bytearray(rows[y * stride + 1:(y + 1) * stride])
    for x in range(len(line)):
        left = line[x - bpp] if x >= bpp else 0
        up, ul = prev[x], prev[x - bpp] if x >= bpp else 0
        if f == 1:
            line[x] = (line[x] + left) & 255
        elif f == 2:
            line[x] = (line[x] + up) & 255
        elif f == 3:
            line[x] = (line[x] + (left + up) // 2) & 255
        elif f == 4:
            pa, pb, pc = abs(up - ul), abs(left - ul), abs(left + up - 2 * ul)
            line[x] = (line[x] + (left if pa <= pb and pa <= pc else up if pb <= pc else ul)) & 255
    plain += b"\0" + line
    prev = line
plain[1] = (plain[1] + 1) & 255
write_chunks(os.path.join(a, "near.png"),
             [(k, c) for k, c in cs if k == b"IHDR"] + [(b"IDAT", zlib.compress(bytes(plain)))]
             + [(b"IEND", b"")])
before = {n: open(os.path.join(b, n), "rb").read() for n in ("same.png", "near.png")}
r = run("compare", b, a, "--update=all")
after = {n: open(os.path.join(b, n), "rb").read() for n in ("same.png", "near.png")}
ok(after["same.png"] == before["same.png"] and "replaced" not in
   "".join(l for l in r.stdout.splitlines() if "same.png" in l),
   f"--update=all leaves a baseline whose pixels are unchanged (only Source differs) ({r.stdout.strip()})")
ok(after["near.png"] != before["near.png"] and r.returncode == 0,
   "--update=all replaces a baseline whose pixels moved within tolerance")

# Provenance notes whole (not cut to 16 characters) and on a pass too.
src1, src2 = "llvmpipe (LLVM 15.0.6, 256 bits)", "llvmpipe (LLVM 19.1.7, 128 bits)"
retext(W("a.png"), W("r1.png"), "Source", src1)
retext(W("a.png"), W("r2.png"), "Source", src2)
r = run("compare", W("r1.png"), W("r2.png"))
ok(r.returncode == 0 and f"{src1} vs {src2}" in r.stdout,
   f"a pass across renderers notes both renderers in full ({r.stdout.strip()})")
retext(W("moved.png"), W("r3.png"), "Source", src2)
r = run("compare", W("r1.png"), W("r3.png"), "--json")
notes = json.loads(r.stdout)["results"][0]["notes"]
ok(r.returncode == 1 and any(src1 in n and src2 in n for n in notes),
   f"a failure's renderer note in full ({notes})")

# Empty folders: not "ok"; exit 2 with the reason on stdout, JSON and JUnit.
os.makedirs(W("empty", "e")), os.makedirs(W("empty", "a"))
r = run("compare", W("empty", "e"), W("empty", "a"), "--junit", W("empty", "j.xml"))
ok(r.returncode == 2 and not r.stdout.startswith("ok") and "no PNG files" in r.stdout,
   f"empty folders: exit 2 and the summary says why ({r.stdout.strip()})")
root = ET.parse(W("empty", "j.xml")).getroot()
ok(root.get("errors") == "1" and root.find(".//error") is not None,
   "empty folders: the JUnit file has an error, not an empty pass")
r = run("compare", W("empty", "e"), W("empty", "a"), "--json")
ok(json.loads(r.stdout)["pass"] is False, "empty folders: JSON pass false")

# No baselines: nothing was compared; the hint once.
b, a = folders("missing", {f"{i}.png": (None, "a.png") for i in range(3)})
shutil.rmtree(b)
r = run("compare", b, a)
last = r.stdout.strip().splitlines()[-1]
ok(r.returncode == 2 and "0 compared" in last and "3 missing" in last,
   f"no baselines: 0 compared, 3 missing ({last})")
ok(r.stdout.count("--update=missing") == 1,
   f"the --update hint once, not per image ({r.stdout.count('--update=missing')} times)")

# JUnit: times and a suite named after the folder.
b, a = folders("snapshots_x", {"one.png": ("a.png", "a.png"), "two.png": ("a.png", "moved.png")})
run("compare", b, a, "--junit", W("t.xml"))
root = ET.parse(W("t.xml")).getroot()
times = [c.get("time") for c in root.iter("testcase")]
suites = [s.get("name") for s in root.iter("testsuite")]
ok(all(t is not None and float(t) > 0 for t in times) and root.find("testsuite").get("time"),
   f"JUnit: every test case has its time ({times})")
ok(suites and all(s.endswith("snapshots_x/base") for s in suites),
   f"JUnit: the suite is named after the baselines' folder ({suites})")

# The command line tightens compare.ini: [*] allows everything, --max-pixels 0
# still fails; --max-diff 0 beats a section's max_diff = 255.
b, a = folders("tighten", {"two.png": ("a.png", "moved.png")})
with open(os.path.join(b, "compare.ini"), "w") as f:
    f.write("[*]\nmax_pixels = 100%\n")
r1, r2 = run("compare", b, a), run("compare", b, a, "--max-pixels", "0")
ok(r1.returncode == 0 and r2.returncode == 1,
   f"[*] max_pixels = 100% passes; --max-pixels 0 tightens it to a failure ({r1.returncode}, {r2.returncode})")
with open(os.path.join(b, "compare.ini"), "w") as f:
    f.write("[two.png]\nmax_diff = 255\n")
r1 = run("compare", b, a, "--max-diff", "3")
r2 = run("compare", b, a, "--max-diff", "255")
with open(os.path.join(b, "compare.ini"), "w") as f:
    f.write("[two.png]\nmax_pixels = 0\n")
r3 = run("compare", b, a, "--max-pixels", "100%")
ok(r1.returncode == 1 and r2.returncode == 0 and r3.returncode == 1,
   f"the command line tightens a [file] section (--max-diff 3 under max_diff = 255 fails), "
   f"never loosens one (--max-pixels 100% under max_pixels = 0 fails) "
   f"({r1.returncode}, {r2.returncode}, {r3.returncode})")

# Videos of different lengths: the message gives both frame counts, as
# ffprobe counts them.
for name, dur in (("short", "0.4"), ("long", "0.7")):
    run("render", default, "--size", "96x64", "--fps", "10", "--set", f"video.duration={dur}",
        "-o", f"{name}.mp4", "-q")
if shutil.which("ffprobe"):
    def frames(p):
        return int(subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams",
                                   "v:0", "-show_entries", "stream=nb_read_frames", "-of", "csv=p=0",
                                   p], capture_output=True, text=True).stdout.strip())
    ns, nl = frames(W("short.mp4")), frames(W("long.mp4"))
    for e, x, ne, nx in (("short", "long", ns, nl), ("long", "short", nl, ns)):
        r = run("compare", W(f"{e}.mp4"), W(f"{x}.mp4"))
        ok(r.returncode == 2 and f"{e}.mp4 has {ne} frames" in r.stdout
           and f"{x}.mp4 has {nx}" in r.stdout,
           f"videos of {ne} and {nx} frames: both counts named ({r.stdout.strip()})")
else:
    skip("frame counts of videos of different lengths", "ffprobe is not installed")
    skip("frame counts of videos of different lengths, reversed", "ffprobe is not installed")

done()
