"""The one-line progress report of a running sweep: done, running, failed, ETA."""
import sys
import time


def _clock(seconds):
    s = int(round(seconds))
    return f"{s // 3600}:{s % 3600 // 60:02d}:{s % 60:02d}"


class Progress:
    """Prints `NAME: D/N done, R running, F failed, ETA h:mm:ss` to `stream`:
    rewritten in place on a terminal, one line per change otherwise."""

    def __init__(self, name, total, workers, stream=None):
        self.name, self.total, self.workers = name, total, max(1, workers)
        self.stream = stream or sys.stderr
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.t0 = time.monotonic()
        self.finished_here = 0   # runs finished by this session (for the rate)
        self.last = None

    def line(self, done, running, failed):
        left = self.total - done - failed
        elapsed = time.monotonic() - self.t0
        if left == 0:
            eta = "0:00:00"
        elif self.finished_here:
            eta = _clock(elapsed / self.finished_here * left)
        else:
            eta = "?"
        return f"{self.name}: {done}/{self.total} done, {running} running, {failed} failed, ETA {eta}"

    def show(self, done, running, failed, force=False):
        key = (done, running, failed)
        if key == self.last and not (force and self.tty):
            return
        self.last = key
        text = self.line(done, running, failed)
        if self.tty:
            self.stream.write("\r" + text + "\033[K")
        else:
            self.stream.write(text + "\n")
        self.stream.flush()

    def note(self, text):
        """A message on its own line (a failed run, a warning)."""
        self.stream.write(("\r\033[K" if self.tty else "") + text + "\n")
        self.stream.flush()
        self.last = None

    def close(self):
        if self.tty:
            self.stream.write("\n")
            self.stream.flush()
