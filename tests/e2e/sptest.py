"""springpend tests: what the Python tests share. TAP output (ok, skip,
done), a test's start (setup), running the binary under test (runner,
runner_bytes) and reading what it said (err, part_files), --set arguments
(sets), scipy or a skip (need_scipy), a picture's pixels through ffmpeg
(ffmpeg_rgb), a PNG's text read or its record forged (png_text,
png_with_command), and the physics reference (model, start, solve: scipy's DOP853 on the
Cartesian equations of sim.h), and the manual's text (doc_pages, manual,
doc_page, readme_ci: README.md and doc/*.md). Python puts a
script's own folder first on sys.path, so each test imports this with
`from sptest import ...`."""
import math
import os
import signal
import subprocess
import sys

# A suite started in the background of a non-interactive shell (`sh -c
# 'meson test &'`, a CI step run that way) inherits SIGINT and SIGQUIT
# ignored, and springpend rightly keeps an inherited ignored signal
# ignored (signals.c), so a test that sends one would wait for a run that
# never stops. The binaries under test start with every stop signal at its
# default; a test that wants one ignored (nohup) says so itself.
for _sig in (signal.SIGINT, signal.SIGQUIT, signal.SIGHUP, signal.SIGTERM, signal.SIGUSR1,
             signal.SIGUSR2, signal.SIGALRM, signal.SIGVTALRM, signal.SIGXCPU, signal.SIGPWR,
             signal.SIGPROF, signal.SIGIO, *range(signal.SIGRTMIN, signal.SIGRTMAX + 1)):
    if signal.getsignal(_sig) == signal.SIG_IGN:
        signal.signal(_sig, signal.SIG_DFL)

_count = _failed = 0


def _skipped(what, why):
    global _count
    _count += 1
    what = " | ".join(str(what).splitlines())
    print(f"ok {_count} - {what} # SKIP {why}", flush=True)
    return True


def ok(cond, what, skip=None):
    """One TAP line (a description that quotes a program's output keeps to
    that line); returns cond. With skip (why the check cannot run here): a
    skipped check, and True."""
    global _count, _failed
    if skip:
        return _skipped(what, skip)
    _count += 1
    _failed += not cond
    what = " | ".join(str(what).splitlines())
    print(f"{'' if cond else 'not '}ok {_count} - {what}", flush=True)
    return cond


def png_text(path, compressed=False):
    """A PNG's tEXt and uncompressed iTXt chunks (and zTXt and compressed
    iTXt ones, inflated, when compressed) as {keyword: text}. springpend
    writes ASCII text as tEXt/zTXt and UTF-8 beyond it as iTXt."""
    import struct
    import zlib
    data, text, i = open(path, "rb").read(), {}, 8
    while i < len(data):
        n, kind = struct.unpack(">I4s", data[i:i + 8])
        body = data[i + 8:i + 8 + n]
        if kind == b"tEXt" or (compressed and kind == b"zTXt"):
            k, v = body.split(b"\0", 1)
            text[k.decode("latin-1")] = (zlib.decompress(v[1:]) if kind == b"zTXt" else v).decode("utf-8")
        elif kind == b"iTXt":
            k, rest = body.split(b"\0", 1)
            flag, rest = rest[0], rest[2:]
            _lang, _tkey, v = rest.split(b"\0", 2)
            if flag == 0 or compressed:
                text[k.decode("latin-1")] = (zlib.decompress(v) if flag else v).decode("utf-8")
        i += 12 + n
    return text


def png_with_command(src, out, line):
    """Writes the PNG src to out with its springpend.command text (tEXt or
    iTXt) replaced by line, the chunk's CRC made anew: a forged record."""
    import struct
    import zlib
    data, i, chunks = open(src, "rb").read(), 8, b""
    while i < len(data):
        n, = struct.unpack(">I", data[i:i + 4])
        kind, body = data[i + 4:i + 8], data[i + 8:i + 8 + n]
        if kind in (b"tEXt", b"iTXt") and body.startswith(b"springpend.command\0"):
            body = b"springpend.command\0" + (b"\0\0\0\0" if kind == b"iTXt" else b"") + \
                line.encode()
        chunks += struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
        i += 12 + n
    with open(out, "wb") as f:
        f.write(data[:8] + chunks)


