#!/usr/bin/env python3
"""Adds where a benchmark's figures come from to its JSON file.

    scripts/bench-provenance.py FILE.json --command "deploy/ucon bench nav --seeds 10"

Writes a "provenance" object into the file's top-level JSON object: the git revision of the
checkout (with "-dirty" when it has uncommitted changes to tracked files), the UTC date, the
machine (CPU model, logical cores, memory, kernel) and the exact command. `deploy/ucon bench
NAME --json FILE` calls it after every run, so every file in docs/benchmarks/ says which code,
which machine and which command produced it.
"""
import argparse
import datetime
import json
import os
import platform
import subprocess
import sys


def git(root, *args):
    try:
        return subprocess.run(["git", "-C", root, *args], check=True, capture_output=True,
                              text=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return ""


def cpu_model():
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def memory_gib():
    try:
        with open("/proc/meminfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("MemTotal:"):
                    return round(int(line.split()[1]) / (1024 * 1024), 1)
    except OSError:
        pass
    return None


def provenance(root, command):
    rev = git(root, "rev-parse", "HEAD") or "unknown"
    if rev != "unknown" and git(root, "status", "--porcelain", "--untracked-files=no"):
        rev += "-dirty"
    return {
        "git_revision": rev,
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "machine": {
            "cpu_model": cpu_model(),
            "cores": os.cpu_count(),
            "memory_gib": memory_gib(),
            "kernel": platform.release(),
        },
        "command": command,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("file", help="benchmark JSON file (a JSON object)")
    ap.add_argument("--command", required=True, help="the exact command that produced it")
    ap.add_argument("--note", help="a sentence on the conditions (e.g. what else ran)")
    ap.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."),
                    help="the checkout whose revision is recorded")
    args = ap.parse_args()
    try:
        with open(args.file, encoding="utf-8") as f:
            data = json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        print(f"bench-provenance: cannot read {args.file}: {e}", file=sys.stderr)
        return 2
    if not isinstance(data, dict):
        print(f"bench-provenance: {args.file}: top level is not a JSON object", file=sys.stderr)
        return 2
    data["provenance"] = provenance(args.root, args.command)
    if args.note:
        data["provenance"]["note"] = args.note
    tmp = args.file + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        json.dump(data, f, indent=1)
        f.write("\n")
    os.replace(tmp, args.file)
    return 0


if __name__ == "__main__":
    sys.exit(main())
