#!/usr/bin/python3
"""Every relative link and image in README.md, CHANGELOG.md and docs/*.md resolves (Docs.LinksResolve).

    check_links.py SOURCE_DIR

A link [text](path) or ![alt](path) that is not a URL must name a file or folder of the
repository (relative to the document); a #anchor, in the same document or another Markdown file,
must be one of that file's headings as GitHub spells them (lower case, punctuation dropped, spaces
to hyphens, -1, -2 for repeats). Links inside code blocks and code spans are not links.
"""
import re
import sys
from pathlib import Path


def strip_code(text):
    text = re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)
    return re.sub(r"`[^`\n]*`", "", text)


def anchors(path):
    seen, out = {}, set()
    text = re.sub(r"^```.*?^```", "", path.read_text(encoding="utf-8"), flags=re.S | re.M)
    for m in re.finditer(r"^#{1,6} +(.+?) *#*$", text, re.M):
        slug = re.sub(r"[^\w\- ]", "", m.group(1).lower()).replace(" ", "-")
        n = seen.get(slug, 0)
        seen[slug] = n + 1
        out.add(slug if n == 0 else f"{slug}-{n}")
    return out


def main():
    source = Path(sys.argv[1]).resolve()
    docs = [source / "README.md", source / "CHANGELOG.md", *sorted((source / "docs").glob("*.md"))]
    failures, count = [], 0
    for doc in docs:
        for m in re.finditer(r"!?\[[^\]]*\]\(([^)\s]+)\)", strip_code(doc.read_text(encoding="utf-8"))):
            target = m.group(1)
            if re.match(r"[a-z]+:", target):
                continue  # a URL (https:, mailto:): not checked offline
            count += 1
            path, _, anchor = target.partition("#")
            file = (doc.parent / path).resolve() if path else doc
            where = f"{doc.relative_to(source)}: ({target})"
            if not file.exists():
                failures.append(f"{where}: no such file {file.relative_to(source) if file.is_relative_to(source) else file}")
            elif not file.is_relative_to(source):
                failures.append(f"{where}: points outside the repository")
            elif anchor and file.suffix == ".md" and anchor not in anchors(file):
                failures.append(f"{where}: {file.relative_to(source)} has no heading #{anchor}")
    for f in failures:
        print("FAIL:", f)
    print(f"{count} relative links in {len(docs)} documents, {len(failures)} broken")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
