"""`mbrt sweep`: runs one compiled model over many parameter sets and
collects every run into one table (docs/sweeps.md).

    mbrt sweep MODEL.yaml (--grid SPEC | --samples N --distribution SPEC [--seed S]) --out DIR
               [--executor local|dask|slurm] [--workers N] [--scheduler ADDRESS]
               [generation options] [--t-end T] [--outputs COLS]

The program is compiled once (`mbrt build`); each sample runs it with its
parameters as `--set KEY=VALUE`. Exit 0 when every sample finished (whatever
its status), 1 when some could not be run (a rerun resumes them) or the model
is invalid, 2 for a bad command line.
"""
import argparse
import collections
import functools
import hashlib
import json
import pathlib
import subprocess
import sys
import tempfile

from .. import _mbrt_executable
from . import executors, slurm, spec
from .journal import JournalWriter, read_records
from .out_dir import OutDir, OutDirError
from .progress import Progress
from .sim_sample import csv_options, run_sim_sample, set_options
from .table import write_csv

EXECUTORS = {"local": executors.run_local, "dask": executors.run_dask, "slurm": slurm.run_slurm}


class UsageError(Exception):
    """A bad command line (exit 2)."""


class RunError(Exception):
    """The model or its program failed before any sample ran (exit 1)."""


def positive_int(text):
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise argparse.ArgumentTypeError(f"expected an integer >= 1, got '{text}'")
    return n


def nonnegative_float(text):
    try:
        x = float(text)
    except ValueError:
        x = -1.0
    if not x >= 0 or x == float("inf"):
        raise argparse.ArgumentTypeError(f"expected a finite number >= 0, got '{text}'")
    return x


