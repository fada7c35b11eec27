#!/usr/bin/env python3
"""clang-tidy over source files, each skipped when it passed before with the same preprocessed text.

Usage: clang_tidy_cached.py BUILD_DIR FILE...   (run from the source root; deploy/lint.sh calls it)

A file's key is the hash of: the .clang-tidy file, clang-tidy's version, the file's path in the tree, its
compile flags and its text as clang-14 preprocesses it (every header it includes, without line markers),
with the tree's location replaced in both, so clones share keys. -march=native is read as -march=x86-64
(by the key and by clang-tidy alike), so keys do not depend on the machine's CPU either.

Two places remember passes: the local cache (KESSLER_LINT_CACHE, default ~/.cache/kessler-lint, an empty
stamp per key) and the tree's own list, deploy/lint-passed.txt (key and path per line), which every clean
run brings up to date and which is committed with the change. A new clone (CI) thus checks
only the files whose preprocessed text differs from the last clean run, plus SPOT_CHECKS files taken at
random from those the list vouches for, so a stale or hand-edited list is caught.
No well-kept cache for clang-tidy is packaged for Debian 12, hence this.
Exit status 1 when any file has a warning (the config makes warnings errors).
"""
import hashlib
import json
import os
import random
import shlex
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

PREPROCESSOR = "clang++-14"
PASS_LIST = "deploy/lint-passed.txt"
SPOT_CHECKS = 3
PORTABLE_ARCH = "-march=x86-64"


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
        kept.append(PORTABLE_ARCH if arg == "-march=native" else arg)
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


def read_pass_list():
    """key -> path of the files the tree's list says passed."""
    if not os.path.exists(PASS_LIST):
        return {}
    with open(PASS_LIST) as listed:
        rows = [line.split() for line in listed if line.strip() and not line.startswith("#")]
    return {row[0]: row[1] for row in rows if len(row) == 2}


def write_pass_list(keys):
    with open(PASS_LIST, "w") as out:
        out.write("# clang-tidy passes: key (deploy/clang_tidy_cached.py) and file; rewritten by deploy/lint.sh\n")
        for path, key in sorted(keys.items()):
            out.write(f"{key} {path}\n")


def run_clang_tidy(build, path):
    run = subprocess.run(["clang-tidy", "-p", build, "--quiet", f"--extra-arg={PORTABLE_ARCH}", path],
                         capture_output=True, text=True)
    return run.returncode == 0, run.stdout + run.stderr


def main():
    build, files = sys.argv[1], sys.argv[2:]
    root = os.path.realpath(".")
    with open(os.path.join(build, "compile_commands.json")) as db:
        entries = {os.path.realpath(e["file"]): e for e in json.load(db)}
    cache = os.environ.get("KESSLER_LINT_CACHE", os.path.expanduser("~/.cache/kessler-lint"))
    os.makedirs(cache, exist_ok=True)
    common = common_hash()
    listed = read_pass_list()
    keys = {}

    def lint(path):
        entry = entries.get(os.path.realpath(path))
        if entry is None:
            return path, False, f"{path}: not in {build}/compile_commands.json\n", None
        key = key_of(path, entry, root, common)
        keys[path] = key
        stamp = os.path.join(cache, key) if key else None
        if stamp and os.path.exists(stamp):
            return path, True, "", "stamp"
        if key and listed.get(key) == path:
            return path, True, "", "list"
        ok, output = run_clang_tidy(build, path)
        if ok and stamp:
            open(stamp, "w").close()
        return path, ok, output, None

    with ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
        results = list(pool.map(lint, files))
        vouched = sorted(path for path, _, _, source in results if source == "list")
        spot = random.sample(vouched, min(SPOT_CHECKS, len(vouched)))
        spot_results = list(pool.map(lambda path: (path, *run_clang_tidy(build, path)), spot))
    failed = [(path, output) for path, ok, output, _ in results if not ok]
    failed += [(path, f"{path}: listed in {PASS_LIST} as clean, but:\n{output}") for path, ok, output in spot_results
               if not ok]
    cached = sum(1 for *_, source in results if source)
    for path, output in failed:
        lines = [line for line in output.splitlines() if "warning:" in line or "error:" in line]
        sys.stderr.write("\n".join(lines or output.splitlines()[-20:]) + "\n")
    if failed:
        sys.stderr.write(f"lint: clang-tidy found problems in {len(failed)} of {len(files)} files\n")
        return 1
    if all(keys.get(path) for path in files):
        # Files outside this run keep their entries while they exist; a deleted file's entry goes.
        merged = {path: key for key, path in listed.items() if path not in keys and os.path.exists(path)}
        merged.update(keys)
        write_pass_list(merged)
    print(f"lint: clang-tidy clean on {len(files)} files ({cached} unchanged since a clean run, from the caches; "
          f"{len(spot)} of those checked again at random)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
