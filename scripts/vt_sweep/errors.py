"""The one error type of the sweep tools: a dotted path and a reason."""


class SweepError(Exception):
    """Bad sweep input, reported on one line as `path: reason`."""

    def __init__(self, path, reason):
        super().__init__(f"{path}: {reason}" if path else reason)
        self.path = path
        self.reason = reason
