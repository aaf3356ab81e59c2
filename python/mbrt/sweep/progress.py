"""Progress on stderr: samples done of the total, how many did not end ok,
the rate and the time left, at most once a second and at the end."""
import sys
import time


class Progress:
    def __init__(self, total, done):
        self.total, self.done, self.resumed, self.not_ok = total, done, done, 0
        self.started = self.last = time.monotonic()
        if done:
            print(f"sweep: resuming, {done} of {total} samples already finished", file=sys.stderr)

    def finished(self, record):
        self.done += 1
        self.not_ok += record["status"] != "ok"
        now = time.monotonic()
        if now - self.last >= 1.0 or self.done == self.total:
            self.last = now
            rate = (self.done - self.resumed) / max(now - self.started, 1e-9)
            eta = (self.total - self.done) / rate if rate > 0 else float("inf")
            print(f"sweep: {self.done}/{self.total} samples ({self.not_ok} not ok), {rate:.3g}/s, ETA {eta:.0f} s",
                  file=sys.stderr, flush=True)
