#!/usr/bin/env python3
"""Writes springpend(1) and a page per command (springpend-render(1), ...),
or the bash completion, from the built executable's own texts: 'springpend
--help', 'springpend COMMAND --help' for every command --help lists, and
'springpend keys'. Run at build time (meson.build), so none can drift from
--help. The man outputs are springpend.1 and then one springpend-COMMAND.1
per command, in the order --help lists them (doc/meson.build declares them;
a command added to --help and not there, or the other way round, fails the
build naming both lists).
The pages are installed: where --help names the source tree's scenes/ (the
built executable runs from the build tree), they name the installed
folders, SCENES and DOCS (where README.md and doc/*.md are installed).
usage: make_docs.py man SPRINGPEND SCENES DOCS springpend.1 springpend-COMMAND.1 ...
       make_docs.py bash SPRINGPEND OUTPUT"""
import os
import re
import subprocess
import sys

if sys.argv[1:2] in (["-h"], ["--help"]):
    sys.exit(print(__doc__))
if len(sys.argv) < 4 or sys.argv[1] not in ("man", "bash"):
    print(__doc__, file=sys.stderr)
    sys.exit(2)
kind, exe = sys.argv[1], sys.argv[2]
if kind == "man":
    installed_scenes, installed_docs = sys.argv[3], sys.argv[4]
    del sys.argv[3:5]
out = sys.argv[3]


def text(*args):
    return subprocess.run([exe, *args], capture_output=True, text=True, check=True).stdout


top = text("--help")
if kind == "man":
    # the build tree's executable names the source's scenes/; the page is
    # for the installed program
    source_scenes = os.path.realpath(os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                  "..", "scenes"))
    if f"  {source_scenes}/\n" not in top:
        sys.exit(f"make_docs.py: --help does not name the source's scenes folder {source_scenes}/")
    top = top.replace(f"  {source_scenes}/\n", f"  {installed_scenes}/\n")
    source_docs = os.path.dirname(os.path.realpath(os.path.abspath(__file__)))
    if f"  {source_docs}/\n" not in top:
        sys.exit(f"make_docs.py: --help does not name the source's guides folder {source_docs}/")
    top = top.replace(f"  {source_docs}/\n", f"  {installed_docs}/\n")
block = top.split("commands:\n", 1)[1].split("\n\n", 1)[0]
# a command's line, with the lines its description wraps onto
commands = [(m.group(1), " ".join(m.group(2).split()))
            for m in re.finditer(r"^  (\w+)\s+(.*(?:\n {4,}\S.*)*)", block, re.M)]
helps = {name: text(name, "--help") if name != "keys" else "" for name, _ in commands}
keys_text = text("keys")
keys, section = [], ""
for line in keys_text.splitlines():
    m = re.match(r"^  \[(\w+)\]$", line)
    if m:
        section = m.group(1)
    m = re.match(r"^    (\w+)\s", line)
    if m and section:
        keys.append(f"{section}.{m.group(1)}")


OPTION = r"(?<![\w-])(--[a-z][a-z-]*|-[a-z])\b"


def options(help_text):
    """The options a command takes: those of its usage lines (the first
    paragraph) and of its option list (a line "  -o, --output PATH   what",
    the part before the description). Not every dashed word of the text:
    the prose names other commands' options ("--state is still's")."""
    usage = help_text.split("\n\n", 1)[0]
    listed = [re.split(r" {2,}", line.strip(), maxsplit=1)[0]
              for line in help_text.splitlines() if re.match(r"^ {2}-", line)]
    return sorted(set(re.findall(OPTION, usage + "\n" + "\n".join(listed))) | {"-h", "--help"})


def roff(s):
    """Verbatim text for a .nf block: backslashes and leading dots escaped."""
    lines = []
    for line in s.rstrip("\n").split("\n"):
        line = line.replace("\\", "\\e").replace("-", "\\-")
        lines.append("\\&" + line if line.startswith((".", "'")) else line)
    return "\n".join(lines)


def command_page(name, what, version, others):
    """springpend-NAME(1): the command's line of --help, its own --help (for
    keys, the key list), the exit statuses and the other pages."""
    text = helps[name] or keys_text
    usage, body = text.split("\n\n", 1) if text.startswith("usage:") else (f"springpend {name}", text)
    parts = [f'.TH SPRINGPEND\\-{name.upper()} 1 "" "springpend {version}" "User Commands"',
             ".SH NAME", f"springpend\\-{name} \\- " + roff(what),
             ".SH SYNOPSIS", ".nf", roff(usage.replace("usage: ", "", 1)), ".fi",
             ".SH DESCRIPTION", ".nf", roff(body), ".fi",
             ".SH EXIT STATUS", ".nf", roff(exit_status), ".fi",
             ".SH SEE ALSO", ".nh", ",\n".join(f".BR {page} (1)" for page in ["springpend"] + others)]
    return "\n".join(parts) + "\n"


