"""The Slurm executor: one job array (`sbatch --array`), each array task
running a chunk of the samples (slurm_task.py) and journaling each result in
its own file under OUT/journal/. The driver polls the journal, passing
on results as they appear, until every sample has one or the job has left
the queue (`squeue`).

The out directory, the compiled program and this package must be on a file
system the compute nodes share, at the same paths. Partition, account and
time limit come from Slurm's own environment (SBATCH_PARTITION,
SBATCH_ACCOUNT, SBATCH_TIMELIMIT, ...).
"""
import pathlib
import pickle
import shlex
import subprocess
import sys
import time
import uuid

from . import PACKAGE_ROOT
from .journal import read_records

_POLL_S = 0.5


def _script(job_file, journal_dir):
    command = [sys.executable, "-m", "mbrt.sweep.slurm_task", str(job_file), str(journal_dir)]
    return ("#!/bin/sh\n"
            f"export PYTHONPATH={shlex.quote(str(PACKAGE_ROOT))}${{PYTHONPATH:+:$PYTHONPATH}}\n"
            f'exec {shlex.join(command)} "$SLURM_ARRAY_JOB_ID" "$SLURM_ARRAY_TASK_ID"\n')


def _in_queue(job):
    r = subprocess.run(["squeue", "-h", "-j", job, "-o", "%i"], capture_output=True, text=True)
    return r.returncode == 0 and r.stdout.strip() != ""


def run_slurm(task, samples, on_result, out_dir, workers=None, **_):
    """workers: the number of array tasks (default: one per sample, at most 100)."""
    count = min(len(samples), workers or 100)
    slurm_dir, journal_dir = pathlib.Path(out_dir) / "slurm", pathlib.Path(out_dir) / "journal"
    slurm_dir.mkdir(parents=True, exist_ok=True)
    job_file = slurm_dir / f"job-{uuid.uuid4().hex}.pickle"
    job_file.write_bytes(pickle.dumps((task, [samples[i::count] for i in range(count)])))
    script = slurm_dir / "task.sh"
    script.write_text(_script(job_file, journal_dir))
    r = subprocess.run(["sbatch", "--parsable", f"--array=0-{count - 1}", "--job-name=mbrt-sweep",
                        f"--output={slurm_dir}/%A_%a.log", str(script)], capture_output=True, text=True)
    if r.returncode != 0:
        return {s[0]: f"sbatch failed (exit {r.returncode}): {r.stderr.strip()}" for s in samples}
    job = r.stdout.strip().split(";")[0]
    pending = {s[0] for s in samples}

    def collect():
        for index, record in read_records(journal_dir).items():
            if index in pending:
                pending.discard(index)
                on_result(record)

    # Done when every sample is journaled, or when the job has left the queue without some.
    try:
        while pending and _in_queue(job):
            time.sleep(_POLL_S)
            collect()
    except BaseException:  # interrupted: the job must not run on beside a rerun
        subprocess.run(["scancel", job])
        raise
    collect()
    job_file.unlink()
    return {index: f"no result from Slurm job {job} (task logs in {slurm_dir})" for index in pending}
