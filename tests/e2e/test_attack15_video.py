#!/usr/bin/env python3
"""springpend tests (issue 28): the fifteenth attacker's pass
(doc/notes/2026-11-27/attack15.md), findings #4 and #5, compare's videos:
- #4: compare never looked at a WebM's alpha (FFmpeg's VP9 decoder drops
  the Matroska BlockAdditional alpha that browsers composite): springpend's
  own transparent WebM made all opaque or all invisible, or an opaque one
  made nearly transparent, passed against its baseline. Now the alpha is
  decoded and compared as a PNG's is (RGBA). The hostile files are made as
  the reproductions make them (ffmpeg's geq, libvpx-vp9 lossless); the
  oracle is ffmpeg's libvpx-vp9 decoder (the alpha plane browsers use),
  ffprobe (the alpha_mode tag) and numpy's 8x8 block means of the alpha,
  never springpend's output;
- #5: an MP4 with two video tracks was judged by FFmpeg's pick (the larger
  bit rate) while browsers play the first, and the colour-tag check looked
  at the stream judged only: a video with more than one video stream is
  refused, exit 2, naming the count (ffprobe counts them here).
usage: test_attack15_video.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import re
import shutil
import subprocess

import sptest
from sptest import done, err, ok, skip

sptest.need_scipy()  # numpy, with Debian's python3 if need be
import numpy as np  # noqa: E402

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack15-video")
W, H, FRAMES, BLOCK, LEVELS = 320, 180, 15, 8, 16  # 0.25 s at 60 fps; the videos' default rule


def ffmpeg(*args):
    r = subprocess.run(["ffmpeg", "-v", "error", "-y", *args], capture_output=True, cwd=work)
    return r.returncode == 0


def render(scene, out, *more):
    r = run("render", os.path.join(scenes, scene), "--set", "video.duration=0.25", "--size",
            f"{W}x{H}", *more, "-o", path(out), "-q")
    return r.returncode == 0 and os.path.exists(path(out))


def with_alpha(src_name, out, alpha):
    """src_name's colour planes as they are, its alpha set to alpha (a geq
    expression), lossless VP9 with alpha: the reproduction's recipe."""
    return ffmpeg("-c:v", "libvpx-vp9", "-i", src_name, "-vf",
                  f"format=yuva420p,geq=lum='lum(X,Y)':cb='cb(X,Y)':cr='cr(X,Y)':a='{alpha}'",
                  "-c:v", "libvpx-vp9", "-lossless", "1", "-pix_fmt", "yuva420p", "-auto-alt-ref",
                  "0", "-colorspace", "bt709", "-color_primaries", "bt709", "-color_trc", "bt709",
                  "-color_range", "tv", out)


def alpha_planes(name):
    """The file's alpha, frame by frame, as libvpx-vp9 decodes it (255
    where it has none): an (n, H, W) int array."""
    raw = subprocess.run(["ffmpeg", "-v", "error", "-c:v", "libvpx-vp9", "-i", path(name), "-f",
                          "rawvideo", "-pix_fmt", "rgba", "-"], capture_output=True,
                         check=True).stdout
    return np.frombuffer(raw, np.uint8).reshape(-1, H, W, 4)[..., 3].astype(int)


