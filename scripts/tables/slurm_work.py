#!/usr/bin/env python3
"""The "Work per job" table of docs/BENCHMARKS.md (Slurm): the CPU time of each job script of
examples/slurm/ when its packbench command runs outside Slurm, one core, one array task at a
time.

Usage:
  scripts/tables/slurm_work.py [--packbench BIN] [--out DIR]

BIN defaults to $PACKBENCH, else target/release/packbench. For each `*.sbatch`, the script reads
the packbench command of its last branch (the first start of a requeued job; continuation lines
joined, `exec` dropped), and runs it once per task of its `#SBATCH --array` (SLURM_ARRAY_TASK_ID
set, SLURM_CPUS_PER_TASK=1) in DIR/JOB, under GNU time (CPU = user + system, peak resident
memory). Runs, collisions and φ come from what the command wrote (runs.json of a compare, the
JSON sidecar of a pack). Without Slurm no time limit stops a task, so these are the whole work.
"""

import argparse
import json
import os
import re
import shlex
import shutil
from pathlib import Path

from common import run_timed

SLURM = Path(__file__).resolve().parents[2] / "examples" / "slurm"


def job_command(text):
    """The packbench command the job runs first (its last `packbench …` line, joined)."""
    joined = re.sub(r"\\\n\s*", " ", text)
    lines = [l.strip() for l in joined.splitlines() if re.match(r"\s*(exec\s+)?packbench\s", l)]
    return shlex.split(lines[-1].removeprefix("exec").strip())


def array_tasks(text):
    """The task ids of `#SBATCH --array=A-B` (or [None] for a job that is no array)."""
    m = re.search(r"#SBATCH --array=(\d+)-(\d+)", text)
    return list(range(int(m.group(1)), int(m.group(2)) + 1)) if m else [None]


def summary(folder):
    """(runs, steps summed) of what a task wrote in `folder`."""
    runs = []
    for path in folder.rglob("runs.json"):
        runs += json.loads(path.read_text())["runs"]
    for path in folder.glob("*.json"):
        if path.name != "runs.json" and not path.name.endswith("checkpoint.json"):
            record = json.loads(path.read_text())
            if "metrics" in record and "steps" in record:
                runs.append(record)
    return len(runs), sum(r.get("steps") or 0 for r in runs)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--packbench", default=os.environ.get("PACKBENCH", "target/release/packbench"))
    ap.add_argument("--out", type=Path, default=Path("packbench-tables/slurm-work"))
    a = ap.parse_args()
    pb = str(Path(a.packbench).resolve())
    print("| job script | task | command | runs | steps (collisions for mls) | CPU s | peak RSS |")
    print("|---|---|---|---|---|---|---|")
    for job in sorted(SLURM.glob("*.sbatch")):
        text = job.read_text()
        cmd = job_command(text)
        for k, task in enumerate(array_tasks(text)):
            folder = a.out / job.stem / str(task or 0)
            shutil.rmtree(folder, ignore_errors=True)
            folder.mkdir(parents=True)
            env = dict(os.environ, SLURM_CPUS_PER_TASK="1", RAYON_NUM_THREADS="1")
            if task is not None:
                env["SLURM_ARRAY_TASK_ID"] = str(task)
            args = [x.replace("$SLURM_ARRAY_TASK_ID", str(task)) for x in cmd[1:]]
            cwd = os.getcwd()
            os.chdir(folder)
            try:
                _, _, cpu, rss = run_timed([pb] + args + ["--quiet"] * ("--verbose" not in args),
                                           Path("time.txt"), env)
            finally:
                os.chdir(cwd)
            n, steps = summary(folder)
            shown = "`" + " ".join(cmd) + "`" if k == 0 else "the same"
            print(f"| `{job.name}` | {task or '–'} | {shown} | {n} | {steps:,} | {cpu:.2f} "
                  f"| {rss / 1024:.0f} MB |", flush=True)


if __name__ == "__main__":
    main()
