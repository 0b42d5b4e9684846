#!/usr/bin/env python3
"""springpend tests (issue 28): what the twelfth attacker's pass found in
compare's baselines (doc/notes/2026-11-27/attack12.md):
- attack12 #15: an alternative baseline x.llvm.png (llvm on compare.ini's
  envs line) still got into the baselines without --env: `--approve` of a
  candidates folder copied it, and `--update=missing` added it while no
  x.png existed yet, after which it alone decided x.png's verdict. Now
  --approve copies a candidate named like an alternative only with
  --env KEY and beside its plain baseline, --update=missing never adds one,
  an alternative with no plain baseline is an error (never compared), and
  --env writes nothing (update or candidate) for an image with no plain
  baseline;
- attack12 #14: a baseline folder squatted in /tmp (another user's, mode
  755) had its owner's compare.ini read by root's compare: another user's
  compare.ini is read only when the folders above it lead, writable by
  their owners alone, to one of root's or this user's that others may not
  write (tests as root only: chown).
usage: test_attack12_baselines.py SPRINGPEND TESTS_SOURCE_DIR OUTPUT_DIR   (TAP on stdout)"""
import os
import shutil

import sptest
from sptest import done, err, ok, skip

exe, src, work, run, path, scenes, sanitized = sptest.attack_setup("attack12-baselines")
default = os.path.join(scenes, "default.ini")

# Two pictures that differ far beyond compare's default rule (the pendulum
# at t = 0 and t = 1 s).
A, Z = path("A.png"), path("Z.png")
for at, name in (("0", A), ("1", Z)):
    r = run("still", default, "--at", at, "--size", "160x90", "-o", name, "-q")
    assert r.returncode == 0, err(r)
assert open(A, "rb").read() != open(Z, "rb").read()


def fresh(*folders, envs="llvm"):
    """Empty folders under env/ (the first gets compare.ini's envs line)."""
    for i, d in enumerate(folders):
        shutil.rmtree(path("env", d), ignore_errors=True)
        os.makedirs(path("env", d))
        if i == 0:
            with open(path("env", d, "compare.ini"), "w") as f:
                f.write(f"envs = {envs}\n")


def ls(d):
    return sorted(os.listdir(path("env", d))) if os.path.isdir(path("env", d)) else []


def out(r):
    return r.stdout.decode() + err(r)


os.makedirs(path("env"), exist_ok=True)
in_env = sptest.runner_bytes(exe, path("env"))

# ---- attack12 #15 (a): --approve copies an alternative only with --env KEY, beside NAME.png ----
fresh("e", "c")
shutil.copy(A, path("env", "e", "x.png"))
shutil.copy(Z, path("env", "c", "x.llvm.png"))  # a pull request's artifact: a broken picture
r = in_env("compare", "--approve", "c", "e")
ok(r.returncode == 2 and ls("e") == ["compare.ini", "x.png"]
   and "c/x.llvm.png is named like the llvm alternative of x.png" in err(r)
   and "only with --env llvm" in err(r),
   f"--approve c e with c/x.llvm.png (llvm on envs), no --env: refused, not copied, exit 2 "
   f"(exit {r.returncode}: {ls('e')}; {out(r)[-200:]!r})")
os.makedirs(path("env", "a2"), exist_ok=True)
shutil.copy(Z, path("env", "a2", "x.png"))
r2 = in_env("compare", "e", "a2")
ok(r2.returncode == 1 and "matched the alternative" not in out(r2),
   f"so a broken x.png still fails (exit {r2.returncode}: {out(r2)[-160:]!r})")
fresh("e", "c", envs="llvm, arm64")
shutil.copy(A, path("env", "e", "x.png"))
shutil.copy(Z, path("env", "c", "x.llvm.png"))
r = in_env("compare", "--approve", "c", "e", "--env", "arm64")
ok(r.returncode == 2 and "x.llvm.png" not in ls("e") and "only with --env llvm" in err(r),
   f"--approve --env arm64 with c/x.llvm.png: refused, not copied (exit {r.returncode}: "
   f"{ls('e')}; {err(r)[-160:]!r})")
r = in_env("compare", "--approve", "c", "e", "--env", "llvm")
ok(r.returncode == 0 and ls("e") == ["compare.ini", "x.llvm.png", "x.png"]
   and open(path("env", "e", "x.llvm.png"), "rb").read() == open(Z, "rb").read(),
   f"--approve --env llvm with e/x.png there: copied, exit 0 (exit {r.returncode}: "
   f"{ls('e')}; {out(r)[-160:]!r})")
