"""springpend tests: what the Python tests share. TAP output (ok, skip,
done), running the binary under test (runner), --set arguments (sets), and
scipy or a skip (need_scipy). Python puts a script's own folder first on
sys.path, so each test imports this with `from sptest import ...`."""
import os
import subprocess
import sys

_count = _failed = 0


def ok(cond, what):
    """One TAP line (a description that quotes a program's output keeps to
    that line); returns cond."""
    global _count, _failed
    _count += 1
    _failed += not cond
    what = " | ".join(str(what).splitlines())
    print(f"{'' if cond else 'not '}ok {_count} - {what}", flush=True)
    return cond


def skip(what, why):
    """A TAP line for a check that cannot run here."""
    global _count
    _count += 1
    print(f"ok {_count} - {what} # SKIP {why}", flush=True)


def done():
    """The TAP plan, and the exit status: 1 when a check failed."""
    print(f"1..{_count}")
    sys.exit(1 if _failed else 0)


def runner(exe, cwd):
    """A function running exe with its arguments in cwd, output captured as text."""
    def run(*args):
        return subprocess.run([exe, *args], capture_output=True, text=True, cwd=cwd)
    return run


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