def block_means(a):
    """8x8 block means of (n, H, W) a, rounded as compare rounds them
    ((sum + n/2) / n; the last row of blocks is 4 px high)."""
    n, h, w = a.shape
    bh, bw = -(-h // BLOCK), -(-w // BLOCK)
    out = np.zeros((n, bh, bw), int)
    for by in range(bh):
        for bx in range(bw):
            part = a[:, by * BLOCK:(by + 1) * BLOCK, bx * BLOCK:(bx + 1) * BLOCK]
            k = part.shape[1] * part.shape[2]
            out[:, by, bx] = (part.sum(axis=(1, 2)) + k // 2) // k
    return out


def stream_tags(name):
    r = subprocess.run(["ffprobe", "-v", "error", "-show_streams", path(name)],
                       capture_output=True, text=True)
    return r.stdout


LINE = re.compile(r"(\d+) of (\d+) frames differ.*?worst frame (\d+): (\d+) of (\d+) blocks .*?"
                  r"largest difference (\d+)")


def alpha_check(expected, actual, what, shown=None):
    """compare EXPECTED ACTUAL fails (exit 1), and its figures are the
    alpha's as libvpx-vp9 decodes the two files (the actual's as shown,
    when given: an alpha players use otherwise): the frames whose alpha
    block means differ by more than 16 levels, and at its worst frame the
    blocks that do (within 2: the colour planes, near equal, may tip a block
    at the threshold) and the largest difference."""
    d = np.abs(block_means(alpha_planes(expected)) -
               block_means(alpha_planes(actual) if shown is None else shown))
    frames = int(((d > LEVELS).sum(axis=(1, 2)) > 0).sum())
    r = run("compare", path(expected), path(actual))
    out = r.stdout.decode(errors="replace")
    m = LINE.search(out)
    if not m or r.returncode != 1:
        return ok(False, f"{what}: fails, exit 1 (exit {r.returncode}: {out.strip()[:300]} "
                         f"{err(r)[:200]}); the alpha differs in {frames} of {len(d)} frames")
    got, worst, blocks, largest = int(m[1]), int(m[3]), int(m[4]), int(m[6])
    want_blocks, want_largest = int((d[worst] > LEVELS).sum()), int(d[worst].max())
    ok(out.startswith("FAIL") and got == frames and abs(blocks - want_blocks) <= 2 and
       largest == want_largest,
       f"{what}: FAIL, exit 1: {got} of {m[2]} frames differ (alpha: {frames}), worst frame "
       f"{worst}: {blocks} blocks (alpha: {want_blocks}), largest difference {largest} "
       f"(alpha: {want_largest})")


have_vpx = shutil.which("ffmpeg") and "libvpx-vp9" in subprocess.run(
    ["ffmpeg", "-hide_banner", "-decoders"], capture_output=True, text=True).stdout
if not have_vpx or not shutil.which("ffprobe"):
    skip("4: a WebM's alpha is compared", "ffmpeg with libvpx-vp9, or ffprobe, missing")
elif not (render("default.ini", "t.webm", "--set", "view.background=transparent") and
          render("default.ini", "base.webm") and with_alpha("t.webm", "a255.webm", 255) and
          with_alpha("t.webm", "a0.webm", 0) and with_alpha("base.webm", "a16.webm", 16) and
          ffmpeg("-c:v", "libvpx-vp9", "-i", "t.webm", "-c:v", "libvpx-vp9", "-lossless", "1",
                 "-pix_fmt", "yuva420p", "-colorspace", "bt709", "-color_primaries", "bt709",
                 "-color_trc", "bt709", "-color_range", "tv", "same.webm")):
    ok(False, "4: the transparent WebM and its altered copies are made")
else:
    tags = {n: stream_tags(n) for n in ("t.webm", "a255.webm", "same.webm", "base.webm")}
    ok("codec_name=vp9" in tags["t.webm"] and "TAG:alpha_mode=1" in tags["t.webm"] and
       "tag:alpha_mode=1" in tags["a255.webm"].lower() and
       "alpha_mode" not in tags["base.webm"].lower(),
       "4: springpend's transparent WebM is VP9 with alpha_mode=1, its opaque one has none "
       "(ffprobe): the premise")
    t_alpha = alpha_planes("t.webm")
    ok(len(t_alpha) == FRAMES and 0 < (t_alpha == 0).mean() < 1,
       f"4: the transparent WebM's alpha (libvpx-vp9) is 0 in {(t_alpha == 0).mean():.0%} of "
       f"its {len(t_alpha)} frames' pixels: the premise")
    r = run("compare", path("t.webm"), path("t.webm"))
    ok(r.returncode == 0 and b"largest difference 0;" in r.stdout,
       f"4: springpend's transparent WebM compares equal with itself (exit {r.returncode}: "
       f"{r.stdout.decode(errors='replace').strip()[:200]} {err(r)[:200]})")
    same = np.array_equal(alpha_planes("same.webm"), t_alpha)
    r = run("compare", path("t.webm"), path("same.webm"))
    ok(same and r.returncode == 0 and r.stdout.startswith(b"ok"),
       f"4: a lossless re-encode keeping the alpha (libvpx-vp9: equal alpha: {same}) passes "
       f"(exit {r.returncode}: {r.stdout.decode(errors='replace').strip()[:200]} "
       f"{err(r)[:200]})")
    alpha_check("t.webm", "a255.webm", "4: the transparent WebM made all opaque")
    alpha_check("t.webm", "a0.webm", "4: the transparent WebM made all invisible")
    alpha_check("base.webm", "a16.webm", "4: an opaque WebM made nearly transparent (alpha 16)")
    alpha_check("a0.webm", "t.webm", "4: an invisible baseline, the transparent WebM as actual")
    # The track's AlphaMode decides, as in browsers, not FFmpeg's stream tag
    # alpha_mode, which a Matroska Tag ALPHA_MODE overwrites: an all
    # invisible copy whose tag says 0 (browsers still composite its alpha),
    # and the transparent one with no AlphaMode but a tag saying 1 (shown
    # opaque). The tag's byte is patched; ffprobe shows the tag, and the
    # AlphaMode element's bytes (53 C0 81 01) are looked for in the file.
    for src_name, out, frm, to in (("a0.webm", "a0-tag0.webm", "1", "0"),
                                   ("t.webm", "t-tag1.webm", "0", "1")):
        ffmpeg("-i", src_name, "-c", "copy", "-write_crc32", "0", "-metadata:s:v:0",
               f"alpha_mode={frm}", "tmp-" + out)
        data = bytearray(open(path("tmp-" + out), "rb").read())
        at = data.find(b"\x44\x87\x81" + frm.encode(), data.find(b"ALPHA_MODE"))
        data[at + 3] = ord(to)
        open(path(out), "wb").write(data)
    element = {n: b"\x53\xc0\x81\x01" in open(path(n), "rb").read()
               for n in ("a0-tag0.webm", "t-tag1.webm")}
    ok(element == {"a0-tag0.webm": True, "t-tag1.webm": False} and
       "TAG:ALPHA_MODE=0" in stream_tags("a0-tag0.webm") and
       "TAG:ALPHA_MODE=1" in stream_tags("t-tag1.webm"),
       f"4: the copies' AlphaMode elements {element} and tags (ffprobe) are as made: the premise")
    alpha_check("t.webm", "a0-tag0.webm", "4: all invisible, AlphaMode 1, a tag ALPHA_MODE=0")
    # libvpx-vp9 decodes a BlockAdditional alpha whatever AlphaMode says;
    # WebM players (Chromium, Firefox) use it only under AlphaMode 1
    alpha_check("t.webm", "t-tag1.webm", "4: no AlphaMode, a tag ALPHA_MODE=1 (shown opaque)",
                shown=np.full_like(t_alpha, 255))

# 5: two video streams: another scene first (what players show), a copy of
# the baseline second (what FFmpeg's av_find_best_stream picked)
if not shutil.which("ffmpeg") or not shutil.which("ffprobe"):
    skip("5: a video with two video streams is refused", "ffmpeg or ffprobe missing")
elif not (render("default.ini", "base.mp4") and
          render("stiff.ini", "stiff.mp4", "--set", "video.crf=40") and
          ffmpeg("-i", "stiff.mp4", "-c", "copy", "-bsf:v", "h264_metadata=colour_primaries=9:"
                 "transfer_characteristics=16:matrix_coefficients=9", "stiffpq.mp4") and
          all(ffmpeg("-i", a, "-i", b, "-map", "0:v", "-map", "1:v", "-c", "copy",
                     "-disposition:v:0", "default", "-disposition:v:1", "default", out)
              for a, b, out in (("stiff.mp4", "base.mp4", "two.mp4"),
                                ("stiffpq.mp4", "base.mp4", "two-pq.mp4"),
                                ("base.webm", "base.webm", "two.webm")))):
    ok(False, "5: the videos with two video streams are made")
else:
    for expected, actual in (("base.mp4", "two.mp4"), ("two.mp4", "base.mp4"),
                             ("base.mp4", "two-pq.mp4"), ("base.webm", "two.webm")):
        two = actual if actual.startswith("two") else expected
        n = stream_tags(two).count("codec_type=video")
        r = run("compare", path(expected), path(actual))
        e = err(r)
        ok(n == 2 and r.returncode == 2 and f"{two}: holds 2 video streams; springpend writes one"
           in e and "-map 0:v:0" in e and not r.stdout.startswith(b"ok"),
           f"5: compare {expected} {actual} ({two}: {n} video streams, ffprobe): refused, exit 2, "
           f"naming the count (exit {r.returncode}: {e[:300]})")
done()
