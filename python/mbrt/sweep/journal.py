"""The sweep's journal: one JSON line per finished sample, in files under
OUT/journal/ (the driver's, and one per Slurm array task). A line is written
whole with one write(2) and made durable with fsync before the sample counts
as finished; a line cut short by a crash is dropped on reading (and trimmed
before the next append), so the sample runs again. Reading dedupes by sample
index: a result is never counted twice.
"""
import json
import os
import pathlib


def _complete_lines(path):
    """The complete lines of path, and the byte length they take."""
    data = path.read_bytes()
    end = data.rfind(b"\n") + 1
    return data[:end].decode().splitlines(), end


def read_records(directory):
    """Every finished sample's record under directory, by sample index (the first written wins)."""
    records = {}
    for path in sorted(pathlib.Path(directory).glob("*.jsonl")):
        for line in _complete_lines(path)[0]:
            try:
                r = json.loads(line)
            except ValueError:
                continue  # not a line this journal wrote whole
            records.setdefault(r["sample"], r)
    return records


class JournalWriter:
    """Appends records to one journal file, durably."""

    def __init__(self, path):
        self.path = pathlib.Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.fd = os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_APPEND, 0o644)
        os.ftruncate(self.fd, _complete_lines(self.path)[1])  # a line cut short by a crash

    def append(self, record):
        os.write(self.fd, (json.dumps(record, allow_nan=False) + "\n").encode())
        os.fsync(self.fd)

    def close(self):
        os.close(self.fd)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
