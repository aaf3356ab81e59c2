"""`mbrt sweep`: runs one compiled model over many parameter sets and
collects every run into one table (docs/sweeps.md).

    mbrt sweep MODEL.yaml (--grid SPEC | --samples N --distribution SPEC) [--seed S] --out DIR
               [--executor local|dask|slurm] [--workers N] [--scheduler ADDRESS]
               [generation options] ([--t-end T] [--outputs COLS] | --hil [--duration S] [--hil-args A] [--stub-args A])

The program is compiled once (`mbrt build`); each sample runs it with its
parameters as `--set KEY=VALUE`. With --hil, each sample is a closed loop of
the model's `hil` and `stub` programs in a private network namespace, its
parameters their options (stub.drop=0.1: the stub's --drop 0.1). Exit 0 when
every sample finished (whatever its status), 1 when some could not be run (a
rerun resumes them) or the model is invalid, 2 for a bad command line.
"""
import argparse
import collections
import functools
import hashlib
import json
import pathlib
import shlex
import signal
import subprocess
import sys
import tempfile

from .. import _mbrt_executable
from . import executors, slurm, spec
from .journal import JournalWriter, read_records
from .hil_sample import run_hil_sample
from .out_dir import OutDir, OutDirError
from .progress import Progress
from .record import error_message
from .sim_sample import csv_options, run_sim_sample, set_options
from .table import write_csv

EXECUTORS = {"local": executors.run_local, "dask": executors.run_dask, "slurm": slurm.run_slurm}


class UsageError(Exception):
    """A bad command line (exit 2)."""


class RunError(Exception):
    """The model or its program failed before any sample ran (exit 1)."""


