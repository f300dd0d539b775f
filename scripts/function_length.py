#!/usr/bin/python3
"""Functions longer than 150 lines in src/, apps/ and python/src/ (issue 26: "functions over 150
lines split into named phases"). A function's length is the lines strictly between the line of its
opening brace and the line of its closing one; a lambda or a local class counts towards the function
that holds it. Functions are found by their braces at namespace or class scope, after comments,
string and character literals are blanked out, so no compiler is needed:

    /usr/bin/python3 scripts/function_length.py            # list every function over the limit
    /usr/bin/python3 scripts/function_length.py --check    # exit 1 for one not in ALLOWED, or for an
                                                           # ALLOWED entry that is now short or gone

The test Code.FunctionsAtMost150Lines runs --check, so a long function cannot come back silently:
split it into named phases (the existing tests are the oracle), or, if it cannot be split yet, add
it to ALLOWED below with the reason, where the lead sees it.
"""

import argparse
import pathlib
import re
import sys

LIMIT = 150
ROOT = pathlib.Path(__file__).resolve().parents[1]
DIRECTORIES = ("src", "apps", "python/src")

# path:function → why it is still longer than LIMIT. Keep it short: each entry is a debt.
ALLOWED = {
}


def blank(text):
    """The text with comments and string/character literals blanked (newlines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            if end < 0:
                out.append(text[i])
                i += 1
                continue
            j = end + len(m.group(1)) + 2
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j
        elif text[i] in "\"'":
            quote = text[i]
            if quote == "'" and i > 0 and text[i - 1].isalnum():  # a digit separator: 1'000
                out.append(" ")
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != quote and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(quote * 2)
            i = j + 1
        else:
            out.append(text[i])
            i += 1
    return "".join(out)


def long_functions(path, limit=LIMIT):
    """(lines, first line, name) of each function in `path` longer than `limit` lines."""
    text = blank(path.read_text(encoding="utf-8"))
    found, stack, last, line = [], [], 0, 1
    for i, c in enumerate(text):
        if c == "\n":
            line += 1
        elif c == "{":
            head = text[last:i]
            kind = "block"
            if all(k in ("namespace", "class") for k, _, _ in stack):
                if re.search(r"\bnamespace\b", head) or re.search(r'\bextern\s*""', head):
                    kind = "namespace"
                elif re.search(r"\b(struct|class|union|enum)\b", head) and ")" not in head:
                    kind = "class"
                elif ")" in head:
                    kind = "function"
            stack.append((kind, line, head))
            last = i + 1
        elif c == "}":
            kind, start, head = stack.pop()
            last = i + 1
            if kind == "function" and line - start - 1 > limit:
                names = re.findall(r"([A-Za-z_~][\w:~]*)\s*\(", head)
                found.append((line - start - 1, start, names[0] if names else "?"))
        elif c == ";":
            last = i + 1
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="exit 1 for a long function not in ALLOWED, or a stale entry")
    args = parser.parse_args()
    seen, bad = set(), []
    for directory in DIRECTORIES:
        for path in sorted((ROOT / directory).rglob("*.cpp")):
            for lines, start, name in long_functions(path):
                key = f"{path.relative_to(ROOT).as_posix()}:{name}"
                seen.add(key)
                allowed = key in ALLOWED
                print(f"{lines:5d} lines  {path.relative_to(ROOT)}:{start} {name}" + ("  (allowed: " + ALLOWED[key] + ")" if allowed else ""))
                if not allowed:
                    bad.append(f"{key} has {lines} lines (at most {LIMIT}): split it into named phases, or add it to "
                               f"ALLOWED in scripts/function_length.py with the reason")
    bad += [f"{key} is in ALLOWED but no longer over {LIMIT} lines (or gone): remove its entry" for key in ALLOWED
            if key not in seen]
    if args.check and bad:
        print("\n".join(bad), file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