def module_copy(exe, scene, work):
    """A copy of springpend at WORK/pfx/bin with springpend-cairo.so from
    exe's build folder installed where that copy looks for it (the path
    its "cannot load" message names). Checks (TAP) that the message names
    a path under pfx and that the copy then loads the module. Returns
    (still, installed): still(out) runs `still scene` at 64x48 to
    WORK/out with the copy; installed is the module's path. None when the
    build has no module or the path is not named (a failed check)."""
    import re
    import shutil
    cairo = os.path.join(os.path.dirname(exe), "springpend-cairo.so")
    if not os.path.exists(cairo):
        return None
    pfx = os.path.join(work, "pfx")
    tool = os.path.join(pfx, "bin", "springpend")
    os.makedirs(os.path.dirname(tool))
    shutil.copy(exe, tool)

    def still(out):
        return subprocess.run([tool, "still", scene, "--size", "64x48", "-q", "-o", out],
                              capture_output=True, text=True, cwd=work, timeout=60)

    r = still("m0.svg")
    m = re.search(r"\((/\S+?/springpend-cairo\.so):", r.stderr)
    if not (m and m.group(1).startswith(pfx)):
        ok(False, f"the message names the installed module path ({r.stderr.strip()[-200:]})")
        return None
    installed = os.path.normpath(m.group(1))
    os.makedirs(os.path.dirname(installed), exist_ok=True)
    shutil.copy(cairo, installed)
    os.chmod(installed, 0o755)
    r = still("m1.svg")
    ok(r.returncode == 0 and os.path.exists(os.path.join(work, "m1.svg")),
       f"the module installed beside a copy of springpend loads ({r.stderr.strip()[-200:]})")
    return still, installed


def png_overlay(path):
    """The springpend.overlay chunk's key=value lines as a dict."""
    return dict(line.split("=", 1) for line in png_text(path).get("springpend.overlay", "").splitlines())


def diag(text):
    """A TAP comment: every line of text after '# '."""
    print("\n".join(f"# {line}" for line in str(text).splitlines()), flush=True)


def skip(what, why):
    """A TAP line for a check that cannot run here."""
    _skipped(what, why)


def done():
    """The TAP plan, and the exit status: 1 when a check failed."""
    print(f"1..{_count}")
    sys.exit(1 if _failed else 0)


def meson_deb_packages(root):
    """{dependency: Debian package} for every dependency('X') of root's
    meson.build but threads, through X's .pc file and dpkg -S ('' where
    none is found). Needs pkg-config and dpkg."""
    import re
    meson = open(os.path.join(root, "meson.build")).read()
    pkgs = {}
    for d in sorted(set(re.findall(r"dependency\('([^']+)'", meson)) - {"threads"}):
        pcdir = subprocess.run(["pkg-config", "--variable=pcfiledir", d], capture_output=True,
                               text=True).stdout.strip()
        pkgs[d] = subprocess.run(["dpkg", "-S", os.path.join(pcdir, d + ".pc")],
                                 capture_output=True, text=True).stdout.split(":")[0]
    return pkgs


def runner(exe, cwd):
    """A function running exe with its arguments in cwd, output captured as text."""
    def run(*args):
        return subprocess.run([exe, *args], capture_output=True, text=True, cwd=cwd)
    return run


def runner_bytes(exe, cwd):
    """A function running exe with its arguments in cwd (at most timeout s,
    60 by default; further keywords go to subprocess.run), output captured
    as bytes unless told otherwise."""
    def run(*args, timeout=60, **kw):
        kw.setdefault("capture_output", True)
        return subprocess.run([exe, *args], cwd=cwd, timeout=timeout, **kw)
    return run


def scene_command(run):
    """A function naming what `scene NAME --command` prints for NAME (text),
    or '(exit N: the error)', run through run (a runner_bytes)."""
    def command(name):
        r = run("scene", name, "--command")
        return r.stdout.decode().strip() if r.returncode == 0 else f"(exit {r.returncode}: {err(r)})"
    return command


def same_bytes_in(folder):
    """A function telling whether two files in folder hold the same bytes."""
    def same_bytes(a, b):
        with open(os.path.join(folder, a), "rb") as fa, open(os.path.join(folder, b), "rb") as fb:
            return fa.read() == fb.read()
    return same_bytes


def hangs(run, *args, timeout=10):
    """Runs springpend through run (a runner) for at most timeout s:
    (returncode or 'hung', stderr)."""
    try:
        r = run(*args, timeout=timeout)
        return r.returncode, err(r)
    except subprocess.TimeoutExpired:
        return "hung", ""


def err(r):
    """What a finished run wrote to stderr (bytes or text), stripped."""
    e = r.stderr
    return (e.decode(errors="replace") if isinstance(e, bytes) else e or "").strip()


def part_files(folder):
    """The .part files in folder (none when it is not there)."""
    return [n for n in os.listdir(folder) if n.endswith(".part")] if os.path.isdir(folder) else []