fresh("e", "c")
shutil.copy(Z, path("env", "c", "x.llvm.png"))
r = in_env("compare", "--approve", "c", "e", "--env", "llvm")
ok(r.returncode == 2 and ls("e") == ["compare.ini"] and "which has no baseline e/x.png" in err(r),
   f"--approve --env llvm with no e/x.png: refused (an alternative alone), not copied "
   f"(exit {r.returncode}: {ls('e')}; {err(r)[-160:]!r})")
shutil.copy(A, path("env", "c", "x.png"))
r = in_env("compare", "--approve", "c", "e", "--env", "llvm")
ok(r.returncode == 0 and ls("e") == ["compare.ini", "x.llvm.png", "x.png"],
   f"--approve --env llvm with c/x.png beside it: the plain one first, then its alternative "
   f"(exit {r.returncode}: {ls('e')}; {out(r)[-160:]!r})")
r = in_env("compare", "--approve", "c", "e", "--env", "zz")
ok(r.returncode == 2 and "--env zz is not among the keys declared here" in err(r),
   f"--approve --env zz (not on envs): refused (exit {r.returncode}: {err(r)[-120:]!r})")
fresh("e", "c")
shutil.copy(A, path("env", "c", "fig.1.png"))
r = in_env("compare", "--approve", "c", "e")
ok(r.returncode == 0 and ls("e") == ["compare.ini", "fig.1.png"],
   f"--approve of a dotted name whose last part is no key: copied as before (exit "
   f"{r.returncode}: {ls('e')}; {out(r)[-160:]!r})")

# ---- attack12 #15 (b): --update=missing adds no alternative, whatever exists --------------
fresh("e", "a")
shutil.copy(Z, path("env", "a", "x.llvm.png"))
r = in_env("compare", "e", "a", "--update=missing")
ok(r.returncode == 2 and ls("e") == ["compare.ini"]
   and "a/x.llvm.png is named like the llvm alternative of x.png" in out(r),
   f"--update=missing with a/x.llvm.png and no x.png anywhere: not added, an error (exit "
   f"{r.returncode}: {ls('e')}; {out(r)[-200:]!r})")
# the state that step made before: e/x.llvm.png alone, then an actual x.png
shutil.copy(Z, path("env", "e", "x.llvm.png"))
os.remove(path("env", "a", "x.llvm.png"))
shutil.copy(Z, path("env", "a", "x.png"))
r = in_env("compare", "e", "a")
ok(r.returncode == 2 and "ok   x.png" not in out(r) and "matched the alternative" not in out(r)
   and "no baseline e/x.png, only its alternative e/x.llvm.png" in out(r),
   f"e/x.llvm.png with no e/x.png: x.png is an error, not a pass by the alternative alone "
   f"(exit {r.returncode}: {out(r)[-220:]!r})")
r = in_env("compare", "e", "a", "--update=missing", "--env", "llvm")
r2 = in_env("compare", "e", "a", "--candidates", "cand", "--env", "llvm")
ok(r.returncode == 2 and ls("e") == ["compare.ini", "x.llvm.png"] and ls("cand") == []
   and "goes beside the plain baseline, never alone" in out(r),
   f"--update=missing / --candidates with --env llvm for an image with no plain baseline: "
   f"nothing written (exit {r.returncode}, {r2.returncode}: {ls('e')}, {ls('cand')}; "
   f"{out(r)[-200:]!r})")
r = in_env("compare", "e", "a", "--update=missing")
ok(ls("e") == ["compare.ini", "x.llvm.png", "x.png"]
   and open(path("env", "e", "x.png"), "rb").read() == open(Z, "rb").read(),
   f"--update=missing without --env adds the plain baseline x.png (exit {r.returncode}: "
   f"{ls('e')})")
fresh("e", "a")
shutil.copy(Z, path("env", "e", "y.llvm.png"))
shutil.copy(A, path("env", "e", "x.png"))
shutil.copy(A, path("env", "a", "x.png"))
r = in_env("compare", "e", "a", "--update=all")
ok(r.returncode == 2 and "e/y.llvm.png is the llvm alternative of y.png, which is in neither "
   "folder" in out(r) and "y.llvm.png" in ls("e"),
   f"e/y.llvm.png with y.png in neither folder: an error naming it, left in place by "
   f"--update=all (exit {r.returncode}: {ls('e')}; {out(r)[-200:]!r})")
