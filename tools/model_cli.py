"""The command line the model writers share: N, and --name to rename the model."""
import argparse
import sys


def run(doc, model, name_pattern, what):
    """Parse `N [--name NAME]` and print model(N, name); name_pattern % N is the default name."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("n", type=int, help="%s (N >= 1)" % what)
    parser.add_argument("--name", help="model name (default %s)" % name_pattern.replace("%d", "N"))
    args = parser.parse_args()
    if args.n < 1:
        parser.error("N must be at least 1")
    sys.stdout.write(model(args.n, args.name or name_pattern % args.n))