def ffmpeg_rgb(path, w, h):
    """A w x h picture's pixels through ffmpeg, as an (h, w, 3) int array
    of RGB (numpy must import)."""
    import numpy as np
    raw = subprocess.run(["ffmpeg", "-v", "error", "-i", path, "-f", "rawvideo", "-pix_fmt",
                          "rgb24", "-"], capture_output=True, check=True).stdout
    return np.frombuffer(raw, np.uint8).reshape(h, w, 3).astype(int)


def setup(name, tools):
    """A test's start: (springpend, the tests' source folder, a fresh output
    folder `name` under argv[3], a runner there) from the usual arguments
    SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR; skips (exit 77) when one of the
    tools is not on PATH."""
    import shutil
    need = [t for t in tools if not shutil.which(t)]
    if need:
        print(f"1..0 # SKIP {', '.join(need)} not installed")
        sys.exit(77)
    exe, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    work = os.path.abspath(os.path.join(sys.argv[3], name))
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    return exe, src, work, runner(exe, work)


def edit_file(path, old, new):
    """Replaces old by new in the file at path once; asserts it was there."""
    with open(path) as f:
        text = f.read()
    assert old in text, (path, old)
    with open(path, "w") as f:
        f.write(text.replace(old, new, 1))

def attack_setup(name):
    """An attacker's-pass test's start (test_attack*.py): springpend, the
    tests' source folder, its fresh output folder `name`, a runner_bytes
    there, a function naming a file in that folder, the shipped scenes
    folder, and whether springpend is built with ASan (whose shadow memory
    a ulimit -v cannot hold)."""
    exe, src, work, _ = setup(name, [])
    scenes = os.path.abspath(os.path.join(src, "..", "scenes"))
    return (exe, src, work, runner_bytes(exe, work), lambda *names: os.path.join(work, *names),
            scenes, b"__asan_init" in open(exe, "rb").read())

def sets(d):
    """--set KEY=VALUE for each item of d."""
    return [a for k, v in d.items() for a in ("--set", f"{k}={v}")]


def need_scipy():
    """Returns when numpy and scipy import; else runs the test again with
    Debian's python3 (a pyenv shim on PATH may lack them), or skips it."""
    try:
        import numpy  # noqa: F401
        import scipy.integrate  # noqa: F401
    except ImportError:
        if os.path.exists("/usr/bin/python3") and os.path.realpath(sys.executable) != \
                os.path.realpath("/usr/bin/python3") and not os.environ.get("SP_REEXEC"):
            os.environ["SP_REEXEC"] = "1"
            os.execv("/usr/bin/python3", ["/usr/bin/python3", *sys.argv])
        print("1..0 # SKIP python3-scipy is not installed")
        sys.exit(77)


# ---- the reference: scipy on the Cartesian equations (sim.h) --------------
def model(L0, k, m, b=0.0, A=0.0, f=0.0, g=9.81):
    """The right-hand side in the pivot's frame: pivot y_p = A sin 2 pi f t
    (f in Hz), damping b on the velocity relative to the air (the lab)."""
    km, gam, W = k / m, b / m, 2 * math.pi * f

    def rhs(t, u):
        x, y, vx, vy = u
        c = km * (1 - L0 / math.hypot(x, y))
        vp, ap = A * W * math.cos(W * t), -A * W * W * math.sin(W * t)
        return [vx, vy, -c * x - gam * vx, -c * y - g - ap - gam * (vy + vp)]
    return rhs


def start(r, th_deg, rd=0.0, thd=0.0):
    """(x, y, vx, vy) from r (m), theta (degrees), r_dot (m/s), theta_dot (rad/s)."""
    th = math.radians(th_deg)
    return [r * math.sin(th), -r * math.cos(th), rd * math.sin(th) + r * thd * math.cos(th),
            -rd * math.cos(th) + r * thd * math.sin(th)]


def solve(rhs, u0, tend, ts=None, **kw):
    """scipy's DOP853 at rtol 1e-11 (call need_scipy first)."""
    from scipy.integrate import solve_ivp
    return solve_ivp(rhs, (0, tend), u0, method="DOP853", rtol=1e-11, atol=1e-13,
                     t_eval=ts, **kw)


# ---- the 3-D reference and the swing plane's precession (issue 26) --------
def model3(L0, k, m, b=0.0, A=0.0, f=0.0, g=9.81):
    """The 3-D equations in the pivot's frame, u = (x, y, z, vx, vy, vz), y up,
    pivot y_p = A sin(2 pi f t), damping on the velocity relative to the air."""
    km, gam, W = k / m, b / m, 2 * math.pi * f

    def rhs(t, u):
        x, y, z, vx, vy, vz = u
        c = km * (1 - L0 / math.sqrt(x * x + y * y + z * z))
        vp, ap = A * W * math.cos(W * t), -A * W * W * math.sin(W * t)
        return [vx, vy, vz, -c * x - gam * vx, -c * y - g - ap - gam * (vy + vp),
                -c * z - gam * vz]
    return rhs


