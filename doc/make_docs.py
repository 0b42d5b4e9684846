#!/usr/bin/env python3
"""Writes springpend(1) or its bash completion from the built executable's
own texts: 'springpend --help', 'springpend COMMAND --help' for every
command --help lists, and 'springpend keys'. Run at build time (meson.build),
so neither can drift from --help.
usage: make_docs.py man|bash SPRINGPEND OUTPUT"""
import re
import subprocess
import sys

kind, exe, out = sys.argv[1:4]


def text(*args):
    return subprocess.run([exe, *args], capture_output=True, text=True, check=True).stdout


top = text("--help")
block = top.split("commands:\n", 1)[1].split("\n\n", 1)[0]
commands = [(m.group(1), m.group(2)) for m in re.finditer(r"^  (\w+)\s+(.*)$", block, re.M)]
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


def options(help_text):
    return sorted(set(re.findall(r"(?<![\w-])(--[a-z][a-z-]*|-[a-z])\b", help_text)))


def roff(s):
    """Verbatim text for a .nf block: backslashes and leading dots escaped."""
    lines = []
    for line in s.rstrip("\n").split("\n"):
        line = line.replace("\\", "\\e").replace("-", "\\-")
        lines.append("\\&" + line if line.startswith((".", "'")) else line)
    return "\n".join(lines)


if kind == "man":
    version = top.split("\n", 1)[0].split()[1]
    intro, rest = top.split("usage:", 1)
    exit_status = top.split("exit status:", 1)[1].strip()
    parts = [f'.TH SPRINGPEND 1 "" "springpend {version}" "User Commands"',
             ".SH NAME", "springpend \\- " + intro.split(" - ", 1)[1].strip().replace("-", "\\-"),
             ".SH SYNOPSIS", ".nf"]
    parts += [f".B springpend {name}" + (" SCENE" if name not in ("keys", "compare") else "")
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
              ".SH FILES", "Scene files are INI text; see the scenes/ folder of the source and "
              "README.md, doc/scenes.md.", ".SH SEE ALSO", "ffmpeg(1)"]
    open(out, "w").write("\n".join(parts) + "\n")
else:
    names = " ".join(name for name, _ in commands)
    cases = "\n".join(f"        {name}) opts=\"{' '.join(options(helps[name]))}\" ;;"
                      for name, _ in commands if helps[name])
    open(out, "w").write(f"""# bash completion for springpend, generated from its --help and keys
# (doc/make_docs.py): commands, each command's options, scene keys for --set.
_springpend() {{
    local cur=${{COMP_WORDS[COMP_CWORD]}} prev=${{COMP_WORDS[COMP_CWORD-1]}} opts=""
    if [ "$COMP_CWORD" -eq 1 ]; then
        COMPREPLY=($(compgen -W "{names} --help --version" -- "$cur"))
        return
    fi
    if [ "$prev" = "--set" ]; then
        compopt -o nospace 2>/dev/null
        COMPREPLY=($(compgen -W "{' '.join(k + '=' for k in keys)}" -- "$cur"))
        return
    fi
    case ${{COMP_WORDS[1]}} in
{cases}
    esac
    if [[ $cur == -* ]]; then
        COMPREPLY=($(compgen -W "$opts" -- "$cur"))
    else
        COMPREPLY=($(compgen -f -- "$cur"))
    fi
}}
complete -o filenames -F _springpend springpend
""")
