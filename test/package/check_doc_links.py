#!/usr/bin/env python3
"""Checks that every relative Markdown link in README.md and doc/*.md resolves: the file it names exists
(relative to the page), and an #anchor names a heading of that page under GitHub's slug rule. Links to
the web are not followed. Pages that a tool generates (GENERATED) may be missing from a fresh tree; a
link to one then passes, its anchor unchecked.

Writes a JUnit file (--xunit) with one test case per page, plus the checker's own checks; exits 1 when
one fails.
"""
import argparse
import glob
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from check_report import report  # noqa: E402

# Written by scripts/measure/results and the parameter-page tool, not kept by hand.
GENERATED = {"doc/results.md", "doc/parameters.md"}

FENCE = re.compile(r"^\s*(```|~~~)")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
# [text](target) and ![alt](target); the target ends at the first space (a title may follow) or ")".
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
CODE_SPAN = re.compile(r"(`+)(.+?)\1")


def slug(heading):
    """GitHub's anchor for a heading: markup dropped, lower case, punctuation removed, spaces to '-'."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # a link keeps its text
    text = text.replace("`", "").lower()
    text = "".join(c for c in text if c.isalnum() or c in " -_")
    return text.replace(" ", "-")


def prose_lines(text):
    """The lines outside fenced code blocks, with their numbers."""
    inside = False
    for number, line in enumerate(text.splitlines(), 1):
        if FENCE.match(line):
            inside = not inside
            continue
        if not inside:
            yield number, line


def anchors(text):
    """Every heading anchor of a page, duplicates numbered as GitHub does (-1, -2, ...)."""
    seen = {}
    out = set()
    for _, line in prose_lines(text):
        match = HEADING.match(line)
        if not match:
            continue
        base = slug(match.group(2))
        count = seen.get(base, 0)
        seen[base] = count + 1
        out.add(base if count == 0 else "%s-%d" % (base, count))
    return out


def links(text):
    """[(line number, target)] of the links in a page's prose (not in code blocks or code spans)."""
    out = []
    for number, line in prose_lines(text):
        line = CODE_SPAN.sub(lambda m: " " * len(m.group(0)), line)
        out.extend((number, m.group(1)) for m in LINK.finditer(line))
    return out


def check_page(root, page, read=None, exists=os.path.exists):
    """Errors of one page (a path relative to root)."""
    read = read or (lambda path: open(path, encoding="utf-8").read())
    text = read(os.path.join(root, page))
    errors = []
    for number, target in links(text):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):  # http:, https:, mailto:
            continue
        path, _, anchor = target.partition("#")
        if path:
            resolved = os.path.normpath(os.path.join(os.path.dirname(page), path))
        else:
            resolved = page
        full = os.path.join(root, resolved)
        if not exists(full):
            if resolved.replace(os.sep, "/") in GENERATED:
                continue
            errors.append("%s:%d: %s: no such file %s" % (page, number, target, resolved))
            continue
        if anchor and full.endswith(".md") and not os.path.isdir(full):
            if anchor not in anchors(read(full)):
                errors.append("%s:%d: %s: no heading with the anchor #%s in %s" % (
                    page, number, target, anchor, resolved))
    return errors


def self_checks():
    """The checker itself: GitHub's slugs, and a missing file or anchor caught."""
    errors = []
    for heading, expected in [
        ("Simulated sequences: `scripts/simulate`", "simulated-sequences-scriptssimulate"),
        ("Bad input: what the node does", "bad-input-what-the-node-does"),
        ("Frames, and odometry or tf poses", "frames-and-odometry-or-tf-poses"),
        ("The `pose_graph` node", "the-pose_graph-node"),
        ("Gravity alignment in a world frame that is not gravity-aligned",
         "gravity-alignment-in-a-world-frame-that-is-not-gravity-aligned"),
    ]:
        if slug(heading) != expected:
            errors.append("slug(%r) = %r, expected %r" % (heading, slug(heading), expected))
    pages = {
        "a.md": "# Top\n## Part one\n## Part one\n```\n# not a heading\n```\n"
                "[ok](#part-one-1) [ok](b.md#b) `[code](missing.md)`\n",
        "b.md": "# B\n[bad anchor](a.md#part-two) [bad file](c.md) [web](https://example.com/x.md)\n",
    }
    read = lambda path: pages[os.path.basename(path)]  # noqa: E731
    exists = lambda path: os.path.basename(path) in pages  # noqa: E731
    found_a = check_page("/", "a.md", read, exists)
    found_b = check_page("/", "b.md", read, exists)
    if found_a:
        errors.append("good links refused: %s" % found_a)
    if len(found_b) != 2 or "#part-two" not in found_b[0] or "c.md" not in found_b[1]:
        errors.append("a missing anchor and a missing file not both caught: %s" % found_b)
    return errors


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--package", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."),
                        help="the repository root (default: this file's)")
    parser.add_argument("--xunit", help="JUnit result file to write")
    args = parser.parse_args()
    root = os.path.abspath(args.package)
    pages = ["README.md"] + sorted(os.path.relpath(p, root) for p in glob.glob(os.path.join(root, "doc", "*.md")))
    cases = [("checker_finds_missing_files_and_anchors", self_checks())]
    cases += [("links_resolve_" + re.sub(r"\W", "_", page), check_page(root, page)) for page in pages]
    return report("doc_links", cases, args.xunit)


if __name__ == "__main__":
    sys.exit(main())
