#!/usr/bin/env python3
"""springpend tests: the environment an image records (issue 24).
`springpend version --verbose` (and `--version --verbose`) name springpend,
the GL renderer, Mesa and LLVM, FreeType, HarfBuzz, FriBidi, fontconfig,
the built-in font with its SHA-256,
zlib, libpng and libavcodec; an image adds each font file that fontconfig
gave its text, with its SHA-256 (the file fc-match resolves, hashed here); each version is checked against the library
itself, asked here through ctypes; every PNG carries the same text in its
springpend.environment chunk; compare names the lines that differ.
usage: test_environment.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR (TAP)"""
import ctypes
import ctypes.util
import hashlib
import os
import re
import shutil
import struct
import subprocess
import sys
import zlib
import json

from sptest import done, ok, skip

exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
work = os.path.abspath(os.path.join(sys.argv[3], "environment"))
default = os.path.join(src, "..", "scenes", "default.ini")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def run(*args):
    return subprocess.run([exe, *args], capture_output=True, text=True, cwd=work, timeout=60)


r1, r2, plain = run("version", "--verbose"), run("--version", "--verbose"), run("--version")
env = dict(l.split(": ", 1) for l in r1.stdout.splitlines() if ": " in l)
ok(r1.returncode == 0 and r1.stdout == r2.stdout and plain.stdout.strip() == "springpend " +
   env.get("springpend", "?"), f"version --verbose and --version --verbose agree ({r1.stdout!r:.200})")
keys = ["springpend", "renderer", "gl", "mesa", "llvm", "freetype", "harfbuzz", "fribidi",
        "fontconfig", "font", "zlib", "libpng", "libavcodec"]
ok(list(env) == keys, f"the lines, in order: {list(env)}")
ok(env.get("mesa", "") in env.get("gl", "-") and env.get("llvm", "") in env.get("renderer", "-")
   and re.fullmatch(r"\d+\.\d+(\.\d+)?", env.get("mesa", "")) is not None,
   f"Mesa {env.get('mesa')} from GL_VERSION {env.get('gl')}, LLVM {env.get('llvm')} from "
   f"{env.get('renderer')}")


def lib(name):
    path = ctypes.util.find_library(name)
    return ctypes.CDLL(path) if path else None


# Each version from the library itself.
ok(env.get("zlib") == zlib.ZLIB_RUNTIME_VERSION, f"zlib {env.get('zlib')} (Python's zlib: "
   f"{zlib.ZLIB_RUNTIME_VERSION})")
png = lib("png16")
if png:
    png.png_get_libpng_ver.restype = ctypes.c_char_p
    want = png.png_get_libpng_ver(None).decode()
    ok(env.get("libpng") == want, f"libpng {env.get('libpng')} ({want})")
else:
    skip("libpng's version", "libpng16 not found by ctypes")
ft = lib("freetype")
if ft:
    h = ctypes.c_void_p()
    a, b, c = ctypes.c_int(), ctypes.c_int(), ctypes.c_int()
    ft.FT_Init_FreeType(ctypes.byref(h))
    ft.FT_Library_Version(h, ctypes.byref(a), ctypes.byref(b), ctypes.byref(c))
    want = f"{a.value}.{b.value}.{c.value}"
    ok(env.get("freetype") == want, f"FreeType {env.get('freetype')} ({want})")
else:
    skip("FreeType's version", "libfreetype not found by ctypes")
# The text stack, each asked its own version.
def hb_version(h):
    h.hb_version_string.restype = ctypes.c_char_p
    return h.hb_version_string().decode()


def fc_version(h):
    v = h.FcGetVersion()
    return f"{v // 10000}.{v // 100 % 100}.{v % 100}"


for key, name, ask in (
        ("harfbuzz", "harfbuzz", hb_version),
        ("fribidi", "fribidi", lambda h: ctypes.c_char_p.in_dll(h, "fribidi_version_info").value
         .decode().split("\n")[0].split()[-1]),
        ("fontconfig", "fontconfig", fc_version)):
    h = lib(name)
    if h:
        want = ask(h)
        ok(env.get(key) == want, f"{key} {env.get(key)} ({want})")
    else:
        skip(f"{key}'s version", f"lib{name} not found by ctypes")
av = lib("avcodec")
if av:
    v = av.avcodec_version()
    want = f"{v >> 16}.{v >> 8 & 255}.{v & 255}"
    ok(env.get("libavcodec", "").startswith(want + " (FFmpeg "),
       f"libavcodec {env.get('libavcodec')} ({want})")
else:
    skip("libavcodec's version", "libavcodec not found by ctypes")
font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"
opts = open(os.path.join(src, "..", "meson_options.txt")).read()
if os.path.exists(font) and font in opts:
    digest = hashlib.sha256(open(font, "rb").read()).hexdigest()
    ok(env.get("font", "").endswith("sha256 " + digest), f"the font's SHA-256 ({env.get('font')})")
