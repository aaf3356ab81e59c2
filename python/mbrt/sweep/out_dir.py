"""The sweep's out directory: sweep.json (what the sweep is), the journal
(journal.py), results.csv, and a lock that keeps a second driver out while one
runs. A rerun resumes only the same sweep: same model file and program, same
run options, same parameter sets and outputs."""
import fcntl
import json
import pathlib


class OutDirError(Exception):
    """The directory holds another sweep or is in use; the message says which."""


class OutDir:
    def __init__(self, path, spec):
        self.path = pathlib.Path(path)
        self.path.mkdir(parents=True, exist_ok=True)
        self.journal = self.path / "journal"
        self.table = self.path / "results.csv"
        self._lock = open(self.path / "lock", "w")
        try:
            fcntl.flock(self._lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise OutDirError(f"--out {self.path}: another sweep is running in this directory") from None
        spec_file = self.path / "sweep.json"
        if spec_file.exists():
            previous = json.loads(spec_file.read_text())
            differ = sorted(k for k in spec.keys() | previous.keys() if spec.get(k) != previous.get(k))
            if differ:
                raise OutDirError(f"--out {self.path} holds another sweep (it differs in {', '.join(differ)}); "
                                  "give a new --out directory, or the same options to resume it")
        else:
            spec_file.write_text(json.dumps(spec, indent=1) + "\n")
