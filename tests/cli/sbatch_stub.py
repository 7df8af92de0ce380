#!/usr/bin/python3
"""A stand-in for Slurm's sbatch (tests/cli/sweep_slurm_hostile.sh): appends its
arguments and the script's #SBATCH directives, parsed as sbatch parses them
(src/sbatch/opt.c: a line each, up to the first command; double or single
quotes group, a backslash escapes, an unquoted # ends the line), to
$SBATCH_STUB_LOG as JSON lines; then runs the script (an array's first and
last task) and prints a job id as --parsable does."""
import json, os, re, subprocess, sys


def directives(text):
    args = []
    for line in text.split("\n")[1:]:
        if not line.startswith("#SBATCH"):
            if line.strip() and not line.lstrip().startswith("#"):
                break
            continue
        if "hetjob" in line.lower() or "packjob" in line.lower():
            args.append("<hetjob separator>")
        rest, i = line[len("#SBATCH"):], 0
        while True:
            while i < len(rest) and rest[i].isspace():
                i += 1
            if i >= len(rest):
                break
            arg, quote, escape = "", "", False
            while i < len(rest) and (quote or not rest[i].isspace()):
                c = rest[i]
                i += 1
                if escape:
                    escape = False
                elif c == "\\":
                    escape = True
                    continue
                elif quote:
                    if c == quote:
                        quote = ""
                        continue
                elif c in "\"'":
                    quote = c
                    continue
                elif c == "#":
                    i = len(rest)
                    break
                arg += c
            if quote:
                args.append("<unmatched quote>")
            if arg:
                args.append(arg)
    return args


script = sys.argv[-1]
with open(script, encoding="utf-8", errors="surrogateescape") as f:
    found = directives(f.read())
runs = []
array = [a for a in found if a.startswith("--array=")]
tasks = [None]
if array:
    m = re.fullmatch(r"--array=0-([0-9]+)", array[-1])
    tasks = ["0", m.group(1)] if m else ["<bad array>"]
for task in tasks:
    env = dict(os.environ)
    if task is not None:
        env["SLURM_ARRAY_TASK_ID"] = task
    code = subprocess.run([script], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode
    runs.append({"task": task, "exit": code})
with open(os.environ["SBATCH_STUB_LOG"], "a") as log:
    log.write(json.dumps({"argv": sys.argv[1:], "directives": found, "runs": runs}) + "\n")
print("4242;cluster" if "--parsable" in sys.argv else "Submitted batch job 4242")
