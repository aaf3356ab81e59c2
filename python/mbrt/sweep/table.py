"""The results table: one row per sample in index order, written as CSV
(floats at full precision, empty where a value is missing or not finite).

Columns: sample, the parameters, status, message, the summary's fields
(sim_sample.SUMMARY_FIELDS) or the HIL reports' (hil_sample.REPORT_FIELDS),
then the chosen outputs at t_end."""
import csv
import os


def row(r, outputs):
    values = [r["sample"], *r["params"].values(), r["status"], r["message"], *r["summary"].values()]
    return values + [r["outputs"].get(c) for c in outputs]


def write_csv(records, outputs, path):
    """Writes the records (sorted by sample) to path, replacing it atomically."""
    records = sorted(records, key=lambda r: r["sample"])
    tmp = f"{path}.tmp{os.getpid()}"
    with open(tmp, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["sample", *records[0]["params"], "status", "message", *records[0]["summary"], *outputs]
                   if records else ["sample"])
        for r in records:
            w.writerow(["" if v is None else repr(v) if isinstance(v, float) else v for v in row(r, outputs)])
    os.replace(tmp, path)