else:
    skip("the font's SHA-256", "built with another font")


def text_chunks(path):
    d, i, out = open(path, "rb").read(), 8, {}
    while i < len(d):
        n, kind = struct.unpack(">I4s", d[i:i + 8])
        body = d[i + 8:i + 8 + n]
        if kind == b"zTXt":
            k, rest = body.split(b"\0", 1)
            out[k.decode()] = zlib.decompress(rest[1:]).decode()
        elif kind == b"tEXt":
            k, v = body.split(b"\0", 1)
            out[k.decode()] = v.decode()
        i += 12 + n
    return out, d


run("still", default, "--size", "160x120", "--at", "1", "-o", "s.png", "-q")
chunks, raw = text_chunks(os.path.join(work, "s.png"))
ok(chunks.get("springpend.environment") == r1.stdout,
   "a still's springpend.environment chunk holds what version --verbose prints")

# compare names the lines that differ: a copy whose chunk says another libpng.
other = chunks["springpend.environment"].replace("libpng: " + env["libpng"], "libpng: 9.9.9")
body = b"springpend.environment\0\0" + zlib.compress(other.encode())
i, out = 8, raw[:8]
while i < len(raw):
    n, kind = struct.unpack(">I4s", raw[i:i + 8])
    piece = raw[i:i + 12 + n]
    if kind == b"zTXt" and raw[i + 8:i + 8 + n].startswith(b"springpend.environment\0"):
        piece = struct.pack(">I", len(body)) + b"zTXt" + body + struct.pack(">I", zlib.crc32(b"zTXt" + body))
    out += piece
    i += 12 + n
open(os.path.join(work, "t.png"), "wb").write(out)
r = run("compare", "s.png", "t.png")
ok(r.returncode == 0 and f"libpng: {env['libpng']} vs 9.9.9" in r.stdout
   and "freetype" not in r.stdout.split("environment")[-1],
   f"compare names the environment line that differs, and only it ({r.stdout.strip()})")

# The reports carry each image's environment whole, not only the lines that
# differ: the JSON per image, the HTML once per distinct environment, linked
# from each row.
import html
import json
r = run("compare", "s.png", "t.png", "--json", "--report", "r.html")
res = json.loads(r.stdout)["results"][0] if r.stdout.startswith("{") else {}
ok(res.get("environment") == {"expected": chunks["springpend.environment"], "actual": other},
   f"--json: each image's springpend.environment whole ({str(res.get('environment'))[:120]})")
page = open(os.path.join(work, "r.html")).read() if os.path.exists(os.path.join(work, "r.html")) else ""
pres = re.findall(r'<div class="env" id="env-(\d)"><h3>([^<]*)</h3><pre>(.*?)</pre>', page, re.S)
ok([(n, html.unescape(t)) for n, _, t in pres] == [("1", chunks["springpend.environment"]),
                                                   ("2", other)]
   and 'made in: expected <a href="#env-1">E1</a>, actual <a href="#env-2">E2</a>' in page,
   f"--report: both environments whole, each once, and the row says which is which ({[h for _, h, _ in pres]})")
r = run("compare", "s.png", "s.png", "--report", "same.html")
page = open(os.path.join(work, "same.html")).read() if os.path.exists(os.path.join(work, "same.html")) else ""
ok(page.count('<div class="env"') == 1 and "E1: 1 expected image, 1 actual image" in page,
   "one environment is listed once")

# Every font file fontconfig gave the text is recorded with its SHA-256,
# "font NAME: sha256 HEX (N bytes)", beside the built-in font's line: a
# fallback font (CJK: DejaVu Sans has none) and a [view] font, each the file
# fc-match resolves, hashed here.
def font_line(path):
    data = open(path, "rb").read()
    return (f"font {os.path.basename(path)}: sha256 {hashlib.sha256(data).hexdigest()} "
            f"({len(data)} bytes)")


def fc_match(pattern, env=None):
    r = subprocess.run(["fc-match", "-f", "%{file}", pattern], capture_output=True, text=True,
                       env=env)
    return r.stdout if r.returncode == 0 and r.stdout else None


