#!/usr/bin/env python3
"""Checks that the repository stands on its own:

- no tracked file cites the design notes that live outside the repository (the reference
  facts the code relies on are in docs/reference.md, in the project's own words); the one
  exception is where a test looks for a data set kept beside the checkout (ALLOWED);
- every relative link in a Markdown file names a file or folder that exists;
- every repository path written in docs/paper-map.md exists.

usage: scripts/check-docs.py [--root DIR]   (exit 1 and one line per problem when one fails)
"""
import argparse
import os
import re
import subprocess
import sys

# Built from parts so that this file does not match itself.
OUTSIDE = [re.compile(re.escape("REFERENCE" + ".md")), re.compile(re.escape(".." + "/shared"))]
# The one deliberate exception: the real LiDAR scan pair is test data kept beside the checkout,
# not in it (its licence and size); the test looks for it there and skips, saying so, without it.
ALLOWED = {"tests/odometry/CMakeLists.txt"}
LINK = re.compile(r"\]\(([^)\s]+)\)")
PATH = re.compile(r"\b((?:common|procs|tests|deploy|scripts|docs|lcmtypes)/[A-Za-z0-9_./-]+\.(?:cpp|hpp|py|sh|yaml|md|lcm))")


def tracked(root):
    out = subprocess.run(["git", "-C", root, "ls-files", "-z"], capture_output=True, check=True).stdout
    return [p for p in out.decode().split("\0") if p]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    root = os.path.abspath(ap.parse_args().root)
    problems = []
    files = tracked(root)
    for rel in files:
        path = os.path.join(root, rel)
        if not os.path.isfile(path):
            continue
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except (UnicodeDecodeError, OSError):
            continue  # binary or unreadable: nothing to cite
        for n, line in enumerate(text.splitlines(), 1):
            if rel in ALLOWED:
                break
            for pat in OUTSIDE:
                if pat.search(line):
                    problems.append(f"{rel}:{n}: cites a file outside the repository: {line.strip()[:100]}")
        if not rel.endswith(".md"):
            continue
        base = os.path.dirname(path)
        for n, line in enumerate(text.splitlines(), 1):
            for target in LINK.findall(line):
                if re.match(r"^[a-z]+:", target) or target.startswith("#"):
                    continue  # URL, or an anchor in the same page
                target = target.split("#")[0]
                if not os.path.exists(os.path.normpath(os.path.join(base, target))):
                    problems.append(f"{rel}:{n}: link to a missing file: {target}")
    paper_map = os.path.join(root, "docs", "paper-map.md")
    if os.path.isfile(paper_map):
        with open(paper_map, encoding="utf-8") as f:
            for n, line in enumerate(f.read().splitlines(), 1):
                for p in PATH.findall(line):
                    if not os.path.exists(os.path.join(root, p)):
                        problems.append(f"docs/paper-map.md:{n}: names a missing file: {p}")
    for p in problems:
        print(p)
    if problems:
        print(f"{len(problems)} problem(s)")
        return 1
    print(f"ok: {len(files)} files, no outside citations, every link and mapped path exists")
    return 0


if __name__ == "__main__":
    sys.exit(main())
