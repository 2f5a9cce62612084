#!/usr/bin/env python3
"""The docs hold together, and the sources point only at them.

  links       every relative link and image of README.md and docs/*.md names a file of the
              repository, and its #anchor a heading of that page (GitHub's anchors)
  references  no source, script, build file, scene or page cites a document the repository does
              not hold (the project's former design notes, a folder outside the checkout) or an
              issue number: a user who clones the project has neither

Usage: docs_consistency.py links|references <source dir>
"""
import os
import re
import sys

# Built from parts so that this file does not match itself.
OUTSIDE = [re.compile(p) for p in (
    r"SPEC" + r" §", r"SPEC" + r" section", r"\bPHYSICS" + r"(\.md| §| section)", r"\bDESIGN" + r"(\.md|:)",
    r"\bTARGETS" + r"\.md", r"shared" + r"/", r"\b[Ii]ssue" + r" [0-9]")]
SKIPPED_DIRS = {".git", "node_modules", "__pycache__"}
TEXT_SUFFIXES = {".cpp", ".hpp", ".h", ".c", ".py", ".sh", ".txt", ".cmake", ".json", ".md", ".in", ".ld",
                 ".dict", ".conf", ".service", ""}


def anchor(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = re.sub(r"[`*_]", "", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def headings(path):
    anchors, fenced = set(), False
    for line in open(path, encoding="utf-8"):
        if line.startswith("```"):
            fenced = not fenced
        elif not fenced and re.match(r"#{1,6} ", line):
            anchors.add(anchor(line.lstrip("#")))
    return anchors


def check_links(source):
    pages = [os.path.join(source, "README.md")]
    docs = os.path.join(source, "docs")
    pages += sorted(os.path.join(docs, f) for f in os.listdir(docs) if f.endswith(".md"))
    problems, count = [], 0
    for page in pages:
        text = re.sub(r"```.*?```", "", open(page, encoding="utf-8").read(), flags=re.S)
        for target in re.findall(r"\]\(([^)\s]+)\)", text):
            if re.match(r"[a-z]+:", target):
                continue  # http:, https:, mailto:
            count += 1
            path, _, fragment = target.partition("#")
            file = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
            where = os.path.relpath(page, source)
            if not os.path.exists(file):
                problems.append(f"{where}: link to {target}: no file {os.path.relpath(file, source)}")
            elif fragment and file.endswith(".md") and fragment not in headings(file):
                problems.append(f"{where}: link to {target}: no heading #{fragment} there")
    return problems, f"links={count} pages={len(pages)}"


def check_references(source):
    problems, count = [], 0
    for root, dirs, files in os.walk(source):
        dirs[:] = [d for d in dirs if d not in SKIPPED_DIRS and not d.startswith("build")]
        for name in files:
            path = os.path.join(root, name)
            if os.path.splitext(name)[1] not in TEXT_SUFFIXES and "corpus" not in path:
                continue
            try:
                lines = open(path, encoding="utf-8").read().split("\n")
            except (UnicodeDecodeError, OSError):
                continue
            count += 1
            for number, line in enumerate(lines, 1):
                if any(p.search(line) for p in OUTSIDE):
                    problems.append(f"{os.path.relpath(path, source)}:{number}: {line.strip()[:100]}")
    return problems, f"files={count}"


def main():
    what, source = sys.argv[1], os.path.abspath(sys.argv[2])
    problems, summary = {"links": check_links, "references": check_references}[what](source)
    for problem in problems:
        print("FAIL", problem)
    print(f"{summary} problems={len(problems)}")
    return 1 if problems else 0


sys.exit(main())