cjk = fc_match("DejaVu Sans:charset=632f") if shutil.which("fc-match") else None
serif = fc_match("Noto Serif") if shutil.which("fc-match") else None
if cjk and "dejavu" not in cjk.lower():
    r = run("still", default, "--size", "320x120", "--at", "1", "--set", "view.title=振り子 Pendel",
            "-o", "cjk.png", "-q")
    cjk_chunks = text_chunks(os.path.join(work, "cjk.png"))[0] if r.returncode == 0 else {}
    cjk_env = cjk_chunks.get("springpend.environment", "")
    lines = cjk_env.splitlines()
    ok(font_line(cjk) in lines and cjk in cjk_chunks.get("springpend.fonts", "") and
       lines.index(font_line(cjk)) == [l.split(":")[0] for l in lines].index("font") + 1 and
       cjk_env.replace(font_line(cjk) + "\n", "") == r1.stdout,
       f"a fallback font's file and SHA-256 (fc-match: {cjk}), after the built-in font's line; "
       f"the rest as version --verbose prints it ({[l for l in lines if l.startswith('font')]})")
    r = run("compare", "s.png", "cjk.png")
    ok(f"{font_line(cjk).split(': ')[0]}: (none) vs {font_line(cjk).split(': ', 1)[1]}" in r.stdout,
       f"compare names a font file that only the actual image was drawn with ({r.stdout.strip()[-300:]})")
    r = run("render", default, "--size", "160x120", "--set", "view.title=振り子",
            "--set", "video.duration=0.1", "-o", "cjk.mp4", "-q")
    tags = subprocess.run(["ffprobe", "-v", "error", "-show_entries", "format_tags", "-of", "json",
                           os.path.join(work, "cjk.mp4")], capture_output=True, text=True)
    tags = json.loads(tags.stdout).get("format", {}).get("tags", {}) if tags.returncode == 0 else {}
    ok(font_line(cjk) in tags.get("springpend.environment", "").splitlines(),
       f"an MP4's springpend.environment tag names it too ({tags.get('springpend.fonts')})")
else:
    skip("a fallback font's SHA-256", f"no CJK font (fc-match: {cjk})")
if serif and "NotoSerif" in serif:
    r = run("still", default, "--size", "320x120", "--at", "1", "--set", "view.title=Pendel",
            "--set", "view.font=Noto Serif", "-o", "serif.png", "-q")
    here = text_chunks(os.path.join(work, "serif.png"))[0] if r.returncode == 0 else {}
    ok(font_line(serif) in here.get("springpend.environment", "").splitlines(),
       f"a [view] font's file and SHA-256 (fc-match: {serif})")
    # The same files in another folder (a fontconfig that knows only that
    # folder): the same environment, only springpend.fonts' path differs.
    fonts = os.path.join(work, "other-fonts")
    os.makedirs(fonts)
    used = [f.strip() for f in here.get("springpend.fonts", "").split(", ") if "(embedded in springpend)" not in f]
    for f in used:  # Noto Serif, and the fallback for what it lacks (U+2212)
        shutil.copy(f, fonts)
    conf = os.path.join(work, "fonts.conf")
    with open(conf, "w") as f:
        f.write(f'<?xml version="1.0"?><fontconfig><dir>{fonts}</dir>'
                f'<cachedir>{work}/fc-cache</cachedir></fontconfig>')
    fenv = dict(os.environ, FONTCONFIG_FILE=conf)
    r = subprocess.run([exe, "still", default, "--size", "320x120", "--at", "1", "--set",
                        "view.title=Pendel", "--set", "view.font=Noto Serif", "-o", "moved.png",
                        "-q"], capture_output=True, text=True, cwd=work, timeout=60, env=fenv)
    there = text_chunks(os.path.join(work, "moved.png"))[0] if r.returncode == 0 else {}
    c = run("compare", "serif.png", "moved.png")
    ok(fc_match("Noto Serif", fenv) == os.path.join(fonts, os.path.basename(serif)) and
       there.get("springpend.fonts", "").startswith(fonts) and
       here.get("springpend.environment") == there.get("springpend.environment") and
       c.returncode == 0 and "environment" not in c.stdout,
       f"the same font file in another folder records the same environment, and compare "
       f"notes none ({there.get('springpend.fonts')!r:.80}; {r.stderr.strip()[-200:]} {c.stdout.strip()[-200:]})")
else:
    skip("a [view] font's SHA-256", f"Noto Serif is not installed (fc-match: {serif})")

# A CSV's metadata records what shapes numbers (environment.h's
# sp_environment_numbers) and loads no FFmpeg module to say so.
import json
libc = ctypes.CDLL(None)
libc.gnu_get_libc_version.restype = ctypes.c_char_p
r = subprocess.run([exe, "data", default, "--every", "50", "-o", "m.csv"], capture_output=True,
                   text=True, cwd=work, timeout=60, env={**os.environ, "LD_DEBUG": "files"})
meta = json.load(open(os.path.join(work, "m.csv-metadata.json")))
numbers = dict(l.split(": ", 1) for l in meta.get("schema:runtimePlatform", "").splitlines())
ok(r.returncode == 0 and numbers == {"springpend": env["springpend"],
                                     "compiler": numbers.get("compiler"),
                                     "libc": "glibc " + libc.gnu_get_libc_version().decode()}
   and re.fullmatch(r"\d+\.\d+.*", numbers.get("compiler", "")) is not None,
   f"a CSV's metadata names springpend, the compiler and glibc ({numbers})")
ok("libavcodec" not in r.stderr and "libavcodec" not in r.stdout,
   "data -o m.csv loads no FFmpeg library (LD_DEBUG=files: "
   f"{[l for l in r.stderr.splitlines() if 'libav' in l][:2]})")

done()
