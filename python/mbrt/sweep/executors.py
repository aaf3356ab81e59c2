"""Where the samples run, behind `--executor`: each takes task (a picklable
callable: sample -> record), the samples (index, params) to run and
on_result(record), called in the driver as each finishes. Each returns the
failures that are not the run's own (a lost worker, a cancelled job) as
{index: message}; those samples are left unfinished for a rerun.

- local: concurrent.futures threads, each waiting on its sample's process;
- dask: a Dask distributed cluster (a LocalCluster unless a scheduler address
  is given), one task per sample;
- slurm: slurm.run, a job array (slurm.py).
"""
import concurrent.futures
import contextlib
import os


def run_local(task, samples, on_result, workers=None, **_):
    failed = {}
    pool = concurrent.futures.ThreadPoolExecutor(workers or os.cpu_count())
    try:
        futures = {pool.submit(task, s): s[0] for s in samples}
        for f in concurrent.futures.as_completed(futures):
            if f.exception():
                failed[futures[f]] = repr(f.exception())
            else:
                on_result(f.result())
    finally:  # interrupted: start nothing more, wait for the samples running
        pool.shutdown(cancel_futures=True)
    return failed


def run_dask(task, samples, on_result, workers=None, scheduler=None, **_):
    import distributed  # Debian: python3-distributed

    failed = {}
    with contextlib.ExitStack() as stack:
        cluster = scheduler or stack.enter_context(distributed.LocalCluster(
            n_workers=workers or os.cpu_count(), threads_per_worker=1, dashboard_address=None))
        client = stack.enter_context(distributed.Client(cluster))
        futures = client.map(task, samples, pure=False)
        index = {f.key: s[0] for f, s in zip(futures, samples)}
        for f in distributed.as_completed(futures):
            if f.status == "finished":
                on_result(f.result())
            else:
                failed[index[f.key]] = repr(f.exception())
            f.release()
    return failed
