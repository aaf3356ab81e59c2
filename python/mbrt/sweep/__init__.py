"""Parameter sweeps and Monte Carlo runs of a compiled model (`mbrt sweep`, docs/sweeps.md)."""
import os
import pathlib

PACKAGE_ROOT = pathlib.Path(__file__).resolve().parents[2]  # holds the package mbrt: python/, or share/mbrt/python


def python_environment():
    """The environment for a python3 that runs this package's modules (-m mbrt.sweep....)."""
    path = os.environ.get("PYTHONPATH")
    return dict(os.environ, PYTHONPATH=str(PACKAGE_ROOT) + (f":{path}" if path else ""))