if kind == "man":
    pages = [os.path.basename(p) for p in sys.argv[4:]]
    want = [f"springpend-{name}.1" for name, _ in commands]
    if os.path.basename(out) != "springpend.1" or pages != want:
        sys.exit(f"make_docs.py: the man pages asked for ({', '.join([os.path.basename(out)] + pages)}) "
                 f"are not springpend.1 and one per command --help lists ({', '.join(want)}); "
                 "update the list in doc/meson.build")
    version = top.split("\n", 1)[0].split()[1]
    intro, rest = top.split("usage:", 1)
    exit_status = top.split("exit status:", 1)[1].strip()
    parts = [f'.TH SPRINGPEND 1 "" "springpend {version}" "User Commands"',
             ".SH NAME", "springpend \\- " + intro.split(" - ", 1)[1].strip().replace("-", "\\-"),
             ".SH SYNOPSIS", ".nf"]
    parts += [f".B springpend {name}" + (" SCENE" if name not in ("keys", "compare", "version") else "")
              + (" EXPECTED ACTUAL" if name == "compare" else "") + (" [options]" * (name != "keys"))
              for name, _ in commands]
    parts += [".fi", ".SH DESCRIPTION", ".nf", roff("usage:" + rest.split("exit status:")[0]), ".fi",
              ".SH COMMANDS"]
    for name, what in commands:
        parts += [f".SS {name}", roff(what)]
        if helps[name]:
            parts += [".PP", ".nf", roff(helps[name]), ".fi"]
    parts += [".SH SCENE KEYS", ".nf", roff(keys_text), ".fi",
              ".SH EXIT STATUS", ".nf", roff(exit_status), ".fi",
              ".SH FILES", f".TP\n{roff(installed_scenes)}/", "The shipped scenes (INI text), to "
              "start from: default.ini, chaotic.ini, ... (scenes/ in the source).",
              f".TP\n{roff(installed_docs)}/", "README.md and the guides: scenes.md (scene "
              "files), outputs.md, ci.md, teaching.md, ... (README.md and doc/ in the source).", ".SH SEE ALSO", ".nh",
              ",\n".join(f".BR springpend\\-{name} (1)" for name, _ in commands) + ",",
              ".BR ffmpeg (1)"]
    open(out, "w").write("\n".join(parts) + "\n")
    for (name, what), path in zip(commands, sys.argv[4:]):
        open(path, "w").write(command_page(name, what, version,
                                           [f"springpend\\-{n}" for n, _ in commands if n != name]))
else:
    # The --set keys each command reads, asked of the binary itself: a key a
    # command does not read is refused before the scene is opened ("does not
    # read", "does not use"), so a scene that does not exist tells them apart.
    probe = {"sweep": ["--vary", "pendulum.mass=1:2:2", "--measure", "lyapunov", "--time", "1",
                       "-o", "-"]}
    def reads(name, key):
        r = subprocess.run([exe, name, "/nonexistent/springpend-probe.ini", *probe.get(name, []),
                            "--set", f"{key}=0"], capture_output=True, text=True)
        return "does not read" not in r.stderr and "does not use" not in r.stderr
    set_keys = {name: [k for k in keys if reads(name, k)]
                for name, _ in commands if "--set" in options(helps[name])}
    names = " ".join(name for name, _ in commands)
    cases = "\n".join(f"        {name}) opts=\"{' '.join(options(helps[name]))}\"\n"
                      f"            keys=\"{' '.join(k + '=' for k in set_keys.get(name, []))}\" ;;"
                      for name, _ in commands if helps[name])
    open(out, "w").write(f"""# bash completion for springpend, generated from its --help and keys
# (doc/make_docs.py): commands, each command's options, scene keys for --set.
_springpend() {{
    local cur=${{COMP_WORDS[COMP_CWORD]}} prev=${{COMP_WORDS[COMP_CWORD-1]}} opts="" keys=""
    if [ "$COMP_CWORD" -eq 1 ]; then
        COMPREPLY=($(compgen -W "{names} --help --version" -- "$cur"))
        return
    fi
    case ${{COMP_WORDS[1]}} in
{cases}
    esac
    if [ "$prev" = "--set" ]; then
        compopt -o nospace 2>/dev/null
        COMPREPLY=($(compgen -W "$keys" -- "$cur"))
    elif [[ $cur == -* ]]; then
        COMPREPLY=($(compgen -W "$opts" -- "$cur"))
    else # one name per line: not split at blanks, not globbed
        mapfile -t COMPREPLY < <(compgen -f -- "$cur")
    fi
}}
complete -o filenames -F _springpend springpend
""")
