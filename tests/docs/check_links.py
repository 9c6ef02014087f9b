#!/usr/bin/env python3
"""Checks the relative links of hrisim's documentation: README.md and docs/**/*.md.

    python3 tests/docs/check_links.py [REPOSITORY ROOT]

Every Markdown link [text](target), image ![alt](target) and reference definition [label]: target
whose target is a path (not http:, https:, mailto: or another scheme) must name a file or folder
that exists inside the repository. A #anchor, alone or after a .md file, must name a heading of
that file, slugged as GitHub does. Links inside code blocks and code spans are not links.

Prints each broken link as FILE:LINE: target (why) and exits 1 when there is one, 0 otherwise.
Python 3 standard library only.
"""

import os
import re
import sys
import unicodedata
import urllib.parse

SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")
FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,})")
ATX = re.compile(r"^ {0,3}(#{1,6})(?:[ \t]+(.*?))?(?:[ \t]+#+)?[ \t]*$")
SETEXT = re.compile(r"^ {0,3}(=+|-+)[ \t]*$")
# [text](target "title"): text may hold one level of brackets; the target may be <...> or hold
# balanced parentheses.
INLINE = re.compile(
    r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]"
    r"\(\s*(<[^>\n]*>|[^()\s]*(?:\([^()\s]*\)[^()\s]*)*)"
    r"(?:\s+(?:\"[^\"]*\"|'[^']*'|\([^()]*\)))?\s*\)")
REFERENCE = re.compile(r"^ {0,3}\[[^\]]+\]:\s*(<[^>]*>|\S+)")
HTML = re.compile(r"<(?:a|img)\b[^>]*?\b(?:href|src)\s*=\s*[\"']([^\"']*)[\"']", re.IGNORECASE)
HTML_ANCHOR = re.compile(r"<a\b[^>]*?\b(?:name|id)\s*=\s*[\"']([^\"']+)[\"']", re.IGNORECASE)


def mask_code_spans(line):
    """The line with every code span's content and backticks replaced by spaces."""
    out, i = [], 0
    while i < len(line):
        if line[i] != "`":
            out.append(line[i])
            i += 1
            continue
        run = len(line[i:]) - len(line[i:].lstrip("`"))
        close = line.find("`" * run, i + run)
        while close != -1 and close + run < len(line) and line[close + run] == "`":
            close = line.find("`" * run, close + run + 1)
        if close == -1:  # no closing run: literal backticks
            out.append(line[i:i + run])
            i += run
            continue
        out.append(" " * (close + run - i))
        i = close + run
    return "".join(out)


def prose_lines(text):
    """(line number, line) of every line outside fenced code blocks."""
    fence = None
    for number, line in enumerate(text.splitlines(), 1):
        opened = FENCE.match(line)
        if fence:
            if opened and opened.group(1)[0] == fence[0] and len(opened.group(1)) >= len(fence) \
                    and not line.strip().lstrip(fence[0]):
                fence = None
            continue
        if opened:
            fence = opened.group(1)
            continue
        yield number, line


def plain_heading(text):
    """A heading's text as GitHub renders it, before slugging."""
    text = re.sub(r"!\[([^\]]*)\]\([^)]*\)", r"\1", text)      # images: their alt text
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)       # links: their text
    text = re.sub(r"<[^>]+>", "", text)                        # HTML tags
    text = re.sub(r"\\(.)", r"\1", text)                        # backslash escapes
    text = text.replace("`", "")                                # code spans keep their content
    text = re.sub(r"(?<![\w])_(\S(?:.*?\S)?)_(?![\w])", r"\1", text)  # _emphasis_
    return text.strip()


def slug(text):
    """GitHub's heading anchor: lower case; letters, digits, _, - and spaces kept; spaces become -."""
    kept = []
    for ch in plain_heading(text).lower():
        category = unicodedata.category(ch)
        if ch in " -_" or category[0] in "LN" or category[0] == "M" or category == "Pc":
            kept.append(ch)
    return "".join(kept).replace(" ", "-")


