"""springpend tests: ink in rendered text, shared by the text tests
(test_text.py: stills; test_sweep_figure.py: sweep figures). Needs numpy,
scipy, ffmpeg, rsvg-convert and poppler-utils."""
import os
import subprocess

import numpy as np
from scipy import ndimage


def gray(path, zoom=1):
    """A PNG (or a vector figure rasterised at zoom px per px or pt) as a 2-D
    array of ink, 0..255."""
    base, ext = os.path.splitext(path)
    if ext == ".svg":
        subprocess.run(["rsvg-convert", "--zoom", str(zoom), path, "-o", base + "_svg.png"],
                       check=True)
        path = base + "_svg.png"
    elif ext == ".pdf":
        subprocess.run(["pdftoppm", "-r", str(72 * zoom), "-png", "-singlefile", path,
                        base + "_pdf"], check=True)
        path = base + "_pdf.png"
    out = subprocess.run(["ffmpeg", "-v", "error", "-i", path, "-f", "rawvideo", "-pix_fmt", "gray",
                          "-"], capture_output=True, check=True).stdout
    probe = subprocess.run(["ffprobe", "-v", "error", "-select_streams", "v", "-show_entries",
                            "stream=width,height", "-of", "csv=p=0", path],
                           capture_output=True, text=True, check=True).stdout.split(",")
    w, h = int(probe[0]), int(probe[1])
    return 255 - np.frombuffer(out, np.uint8).reshape(h, w).astype(int)  # ink is dark on light


def ink_columns(img, thresh=96):
    cols = np.nonzero((img > thresh).any(axis=0))[0]
    return (cols.min(), cols.max()) if len(cols) else (0, -1)


def segments(img, gap=8, thresh=96):
    """Ink split at runs of >= gap empty columns: a list of cropped arrays."""
    on = (img > thresh).any(axis=0)
    out, start, empty = [], None, 0
    for x, v in enumerate(list(on) + [False] * gap):
        if v:
            if start is None:
                start = x
            empty, last = 0, x
        elif start is not None:
            empty += 1
            if empty >= gap:
                seg = img[:, start:last + 1]
                rows = np.nonzero((seg > thresh).any(axis=1))[0]
                out.append(seg[rows.min():rows.max() + 1])
                start = None
    return out


def joined(img, thresh=96):
    """The widest 8-connected run of ink's share of the ink's width."""
    lab, n = ndimage.label(img > thresh, structure=np.ones((3, 3)))
    if not n:
        return 0.0
    x0, x1 = ink_columns(img, thresh)
    widest = max(s[1].stop - s[1].start for s in ndimage.find_objects(lab))
    return widest / (x1 - x0 + 1)


def pdf_text(path):
    """pdftotext's text of a PDF, without the bidi embedding marks it adds
    around right-to-left lines (U+202A-U+202E)."""
    got = subprocess.run(["pdftotext", path, "-"], capture_output=True, text=True).stdout
    return "".join(c for c in got if not 0x202A <= ord(c) <= 0x202E).strip()
