#!/usr/bin/python3
"""The standing mutation campaign (docs/testing.md).

Plants one realistic bug at a time (a mutant from scripts/mutants.json: a file,
an exact text that occurs once in it, its replacement), rebuilds the build
folder incrementally, runs the tests that should catch it and restores the file
byte for byte. Prints a markdown table of caught / MISSED / not applicable /
build failed and exits 1 when a mutant is missed (or, with --strict, when one
no longer applies or does not build).

Usage: scripts/mutants.py [--build DIR] [--only ID,...] [--sample ci]
                          [--table FILE] [--lock FILE] [--strict] [--no-baseline]

Standard library only (Debian's /usr/bin/python3). The source tree is the
checkout this script lives in. The file being mutated is also saved in
DIR/mutants-restore/ before it is changed, so that even a kill -9 of the
script is undone by its next start.
"""

import argparse
import contextlib
import fcntl
import json
import os
import shutil
import signal
import subprocess
import sys
import time

SOURCE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MUTANTS = os.path.join(SOURCE, "scripts", "mutants.json")


class Stop(Exception):
    """SIGTERM/SIGHUP, turned into an exception so that the finally blocks restore the tree."""


def on_signal(signum, _frame):
    raise Stop(f"signal {signum}")


def load(path):
    with open(path, encoding="utf-8") as f:
        doc = json.load(f)
    seen = set()
    for m in doc["mutants"]:
        for key in ("id", "file", "find", "replace", "breaks", "tests"):
            if key not in m:
                sys.exit(f"mutants: {path}: mutant {m.get('id', '?')} has no \"{key}\"")
        if m["id"] in seen:
            sys.exit(f"mutants: {path}: mutant id {m['id']} appears twice")
        seen.add(m["id"])
        if m["find"] == m["replace"]:
            sys.exit(f"mutants: {path}: mutant {m['id']}: the replacement equals the text")
    return doc


def targets_of(mutant):
    targets = []
    for t in mutant["tests"]:
        for name in [t["gtest"]] if "gtest" in t else t.get("targets", []):
            if name not in targets:
                targets.append(name)
    return targets


def find_binary(build, name):
    for root, _dirs, files in os.walk(build):
        if name in files and "CMakeFiles" not in root:
            path = os.path.join(root, name)
            if os.access(path, os.X_OK):
                return path
    raise FileNotFoundError(f"no executable {name} in {build}")


@contextlib.contextmanager
def build_lock(path):
    if not path:
        yield
        return
    with open(path, "a") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(f, fcntl.LOCK_UN)


def run(command, timeout, log):
    """Returns 'pass', 'fail' or 'timeout'; the output goes to log."""
    log.write(f"$ {' '.join(command)}\n")
    log.flush()
    try:
        proc = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    except OSError as e:
        log.write(f"cannot run: {e}\n")
        return "fail"
    try:
        return "pass" if proc.wait(timeout=timeout) == 0 else "fail"
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        return "timeout"
    except BaseException:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        raise


def build(build_dir, targets, log):
    return run(["cmake", "--build", build_dir, "-j2", "--target", *targets], None, log) == "pass"


def run_tests(build_dir, mutant, timeout, log):
    """'pass' when every named test passed, else the first 'fail' or 'timeout'."""
    for t in mutant["tests"]:
        if "gtest" in t:
            command = [find_binary(build_dir, t["gtest"])]
            if "filter" in t:
                command.append("--gtest_filter=" + t["filter"])
        else:
            command = ["ctest", "--test-dir", build_dir, "-R", t["ctest"], "--no-tests=error", "-j2",
                       "--output-on-failure"]
        outcome = run(command, timeout, log)
        if outcome != "pass":
            return outcome
    return "pass"


def restore_dir(build_dir):
    return os.path.join(build_dir, "mutants-restore")


def write_bytes(path, data):
    # A fresh modification time (newer than the objects built from the mutant), so the next build recompiles.
    tmp = path + ".mutants-tmp"
    with open(tmp, "wb") as f:
        f.write(data)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def undo_leftovers(build_dir):
    """Puts back a file saved by a run that was killed before it could restore it."""
    saved_root = restore_dir(build_dir)
    if not os.path.isdir(saved_root):
        return
    for root, _dirs, files in os.walk(saved_root):
        for name in files:
            saved = os.path.join(root, name)
            rel = os.path.relpath(saved, saved_root)
            with open(saved, "rb") as f:
                data = f.read()
            print(f"mutants: restoring {rel} left mutated by an interrupted run", file=sys.stderr)
            write_bytes(os.path.join(SOURCE, rel), data)
            os.remove(saved)


@contextlib.contextmanager
def mutated(build_dir, rel, original, text):
    saved = os.path.join(restore_dir(build_dir), rel)
    os.makedirs(os.path.dirname(saved), exist_ok=True)
    write_bytes(saved, original)
    path = os.path.join(SOURCE, rel)
    try:
        write_bytes(path, text)
        yield
    finally:
        write_bytes(path, original)
        with open(path, "rb") as f:
            if f.read() != original:
                raise RuntimeError(f"mutants: {rel} could not be restored; the original is in {saved}")
        os.remove(saved)


def dirty_files(files):
    out = subprocess.run(["git", "-C", SOURCE, "status", "--porcelain", "--", *files], capture_output=True,
                         text=True, check=True).stdout
    return [line[3:] for line in out.splitlines() if line.strip()]


