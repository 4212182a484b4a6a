"""Progress display of long packbench runs (``progress=True``): a tqdm bar when tqdm is
installed, else one line on stderr at most every two seconds."""

import sys
import time

try:
    from tqdm.auto import tqdm as _tqdm
except ImportError:  # tqdm is optional
    _tqdm = None

_LINE_EVERY_S = 2.0


def _describe(step, phi, values):
    parts = [f"step {step}", f"phi {phi:.6f}"]
    parts += [f"{k} {v:.3g}" for k, v in values.items() if k != "fraction"]
    return "  ".join(parts)


class ProgressDisplay:
    """Shows a method's progress reports (``report``) or counts finished runs (``advance``).

    ``label`` titles the display; ``total`` is the number of runs to count, or None for one
    method's run, whose bar follows the fraction of its budget when the method reports it.
    """

    def __init__(self, label, total=None):
        self.label = label
        self.total = total
        self.count = 0
        self.last_line = 0.0
        self.bar = None
        if _tqdm is not None:
            self.bar = _tqdm(total=total if total is not None else 1.0, desc=label,
                             unit="run" if total is not None else "",
                             bar_format=None if total is not None else
                             "{desc}: {percentage:3.0f}%|{bar}| {elapsed} {postfix}")

    def _line(self, text, force=False):
        now = time.monotonic()
        if force or now - self.last_line >= _LINE_EVERY_S:
            self.last_line = now
            print(f"{self.label}: {text}", file=sys.stderr, flush=True)

    def report(self, step, phi, values):
        """One progress report of a method: its step, φ and named quantities."""
        text = _describe(step, phi, values)
        if self.bar is None:
            self._line(text)
            return
        fraction = values.get("fraction")
        if fraction is not None:
            self.bar.n = min(max(fraction, 0.0), 1.0)
        self.bar.set_postfix_str(text, refresh=False)
        self.bar.refresh()

    def advance(self, text):
        """One finished run, described by ``text``."""
        self.count += 1
        if self.bar is None:
            self._line(f"run {self.count}/{self.total}: {text}", force=True)
            return
        self.bar.set_postfix_str(text, refresh=False)
        self.bar.update(1)

    def close(self):
        """Removes the bar."""
        if self.bar is not None:
            self.bar.close()