def integer(minimum):
    def parse(text):
        try:
            n = int(text)
        except ValueError:
            n = minimum - 1
        if n < minimum:
            raise argparse.ArgumentTypeError(f"expected an integer >= {minimum}, got '{text}'")
        return n
    return parse


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
    p.add_argument("--samples", type=integer(1), metavar="N", help="with --distribution: the number of samples")
    p.add_argument("--seed", type=integer(0), default=0, metavar="S",
                   help="the seed of --distribution's samples and of --hil's fault injection (default 0)")
    p.add_argument("--out", required=True, metavar="DIR", help="results.csv, the journal and sweep.json go here")
    p.add_argument("--executor", choices=sorted(EXECUTORS), default="local")
    p.add_argument("--workers", type=integer(1), metavar="N",
                   help="local: processes at once (default: all cores); dask: LocalCluster workers; "
                        "slurm: array tasks (default: one per sample, at most 100)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="dask: the scheduler of a running cluster (tcp://HOST:PORT)")
    gen = p.add_argument_group("generation options (as mbrt sim)")
    for option in ("--scheme", "--h", "--euler-updates", "--ali3p-projection", "--ali3p-integrator"):
        gen.add_argument(option, metavar="VALUE")
    gen.add_argument("--project-initial", action="store_true")
    gen.add_argument("--no-specialize", nargs="?", const="", metavar="NAME,...")
    p.add_argument("--t-end", type=nonnegative_float, metavar="T", help="run to this time, s (default 1)")
    p.add_argument("--outputs", default="", metavar="COLS",
                   help="columns of mbrt sim's CSV (with --velocities and --reactions) at t_end, comma separated")
    hil = p.add_argument_group("HIL scenario sweeps (keys hil.OPTION, stub.OPTION and the model's parameters, docs/sweeps.md)")
    hil.add_argument("--hil", action="store_true", help="each sample: mbrt hil and mbrt stub in a private network")
    hil.add_argument("--duration", type=nonnegative_float, default=2.0, metavar="S",
                     help="the controller's run time, s (default 2)")
    hil.add_argument("--hil-args", default="", metavar="ARGS", help="options for every sample's hil loop")
    hil.add_argument("--stub-args", default="", metavar="ARGS", help="options for every sample's controller")
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


def build(model, options, program="sim"):
    """The compiled program's path (`mbrt build`)."""
    r = subprocess.run([str(_mbrt_executable(None)), "build", model, "--program", program, *options],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
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
    """Runs the program to t = 0 with the first sample's options: a refused option (exit 2: an unknown key)
    or an unknown output column is the sweep's command line at fault, found before any sample runs. Other
    outcomes are left to the sample's own row."""
    with tempfile.TemporaryDirectory(prefix="mbrt-sweep-") as tmp:
        csv_file = pathlib.Path(tmp) / "t0.csv"
        r = subprocess.run([program, "--t-end", "0", *set_options(params), *csv_options(csv_file)],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if r.returncode == 2:
            raise UsageError(f"the sim program refused the first sample, {' '.join(set_options(params))}: "
                             f"{error_message(r.stderr)}")
        if not csv_file.exists():
            return
        columns = csv_file.read_text().splitlines()[0].split(",")
    for c in outputs:
        if c not in columns:
            raise UsageError(f"--outputs: no column '{c}' in the sim program's CSV; it has {', '.join(columns)}")


class Sweep:
    """What a sweep runs: task (a picklable sample -> record), the output columns, and spec: what a
    resumed sweep must share."""

    def __init__(self, task, outputs, spec):
        self.task, self.outputs, self.spec = task, outputs, spec


def sim_sweep(args, gen, parameter_sets):
    """Builds the sim program and checks it on the first sample."""
    outputs = [c.strip() for c in args.outputs.split(",") if c.strip()]
    t_end = 1.0 if args.t_end is None else args.t_end
    program = build(args.model, gen)
    preflight(program, parameter_sets[0], outputs)
    return Sweep(functools.partial(run_sim_sample, program, ["--t-end", repr(t_end)], outputs), outputs,
                 {"program": pathlib.Path(program).parent.name, "t_end": t_end, "outputs": outputs})


def hil_sweep(args, gen, parameter_sets):
    """Builds the hil and stub programs and checks them on the first sample, for no time."""
    if args.outputs or args.t_end is not None:
        raise UsageError("--t-end and --outputs are sim options; a --hil sweep runs for --duration")
    hil, stub = build(args.model, gen, "hil"), build(args.model, gen, "stub")
    hil_args, stub_args = shlex.split(args.hil_args), shlex.split(args.stub_args)

    r = run_hil_sample(hil, stub, 0.0, args.seed, hil_args, stub_args, (0, parameter_sets[0]))
    if r["status"] == "refused":
        raise UsageError(f"the HIL programs refused the first sample's options: {r['message']}")
    if r["status"] == "error":
        raise RunError(f"cannot run a HIL pair: {r['message']}")
    return Sweep(functools.partial(run_hil_sample, hil, stub, args.duration, args.seed, hil_args, stub_args), [],
                 {"programs": [pathlib.Path(p).parent.name for p in (hil, stub)], "duration": args.duration,
                         "seed": args.seed, "hil_args": hil_args, "stub_args": stub_args})


def run(argv):
    args = parser().parse_args(argv)
    if args.scheduler and args.executor != "dask":
        raise UsageError("--scheduler goes with --executor dask")
    model = pathlib.Path(args.model)
    if not model.is_file():
        raise UsageError(f"MODEL: no file '{args.model}'")
    parameter_sets = samples_of(args)
    gen = generation_options(args)
    sweep = (hil_sweep if args.hil else sim_sweep)(args, gen, parameter_sets)
    out = OutDir(args.out, {
        "model": str(model.resolve()), "model_sha256": hashlib.sha256(model.read_bytes()).hexdigest(),
        "generation": gen, "parameter_sets": len(parameter_sets),
        "parameter_sets_sha256": hashlib.sha256(json.dumps(parameter_sets).encode()).hexdigest(), **sweep.spec})
    finished = read_records(out.journal)
    todo = [(i, p) for i, p in enumerate(parameter_sets) if i not in finished]
    failed = {}
    if todo:
        progress = Progress(len(parameter_sets), len(parameter_sets) - len(todo))
        with JournalWriter(out.journal / "driver.jsonl") as journal:
            def on_result(record):
                journal.append(record)
                progress.finished(record)

            failed = EXECUTORS[args.executor](sweep.task, todo, on_result, workers=args.workers,
                                              scheduler=args.scheduler, out_dir=out.path)
    records = list(read_records(out.journal).values())
    write_csv(records, sweep.outputs, out.table)
    statuses = collections.Counter(r["status"] for r in records)
    print(json.dumps({"samples": len(parameter_sets), "finished": len(records), "status": dict(sorted(statuses.items())),
                      "table": str(out.table)}))
    if failed:
        first = min(failed)
        print(f"error: {len(failed)} samples could not be run (sample {first}: {failed[first]}); "
              "run the same command again to resume them", file=sys.stderr)
        return 1
    return 0


def _terminated(signum, frame):
    raise SystemExit(128 + signum)  # unwinds like Ctrl-C: no more samples start, a Slurm job is cancelled


def main(argv=None):
    signal.signal(signal.SIGTERM, _terminated)
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
