#!/usr/bin/env python3
"""clang-tidy over source files, each skipped when it passed before with the same preprocessed text.

Usage: clang_tidy_cached.py BUILD_DIR FILE...   (run from the source root; deploy/lint.sh calls it)

A file's key is the hash of: the .clang-tidy file, clang-tidy's version, the file's path in the tree, its
compile flags and its text as clang-14 preprocesses it (every header it includes, without line markers),
with the tree's location replaced in both, so clones share keys. A file that passes leaves an empty stamp named by
its key in the cache (KESSLER_LINT_CACHE, default ~/.cache/kessler-lint), so a later run skips it until
something it reads changes. No well-kept cache for clang-tidy is packaged for Debian 12, hence this.
Exit status 1 when any file has a warning (the config makes warnings errors).
"""
import hashlib
import json
import os
import shlex
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

PREPROCESSOR = "clang++-14"


def common_hash():
    h = hashlib.sha256()
    with open(".clang-tidy", "rb") as config:
        h.update(config.read())
    h.update(subprocess.run(["clang-tidy", "--version"], capture_output=True, check=True).stdout)
    return h


def flags_of(entry, root):
    """The compile command without the compiler, output and input: what shapes the file's meaning."""
    args = shlex.split(entry["command"])[1:]
    kept, skip = [], False
    for arg in args:
        if skip:
            skip = False
            continue
        if arg == "-o":
            skip = True
            continue
        if arg == "-c" or os.path.realpath(os.path.join(entry["directory"], arg)) == os.path.realpath(entry["file"]):
            continue
        kept.append(arg)
    return kept, [arg.replace(root, "<root>") for arg in kept]


def key_of(path, entry, root, common):
    flags, portable_flags = flags_of(entry, root)
    text = subprocess.run([PREPROCESSOR, *flags, "-w", "-E", "-P", entry["file"]], cwd=entry["directory"],
                          capture_output=True)
    if text.returncode != 0:
        return None  # let clang-tidy report it
    h = common.copy()
    h.update(path.encode())
    h.update("\0".join(portable_flags).encode())
    h.update(text.stdout.replace(root.encode(), b"<root>"))  # __FILE__ in macros names the tree
    return h.hexdigest()


def main():
    build, files = sys.argv[1], sys.argv[2:]
    root = os.path.realpath(".")
    with open(os.path.join(build, "compile_commands.json")) as db:
        entries = {os.path.realpath(e["file"]): e for e in json.load(db)}
    cache = os.environ.get("KESSLER_LINT_CACHE", os.path.expanduser("~/.cache/kessler-lint"))
    os.makedirs(cache, exist_ok=True)
    common = common_hash()

    def lint(path):
        entry = entries.get(os.path.realpath(path))
        if entry is None:
            return path, False, f"{path}: not in {build}/compile_commands.json\n", False
        key = key_of(path, entry, root, common)
        stamp = os.path.join(cache, key) if key else None
        if stamp and os.path.exists(stamp):
            return path, True, "", True
        run = subprocess.run(["clang-tidy", "-p", build, "--quiet", path], capture_output=True, text=True)
        if run.returncode == 0 and stamp:
            open(stamp, "w").close()
        return path, run.returncode == 0, run.stdout + run.stderr, False

    with ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
        results = list(pool.map(lint, files))
    failed = [(path, output) for path, ok, output, _ in results if not ok]
    cached = sum(1 for *_, from_cache in results if from_cache)
    for path, output in failed:
        lines = [line for line in output.splitlines() if "warning:" in line or "error:" in line]
        sys.stderr.write("\n".join(lines or output.splitlines()[-20:]) + "\n")
    if failed:
        sys.stderr.write(f"lint: clang-tidy found problems in {len(failed)} of {len(files)} files\n")
        return 1
    print(f"lint: clang-tidy clean on {len(files)} files ({cached} unchanged since a clean run, from the cache)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