def try_mutant(args, m, log):
    """Returns (status, seconds)."""
    start = time.monotonic()
    path = os.path.join(SOURCE, m["file"])
    try:
        with open(path, "rb") as f:
            original = f.read()
    except FileNotFoundError:
        return "not applicable (no file)", time.monotonic() - start
    find, replace = m["find"].encode(), m["replace"].encode()
    count = original.count(find)
    if count != 1:
        return f"not applicable ({count} matches)", time.monotonic() - start
    log.write(f"\n===== {m['id']}: {m['file']}: {m['breaks']}\n")
    with build_lock(args.lock):
        start = time.monotonic()  # the time of the mutant's own work, not of the wait for the lock
        with mutated(args.build, m["file"], original, original.replace(find, replace)):
            if not build(args.build, targets_of(m), log):
                status = "build failed"
            else:
                outcome = run_tests(args.build, m, args.timeout, log)
                status = {"pass": "MISSED", "fail": "caught", "timeout": "caught (timeout)"}[outcome]
    return status, time.monotonic() - start


def table(rows, total_seconds):
    counts = {}
    for _m, status, _s in rows:
        key = status.split(" (")[0]
        counts[key] = counts.get(key, 0) + 1
    lines = ["| id | file | breaks | tests | result | s |", "|---|---|---|---|---|---|"]
    for m, status, seconds in rows:
        tests = "; ".join(t["gtest"] + (" " + t["filter"] if "filter" in t else "") if "gtest" in t
                          else "ctest -R " + t["ctest"] for t in m["tests"])
        tests = tests.replace("|", "\\|")
        lines.append(f"| {m['id']} | {m['file']} | {m['breaks'].replace('|', '/')} | {tests} | "
                     f"{status if status != 'MISSED' else '**MISSED**'} | {seconds:.0f} |")
    summary = ", ".join(f"{v} {k}" for k, v in sorted(counts.items()))
    lines.append("")
    lines.append(f"{len(rows)} mutants: {summary}; {total_seconds / 60:.1f} min.")
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", default=os.path.join(SOURCE, "build"), help="the build folder (default: build)")
    parser.add_argument("--only", help="comma-separated mutant ids, run in that order")
    parser.add_argument("--sample", choices=["ci"], help="the fixed subset CI runs")
    parser.add_argument("--table", help="also write the markdown table to this file")
    parser.add_argument("--lock", help="hold this flock file for each mutant's build and tests")
    parser.add_argument("--timeout", type=float, default=600, help="seconds per test command (default 600)")
    parser.add_argument("--mutants", default=MUTANTS, help=argparse.SUPPRESS)
    parser.add_argument("--log", help="the build and test output (default: BUILD/mutants.log)")
    parser.add_argument("--strict", action="store_true", help="also fail when a mutant no longer applies or builds")
    parser.add_argument("--no-baseline", action="store_true",
                        help="skip running the selected tests on the unmutated tree first")
    parser.add_argument("--no-final-rebuild", action="store_true",
                        help="leave the build folder's programs as the last mutant built them")
    args = parser.parse_args()
    args.build = os.path.abspath(args.build)

    doc = load(args.mutants)
    mutants = doc["mutants"]
    if args.only:
        wanted = args.only.split(",")
        unknown = [w for w in wanted if w not in {m["id"] for m in mutants}]
        if unknown:
            sys.exit(f"mutants: --only: no mutant {', '.join(unknown)}")
        by_id = {m["id"]: m for m in mutants}
        mutants = [by_id[w] for w in dict.fromkeys(wanted)]  # in the order given
    if args.sample:
        mutants = [m for m in mutants if args.sample in m.get("samples", [])]
    if not os.path.isfile(os.path.join(args.build, "CMakeCache.txt")):
        sys.exit(f"mutants: --build {args.build} is not a configured build folder")

    for s in (signal.SIGTERM, signal.SIGHUP):
        signal.signal(s, on_signal)
    undo_leftovers(args.build)
    dirty = dirty_files(sorted({m["file"] for m in mutants}))
    if dirty:
        sys.exit("mutants: refusing to start: uncommitted changes to files the mutants change: " + ", ".join(dirty))

    log_path = args.log or os.path.join(args.build, "mutants.log")
    rows = []
    start = time.monotonic()
    failed = False
    with open(log_path, "w") as log:
        if not args.no_baseline:
            print(f"mutants: baseline: building and running the tests of {len(mutants)} mutants unmutated", flush=True)
            with build_lock(args.lock):
                targets = []
                for m in mutants:
                    targets += [t for t in targets_of(m) if t not in targets]
                if not build(args.build, targets, log):
                    sys.exit(f"mutants: the unmutated tree does not build; see {log_path}")
                done = set()
                for m in mutants:
                    key = json.dumps(m["tests"], sort_keys=True)
                    if key in done:
                        continue
                    done.add(key)
                    if run_tests(args.build, m, args.timeout, log) != "pass":
                        sys.exit(f"mutants: the tests of {m['id']} fail on the unmutated tree; see {log_path}")
        try:
            for i, m in enumerate(mutants, 1):
                status, seconds = try_mutant(args, m, log)
                rows.append((m, status, seconds))
                print(f"mutants: [{i}/{len(mutants)}] {m['id']}: {status} ({seconds:.0f} s)", flush=True)
                if status == "MISSED" or (args.strict and not status.startswith("caught")):
                    failed = True
        except (KeyboardInterrupt, Stop) as e:
            print(f"mutants: stopped ({e or 'Ctrl-C'}); the tree is restored", file=sys.stderr)
            failed = True
        if rows and not args.no_final_rebuild:
            # The build folder's programs were last linked with a mutant: bring them back to the tree.
            with build_lock(args.lock):
                targets = []
                for m, _status, _s in rows:
                    targets += [t for t in targets_of(m) if t not in targets]
                build(args.build, targets, log)
    text = table(rows, time.monotonic() - start)
    print(text)
    if args.table:
        with open(args.table, "w", encoding="utf-8") as f:
            f.write(text)
    if failed:
        print(f"mutants: FAILED (the build and test output: {log_path})", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
