"""One Slurm array task of the Slurm executor (slurm.py): runs its chunk of
the job's samples, journaling each result; a requeued task skips the samples
already journaled.

usage: python3 -m mbrt.sweep.slurm_task JOB_FILE JOURNAL_DIR JOB_ID TASK_ID
"""
import pathlib
import pickle
import sys

from .journal import JournalWriter, read_records


def main(job_file, journal_dir, job_id, task_id):
    task, chunks = pickle.loads(pathlib.Path(job_file).read_bytes())
    finished = read_records(journal_dir)
    with JournalWriter(pathlib.Path(journal_dir) / f"slurm-{job_id}-{task_id}.jsonl") as journal:
        for sample in chunks[int(task_id)]:
            if sample[0] not in finished:
                journal.append(task(sample))


if __name__ == "__main__":
    main(*sys.argv[1:])
