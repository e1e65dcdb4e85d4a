#!/usr/bin/env python3
"""Checks README.md and docs/*.md as one set of documents.

  docs_check.py dup ROOT    no paragraph of one file (prose or table, at least
                            MIN characters once whitespace is normalised) is
                            found again in another: each text has one home.
  docs_check.py links ROOT  every relative link and image resolves to a file
                            of the repository, and a #fragment to a heading
                            of that file (GitHub's anchor rule).
Prints each finding as FILE:LINE: problem and exits 1 if there is any."""
import os
import re
import sys

MIN = 120  # shorter paragraphs (a one-line note, a table header) may recur


def files(root):
    out = [os.path.join(root, "README.md")]
    d = os.path.join(root, "docs")
    out += sorted(os.path.join(d, f) for f in os.listdir(d) if f.endswith(".md"))
    return out


def paragraphs(path):
    """(first line, normalised text) of every block outside fenced code."""
    paras, cur, start, fence = [], [], 0, False
    for n, line in enumerate(open(path, encoding="utf-8"), 1):
        if line.startswith("```"):
            fence = not fence
            line = ""
        if fence or not line.strip():
            if cur:
                paras.append((start, " ".join(" ".join(cur).split())))
            cur = []
            continue
        if not cur:
            start = n
        cur.append(line)
    if cur:
        paras.append((start, " ".join(" ".join(cur).split())))
    return paras


def dup(root):
    fs = files(root)
    whole = {f: " \n ".join(p for _, p in paragraphs(f)) for f in fs}
    found = 0
    for f in fs:
        for n, p in paragraphs(f):
            if len(p) < MIN or p.startswith("<!--"):
                continue
            for g in fs:
                if g != f and p in whole[g]:
                    print(f"{os.path.relpath(f, root)}:{n}: paragraph kept twice, also in "
                          f"{os.path.relpath(g, root)}: {p[:70]}...")
                    found += 1
    return found


def slug(heading):
    s = heading.strip().lower()
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def anchors(path):
    seen, out, fence = {}, set(), False
    for line in open(path, encoding="utf-8"):
        if line.startswith("```"):
            fence = not fence
        m = None if fence else re.match(r"^#{1,6} +(.*?) *#*$", line)
        if m:
            s = slug(m.group(1))
            k = seen.get(s, 0)
            seen[s] = k + 1
            out.add(s if k == 0 else f"{s}-{k}")
    return out


LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


def links(root):
    found = 0
    for f in files(root):
        fence = False
        for n, line in enumerate(open(f, encoding="utf-8"), 1):
            if line.startswith("```"):
                fence = not fence
            if fence:
                continue
            for target in LINK.findall(re.sub(r"`[^`]*`", "", line)):
                if re.match(r"^[a-z]+:", target):
                    continue  # http:, https:, mailto:
                path, _, frag = target.partition("#")
                dest = os.path.normpath(os.path.join(os.path.dirname(f), path)) if path else f
                where = f"{os.path.relpath(f, root)}:{n}"
                if not os.path.exists(dest):
                    print(f"{where}: link to a missing file: {target}")
                    found += 1
                elif frag and dest.endswith(".md") and frag not in anchors(dest):
                    print(f"{where}: link to a missing heading: {target}")
                    found += 1
    return found


if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[1] not in ("dup", "links"):
        sys.exit(__doc__)
    sys.exit(1 if {"dup": dup, "links": links}[sys.argv[1]](sys.argv[2]) else 0)
