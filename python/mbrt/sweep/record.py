"""A sample's result, as journaled and tabled: its index and parameters, its
status and message, its summary fields (the same for every status, missing
values None) and its outputs at the end."""
import math


def finite_or_none(x):
    return x if isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) else None


def make_record(index, params, status, message, fields, summary=None, outputs=None):
    return {"sample": index, "params": params, "status": status, "message": message,
            "summary": {k: finite_or_none((summary or {}).get(k)) for k in fields},
            "outputs": {k: finite_or_none(v) for k, v in (outputs or {}).items()}}


def error_message(text):
    """A program's error message from its stderr: the first line saying error, else the first line (the
    programs print their error before their usage)."""
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    return next((line for line in lines if line.startswith("error")), lines[0] if lines else "")
