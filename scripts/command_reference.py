#!/usr/bin/python3
"""Writes docs/commands.md, the command reference, from `toolpoint --help` and every command's and
subcommand's `--help`, so that it says what the binary says.

    /usr/bin/python3 scripts/command_reference.py build/toolpoint docs/commands.md
    /usr/bin/python3 scripts/command_reference.py build/toolpoint docs/commands.md --check

With --check it writes nothing: it regenerates the reference and exits 1, with a diff and the
command above, when docs/commands.md differs (the test Docs.CommandReferenceIsCurrent).
Commands are found in the "Subcommands:" list of each help text, in the order the help lists them.
"""
import difflib
import subprocess
import sys
from pathlib import Path

HEADER = """# Command reference

Generated from `toolpoint --help` and each command's `--help` by `scripts/command_reference.py`;
do not edit: run `/usr/bin/python3 scripts/command_reference.py build/toolpoint docs/commands.md`
after changing an option (the test `Docs.CommandReferenceIsCurrent` fails until then). What each
command is for: the README's [Commands](../README.md#commands) table; the user guide: the README's
[Documentation](../README.md#documentation) list.
"""


def help_text(tool, words):
    r = subprocess.run([tool, *words, "--help"], capture_output=True, text=True, encoding="utf-8", env={"LC_ALL": "C.UTF-8"})
    if r.returncode != 0:
        sys.exit(f"command_reference: `toolpoint {' '.join(words)} --help` exited {r.returncode}:\n{r.stderr}")
    return r.stdout.rstrip("\n") + "\n"


def subcommands(text):
    names, inside = [], False
    for line in text.splitlines():
        if line == "Subcommands:":
            inside = True
        elif inside and line.startswith("  ") and line.strip():
            names.append(line.split()[0])
        elif inside:
            inside = False
    return names


def reference(tool):
    sections, contents = [], []

    def visit(words, depth):
        text = help_text(tool, words)
        title = "toolpoint " + " ".join(words) if words else "toolpoint"
        anchor = "-".join(["toolpoint", *words])
        contents.append("  " * max(depth - 1, 0) + f"- [`{title}`](#{anchor})")
        sections.append(f"{'#' * min(depth + 2, 4)} `{title}`\n\n```text\n{text}```\n")
        for name in subcommands(text):
            visit([*words, name], depth + 1)

    visit([], 0)
    return HEADER + "\n" + "\n".join(contents) + "\n\n" + "\n".join(sections)


def main():
    args = [a for a in sys.argv[1:] if a != "--check"]
    if len(args) != 2:
        sys.exit("usage: command_reference.py TOOLPOINT OUTPUT.md [--check]")
    tool, output = args
    text = reference(tool)
    if "--check" in sys.argv:
        old = Path(output).read_text(encoding="utf-8") if Path(output).exists() else ""
        if old != text:
            diff = difflib.unified_diff(old.splitlines(True), text.splitlines(True), output, "toolpoint --help")
            sys.stdout.writelines(diff)
            print(f"\n{output} is stale: run `/usr/bin/python3 scripts/command_reference.py build/toolpoint docs/commands.md` "
                  "and commit docs/commands.md")
            return 1
        print(f"{output} is current")
        return 0
    Path(output).write_text(text, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