def start3(r, th_deg, rd=0.0, thd=0.0, phd=0.0):
    """(x, y, z, vx, vy, vz) from r, theta (degrees), their rates and the
    azimuth rate phi' (rad/s, about the vertical from +x towards +z)."""
    th = math.radians(th_deg)
    x, y = r * math.sin(th), -r * math.cos(th)
    return [x, y, 0.0, rd * math.sin(th) + r * thd * math.cos(th),
            -rd * math.cos(th) + r * thd * math.sin(th), phd * x]


def swing_maxima(t, x, z, period):
    """Times of the swing's maxima: local maxima of the mean of x^2 + z^2 over
    one pendulum period, at least a quarter of the run's length of them apart
    from each other's neighbourhood (the exchange is slow)."""
    import numpy as np
    n = max(1, int(round(period / (t[1] - t[0]))))
    amp = np.convolve(x * x + z * z, np.ones(n) / n, mode="same")
    out = []
    for i in range(n, len(t) - n):
        if amp[i] == np.max(amp[max(0, i - 10 * n):i + 10 * n]) and amp[i] > 0.5 * amp.max():
            out.append(i)
    return out


def plane_angle(x, z):
    """The principal axis of the points (x, z) about their mean, rad mod pi."""
    import numpy as np
    cxx, czz, cxz = np.mean(x * x), np.mean(z * z), np.mean(x * z)
    return 0.5 * math.atan2(2 * cxz, cxx - czz)


def precessions(t, x, z, period):
    """The swing plane's turn, degrees, between successive swing maxima: each
    plane from the horizontal positions over one pendulum period there."""
    import numpy as np
    n = int(round(period / (t[1] - t[0])))
    angles, prev = [], None
    for i in swing_maxima(t, x, z, period):
        a = plane_angle(x[i - n // 2:i + n // 2 + 1], z[i - n // 2:i + n // 2 + 1])
        if prev is not None:
            a += math.pi * round((prev - a) / math.pi)
        angles.append(a)
        prev = a
    return np.degrees(np.diff(angles)), [t[i] for i in swing_maxima(t, x, z, period)]


def doc_pages(root):
    """The manual's pages, as paths: README.md, then the doc/*.md pages in the
    order README.md links them, then any page it does not link, by name."""
    import glob
    import re
    readme = os.path.join(root, "README.md")
    pages = sorted(glob.glob(os.path.join(root, "doc", "*.md")))
    linked = re.findall(r"\]\(doc/([\w-]+\.md)[)#]", open(readme, encoding="utf-8").read())
    order = [os.path.join(root, "doc", name) for name in dict.fromkeys(linked)]
    return [readme] + [p for p in order if p in pages] + [p for p in pages if p not in order]


def manual(root):
    """README.md and the doc/*.md pages (doc_pages' order) as one text: what
    a check of the documentation's promises reads, wherever a page keeps it."""
    return "\n\n".join(open(p, encoding="utf-8").read() for p in doc_pages(root))


def doc_page(root, name):
    """The text of the page doc/NAME.md."""
    with open(os.path.join(root, "doc", name + ".md"), encoding="utf-8") as f:
        return f.read()


def readme_ci(root):
    """The fenced blocks of the "Snapshot tests in CI" page (doc/ci.md), as
    (language, text) pairs, and a function picking the first block that
    holds a marker (of a language, when given; "" when none does)."""
    import re
    section = doc_page(root, "ci")
    section = section[section.index("# Snapshot tests in CI"):]
    blocks = re.findall(r"^```([a-z]*)\n(.*?)^```", section, re.S | re.M)

    def block(marker, lang=None):
        return next((text for kind, text in blocks
                     if marker in text and (lang is None or kind == lang)), "")
    return blocks, block


def wait_caught(p, sig, limit=20.0):
    """Waits until process p catches signal sig (its handlers are set, as
    /proc/PID/status's SigCgt mask shows), so that a signal test tests the
    program's handling, not how soon a loaded machine started it."""
    import time
    end = time.time() + limit
    while time.time() < end and p.poll() is None:
        try:
            with open(f"/proc/{p.pid}/status") as f:
                caught = next((int(l.split()[1], 16) for l in f if l.startswith("SigCgt:")), 0)
        except OSError:
            caught = 0
        if caught >> (sig - 1) & 1:
            return
        time.sleep(0.01)