# two files: a baseline named like an alternative is not added either
fresh("e", "a")
shutil.copy(Z, path("env", "a", "z.png"))
r = in_env("compare", "e/z.llvm.png", "a/z.png", "--update=missing")
ok(r.returncode == 2 and ls("e") == ["compare.ini"] and "not added" in out(r)
   and "--update=missing" not in out(r),
   f"compare e/z.llvm.png a/z.png --update=missing: not added, no hint to add it (exit "
   f"{r.returncode}: {ls('e')}; {out(r)[-200:]!r})")

# ---- attack12 #14: a squatted baseline folder's compare.ini is not read ---------------------
PASS_ALL = "[*]\nmax_pixels = 100%\nmax_diff = 255\n"
if os.geteuid() == 0:
    os.makedirs(path("sq"), exist_ok=True)
    os.chmod(path("sq"), 0o1777)            # a shared folder, as /tmp is (root's)
    shutil.rmtree(path("sq", "base"), ignore_errors=True)
    os.makedirs(path("sq", "base"))
    os.makedirs(path("sq2"), exist_ok=True)
    shutil.copy(A, path("sq", "base", "exp.png"))
    shutil.copy(Z, path("sq2", "act.png"))
    with open(path("sq", "base", "compare.ini"), "w") as f:
        f.write(PASS_ALL)
    os.chmod(path("sq", "base"), 0o755)
    os.chown(path("sq", "base"), 65534, 65534)  # user nobody made it first, 755
    os.chown(path("sq", "base", "compare.ini"), 65534, 65534)
    r = run("compare", path("sq", "base", "exp.png"), path("sq2", "act.png"))
    ok(r.returncode == 2 and "belongs to user 65534" in err(r) and b"ok " not in r.stdout
       and "not read" in err(r),
       f"a compare.ini of user 65534 in their own 755 folder inside a shared folder: not read, "
       f"exit 2 naming the owner (exit {r.returncode}: {out(r)[-220:]!r})")
    # folder mode the same
    os.makedirs(path("sq2", "a"), exist_ok=True)
    shutil.copy(Z, path("sq2", "a", "exp.png"))
    r = run("compare", path("sq", "base"), path("sq2", "a"))
    ok(r.returncode == 2 and "belongs to user 65534" in err(r) and b"ok " not in r.stdout,
       f"folder mode: the same, not read (exit {r.returncode}: {out(r)[-200:]!r})")
    # a folder of theirs one level deeper: still squatted
    shutil.rmtree(path("sq", "deep"), ignore_errors=True)
    os.makedirs(path("sq", "deep", "base"))
    shutil.copy(A, path("sq", "deep", "base", "exp.png"))
    with open(path("sq", "deep", "base", "compare.ini"), "w") as f:
        f.write(PASS_ALL)
    for p in (path("sq", "deep"), path("sq", "deep", "base"),
              path("sq", "deep", "base", "compare.ini")):
        os.chown(p, 65534, 65534)
    r = run("compare", path("sq", "deep", "base", "exp.png"), path("sq2", "act.png"))
    ok(r.returncode == 2 and "belongs to user 65534" in err(r) and b"ok " not in r.stdout,
       f"the same two folders deep: not read (exit {r.returncode}: {out(r)[-200:]!r})")
    # another user's checkout in a folder of root's that others may not write: read, as a
    # container's root reads the runner's workspace
    os.makedirs(path("home"), exist_ok=True)
    os.chmod(path("home"), 0o755)
    shutil.rmtree(path("home", "u"), ignore_errors=True)
    os.makedirs(path("home", "u", "base"))
    shutil.copy(A, path("home", "u", "base", "exp.png"))
    with open(path("home", "u", "base", "compare.ini"), "w") as f:
        f.write(PASS_ALL)
    for p in (path("home", "u"), path("home", "u", "base"),
              path("home", "u", "base", "compare.ini")):
        os.chown(p, 65534, 65534)
    # every folder above work must be root's and closed to others for this one
    above, closed = os.path.dirname(path("home")), True
    while True:
        st = os.stat(above)
        closed &= st.st_uid == 0 and not (st.st_mode & 0o022)
        if above == os.path.dirname(above):
            break
        above = os.path.dirname(above)
    if closed:
        r = run("compare", path("home", "u", "base", "exp.png"), path("sq2", "act.png"))
        ok(r.returncode == 0 and "ok " in out(r),
           f"user 65534's checkout under root's 755 folders: its compare.ini is read (exit "
           f"{r.returncode}: {out(r)[-200:]!r})")
    else:
        skip("another user's checkout under root's folders", f"a folder above {work} is open")
else:
    skip("a squatted baseline folder", "not root: cannot give folders away")

done()