def parser():
    p = argparse.ArgumentParser(prog="mbrt sweep", description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("model", metavar="MODEL.yaml")
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--grid", metavar="SPEC", help="KEY=START:STOP:COUNT or KEY=V1,V2,..., comma separated")
    what.add_argument("--distribution", metavar="SPEC",
                      help="KEY=uniform(LOW,HIGH), normal(MEAN,SD), lognormal(MU,SIGMA) or a number, comma separated")
    p.add_argument("--samples", type=positive_int, metavar="N", help="with --distribution: the number of samples")
    p.add_argument("--seed", type=int, default=0, metavar="S", help="with --distribution: the seed (default 0)")
    p.add_argument("--out", required=True, metavar="DIR", help="results.csv, the journal and sweep.json go here")
    p.add_argument("--executor", choices=sorted(EXECUTORS), default="local")
    p.add_argument("--workers", type=positive_int, metavar="N",
                   help="local: processes at once (default: all cores); dask: LocalCluster workers; "
                        "slurm: array tasks (default: one per sample, at most 100)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="dask: the scheduler of a running cluster (tcp://HOST:PORT)")
    gen = p.add_argument_group("generation options (as mbrt sim)")
    for option in ("--scheme", "--h", "--euler-updates", "--ali3p-projection", "--ali3p-integrator"):
        gen.add_argument(option, metavar="VALUE")
    gen.add_argument("--project-initial", action="store_true")
    gen.add_argument("--no-specialize", nargs="?", const="", metavar="NAME,...")
    p.add_argument("--t-end", type=nonnegative_float, default=1.0, metavar="T", help="run to this time, s (default 1)")
    p.add_argument("--outputs", default="", metavar="COLS",
                   help="columns of mbrt sim's CSV (with --velocities and --reactions) at t_end, comma separated")
    return p


def generation_options(args):
    out = []
    for option in ("scheme", "h", "euler_updates", "ali3p_projection", "ali3p_integrator"):
        if getattr(args, option) is not None:
            out += ["--" + option.replace("_", "-"), getattr(args, option)]
    if args.project_initial:
        out.append("--project-initial")
    if args.no_specialize is not None:
        out.append("--no-specialize" + (f"={args.no_specialize}" if args.no_specialize else ""))
    return out


def build(model, options):
    """The compiled sim program's path (`mbrt build`)."""
    r = subprocess.run([str(_mbrt_executable(None)), "build", model, *options], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True)
    message = r.stderr.split("\n\n")[0].strip()
    if r.returncode == 2:
        raise UsageError(message)
    if r.returncode != 0:
        raise RunError(message)
    return r.stdout.strip().splitlines()[-1]


def samples_of(args):
    try:
        if args.grid is not None:
            if args.samples is not None:
                raise UsageError("--samples goes with --distribution, not --grid")
            return spec.grid(args.grid)
        if args.samples is None:
            raise UsageError("--distribution needs --samples N")
        return spec.monte_carlo(args.distribution, args.samples, args.seed)
    except spec.SpecError as e:
        raise UsageError(str(e)) from None


def preflight(program, params, outputs):
    """Runs the program to t = 0 with a sample's options: a refused option (exit 2: an unknown key) or an
    unknown output column is the sweep's command line at fault, found before any sample runs. Other
    outcomes are left to the sample's own row."""
    with tempfile.TemporaryDirectory(prefix="mbrt-sweep-") as tmp:
        csv_file = pathlib.Path(tmp) / "t0.csv"
        r = subprocess.run([program, "--t-end", "0", *set_options(params), *csv_options(csv_file)],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if r.returncode == 2:
            raise UsageError(f"the sim program refused {' '.join(set_options(params))}: {r.stderr.strip()}")
        if not csv_file.exists():
            return
        columns = csv_file.read_text().splitlines()[0].split(",")
    for c in outputs:
        if c not in columns:
            raise UsageError(f"--outputs: no column '{c}' in the sim program's CSV; it has {', '.join(columns)}")


def sweep_spec(args, program, gen, parameter_sets, outputs):
    """What a resumed sweep must share with the one in the out directory."""
    model = pathlib.Path(args.model).resolve()
    return {"model": str(model), "model_sha256": hashlib.sha256(model.read_bytes()).hexdigest(),
            "program": pathlib.Path(program).parent.name, "generation": gen, "t_end": args.t_end,
            "parameter_sets": len(parameter_sets),
            "parameter_sets_sha256": hashlib.sha256(json.dumps(parameter_sets).encode()).hexdigest(),
            "outputs": outputs, "spec": args.grid or f"{args.distribution} samples {args.samples} seed {args.seed}"}


def run(argv):
    args = parser().parse_args(argv)
    if args.scheduler and args.executor != "dask":
        raise UsageError("--scheduler goes with --executor dask")
    if not pathlib.Path(args.model).is_file():
        raise UsageError(f"MODEL: no file '{args.model}'")
    parameter_sets = samples_of(args)
    outputs = [c.strip() for c in args.outputs.split(",") if c.strip()]
    gen = generation_options(args)
    program = build(args.model, gen)
    out = OutDir(args.out, sweep_spec(args, program, gen, parameter_sets, outputs))
    finished = read_records(out.journal)
    todo = [(i, p) for i, p in enumerate(parameter_sets) if i not in finished]
    failed = {}
    if todo:
        preflight(program, todo[0][1], outputs)
        progress = Progress(len(parameter_sets), len(parameter_sets) - len(todo))
        task = functools.partial(run_sim_sample, program, ["--t-end", repr(args.t_end)], outputs)
        with JournalWriter(out.journal / "driver.jsonl") as journal:
            def on_result(record):
                journal.append(record)
                progress.finished(record)

            failed = EXECUTORS[args.executor](task, todo, on_result, workers=args.workers,
                                              scheduler=args.scheduler, out_dir=out.path)
    records = list(read_records(out.journal).values())
    write_csv(records, outputs, out.table)
    statuses = collections.Counter(r["status"] for r in records)
    print(json.dumps({"samples": len(parameter_sets), "finished": len(records), "status": dict(sorted(statuses.items())),
                      "table": str(out.table)}))
    if failed:
        first = min(failed)
        print(f"error: {len(failed)} samples could not be run (sample {first}: {failed[first]}); "
              "run the same command again to resume them", file=sys.stderr)
        return 1
    return 0


def main(argv=None):
    try:
        return run(sys.argv[1:] if argv is None else argv)
    except (UsageError, OutDirError) as e:
        print(f"mbrt sweep: error: {e}", file=sys.stderr)
        return 2
    except RunError as e:
        print(f"mbrt sweep: error: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
