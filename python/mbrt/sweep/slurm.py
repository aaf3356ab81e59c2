"""The Slurm executor: one job array (`sbatch --array`), each array task
running a chunk of the samples (slurm_task.py) and journaling each result in
its own file under OUT/journal/. The driver waits for the job (`sbatch
--wait`), passing on results as they appear in the journal.

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


def _script(job_file, journal_dir):
    command = [sys.executable, "-m", "mbrt.sweep.slurm_task", str(job_file), str(journal_dir)]
    return ("#!/bin/sh\n"
            f"export PYTHONPATH={shlex.quote(str(PACKAGE_ROOT))}${{PYTHONPATH:+:$PYTHONPATH}}\n"
            f'exec {shlex.join(command)} "$SLURM_ARRAY_JOB_ID" "$SLURM_ARRAY_TASK_ID"\n')


def run_slurm(task, samples, on_result, out_dir, workers=None, **_):
    """workers: the number of array tasks (default: one per sample, at most 100)."""
    count = min(len(samples), workers or 100)
    slurm_dir, journal_dir = pathlib.Path(out_dir) / "slurm", pathlib.Path(out_dir) / "journal"
    slurm_dir.mkdir(parents=True, exist_ok=True)
    job_file = slurm_dir / f"job-{uuid.uuid4().hex}.pickle"
    job_file.write_bytes(pickle.dumps((task, [samples[i::count] for i in range(count)])))
    script = slurm_dir / "task.sh"
    script.write_text(_script(job_file, journal_dir))
    sbatch = subprocess.Popen(["sbatch", "--parsable", "--wait", f"--array=0-{count - 1}", "--job-name=mbrt-sweep",
                               f"--output={slurm_dir}/%A_%a.log", str(script)],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    job = sbatch.stdout.readline().strip().split(";")[0]  # printed at submission; --wait then waits
    pending = {s[0] for s in samples}

    def collect():
        for index, record in read_records(journal_dir).items():
            if index in pending:
                pending.discard(index)
                on_result(record)

    try:
        while sbatch.poll() is None:
            time.sleep(1.0)
            collect()
    except BaseException:  # interrupted: the job must not run on beside a rerun
        if job:
            subprocess.run(["scancel", job])
        raise
    err = sbatch.communicate()[1]
    collect()
    job_file.unlink()
    why = f"no result from Slurm job {job or '(not submitted)'} (sbatch exit {sbatch.returncode}"
    why += f": {err.strip()}" if err.strip() else f"; task logs in {slurm_dir}"
    return {index: why + ")" for index in pending}
