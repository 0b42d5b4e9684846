#!/usr/bin/env python3
"""springpend tests: valgrind memcheck on a short render, a compare and a
refused scene: no invalid access, no use of uninitialised memory, no
definite or indirect leak (Mesa's own leak in tests/valgrind.supp aside).
Skipped (exit 77) without valgrind.
usage: test_valgrind.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil
import subprocess
import struct
import sys
import zlib

valgrind = shutil.which("valgrind")
if not valgrind:
    print("1..0 # SKIP valgrind is not installed")
    sys.exit(77)
exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "valgrind"))
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
default = os.path.join(src, "..", "scenes", "default.ini")
golden = os.path.join(src, "golden")
count = failed = 0


def memcheck(what, args, want_rc):
    global count, failed
    log = os.path.join(work, f"vg{count + 1}.log")
    r = subprocess.run([valgrind, "--error-exitcode=99", "--leak-check=full",
                        "--show-leak-kinds=definite,indirect",
                        "--errors-for-leak-kinds=definite,indirect",
                        "--suppressions=" + os.path.join(src, "valgrind.supp"),
                        f"--log-file={log}", exe, *args],
                       capture_output=True, text=True, cwd=work)
    summary = [l.split("== ", 1)[-1] for l in open(log) if "ERROR SUMMARY" in l or "lost:" in l]
    count += 1
    good = r.returncode == want_rc
    failed += not good
    print(f"{'' if good else 'not '}ok {count} - valgrind {what}: exit {r.returncode} "
          f"(want {want_rc}); {'; '.join(s.strip() for s in summary)}", flush=True)
    if not good:
        print("# " + open(log).read().replace("\n", "\n# "))


memcheck("still 160x120 with a trail", ["still", default, "--at", "1", "--size", "160x120",
                                        "-o", "still.png", "--state", "still.json", "-q"], 0)

# The threaded paths: render thread, bounded queue, encoder thread, the PNG
# writer pool and the video sink in springpend-av.so.
memcheck("render to a PNG sequence", ["render", default, "--size", "64x48", "--fps", "10",
                                      "--set", "video.duration=0.5", "-o", "seq/%03d.png", "-q"], 0)
memcheck("render to MP4", ["render", default, "--size", "64x48", "--fps", "10",
                           "--set", "video.duration=0.5", "-o", "v.mp4", "-q"], 0)


def write_png(name, rgba_rows):
    """A small RGBA8 PNG, by hand, so the compare below has something to differ."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    w, h = len(rgba_rows[0]) // 4, len(rgba_rows)
    raw = b"".join(b"\0" + bytes(row) for row in rgba_rows)
    with open(os.path.join(work, name), "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


write_png("a.png", [[10, 20, 30, 255] * 5] * 4)
write_png("b.png", [[10, 20, 30, 255] * 4 + [200, 20, 30, 255]] * 4)
memcheck("compare with a diff image", ["compare", "a.png", "b.png", "--diff", "d.png"], 1)
with open(os.path.join(work, "bad.ini"), "w") as f:
    f.write("[pendulum]\nmas = 1\nmass = nan\n[video]\nfps = 0\n")
memcheck("a refused scene", ["still", "bad.ini", "-o", "x.png"], 2)
print(f"1..{count}")
sys.exit(1 if failed else 0)