def anchors_of(text):
    """Every anchor a Markdown text defines: its headings' slugs (numbered when repeated) and HTML ids."""
    anchors, seen, previous = set(), {}, None
    for _, line in prose_lines(text):
        heading = None
        match = ATX.match(line)
        if match:
            heading = match.group(2) or ""
        elif previous is not None and SETEXT.match(line):
            heading = previous
        if heading is not None:
            base = slug(heading)
            count = seen.get(base, 0)
            seen[base] = count + 1
            anchors.add(base if count == 0 else "%s-%d" % (base, count))
            previous = None
            continue
        for found in HTML_ANCHOR.finditer(line):
            anchors.add(found.group(1))
        # A setext heading's text is one plain paragraph line just above the underline.
        stripped = line.strip()
        plain = stripped and not re.match(r"^([-*+>|]|\d+[.)]\s|<|#)", stripped) and not line.startswith("    ")
        previous = stripped if plain else None
    return anchors


def links_of(text):
    """(line number, target) of every link in a Markdown text."""
    for number, line in prose_lines(text):
        masked = mask_code_spans(line)
        for found in INLINE.finditer(masked):
            yield number, found.group(1)
        found = REFERENCE.match(masked)
        if found:
            yield number, found.group(1)
        for found in HTML.finditer(masked):
            yield number, found.group(1)


def documents(root):
    """README.md and every .md file under docs/, sorted."""
    found = []
    if os.path.isfile(os.path.join(root, "README.md")):
        found.append(os.path.join(root, "README.md"))
    for folder, folders, files in os.walk(os.path.join(root, "docs")):
        folders.sort()
        found.extend(os.path.join(folder, name) for name in sorted(files) if name.endswith(".md"))
    return found


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def check(root):
    """Every broken link as (file relative to root, line, target, why)."""
    root = os.path.realpath(root)
    anchor_cache = {}

    def anchors(path):
        if path not in anchor_cache:
            anchor_cache[path] = anchors_of(read(path))
        return anchor_cache[path]

    broken = []
    for document in documents(root):
        name = os.path.relpath(document, root)
        for number, target in links_of(read(document)):
            target = target.strip()
            if target.startswith("<") and target.endswith(">"):
                target = target[1:-1].strip()
            if not target or SCHEME.match(target) or target.startswith("//"):
                continue  # a URL (http:, https:, mailto: …), not a file of the repository
            path, _, anchor = target.partition("#")
            path = urllib.parse.unquote(path.split("?", 1)[0])
            anchor = urllib.parse.unquote(anchor)
            if path:
                base = root if path.startswith("/") else os.path.dirname(document)
                resolved = os.path.realpath(os.path.join(base, path.lstrip("/")))
                if resolved != root and not resolved.startswith(root + os.sep):
                    broken.append((name, number, target, "outside the repository"))
                    continue
                if not os.path.exists(resolved):
                    broken.append((name, number, target, "no such file"))
                    continue
            else:
                resolved = document
            if anchor and resolved.endswith(".md") and os.path.isfile(resolved):
                if anchor not in anchors(resolved):
                    broken.append((name, number, target, "no heading with this anchor"))
    return broken


def main(argv):
    if len(argv) > 2 or (len(argv) == 2 and argv[1] in ("-h", "--help")):
        print(__doc__.strip())
        return 2
    root = argv[1] if len(argv) == 2 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    if not os.path.isdir(root):
        print("check_links.py: no folder %s" % root, file=sys.stderr)
        return 2
    broken = check(root)
    for name, number, target, why in broken:
        print("%s:%d: %s (%s)" % (name, number, target, why))
    checked = len(documents(root))
    if broken:
        print("%d broken link%s in %d files" % (len(broken), "" if len(broken) == 1 else "s", checked))
        return 1
    print("links ok in %d files" % checked)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
