"""Progress display of long packbench runs (``progress=True``): a tqdm bar when tqdm is
installed, else a bar drawn the way tqdm draws it, one line on stderr at most every two
seconds (a log file stays readable)."""

import sys
import time

try:
    from tqdm.auto import tqdm as _tqdm
except ImportError:  # tqdm is optional
    _tqdm = None

_LINE_EVERY_S = 2.0
_WIDTH = 20


def _describe(step, phi, values):
    parts = [f"step {step}", f"phi {phi:.6f}"]
    parts += [f"{k} {v:.3g}" for k, v in values.items() if k not in ("fraction", "progress")]
    return "  ".join(parts)


def _clock(seconds):
    m, s = divmod(int(seconds), 60)
    h, m = divmod(m, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m:02d}:{s:02d}"


def text_bar(label, fraction, elapsed, postfix=""):
    """One line as tqdm draws it: ``label:  43%|########6           | 00:03 postfix``."""
    fraction = min(max(fraction, 0.0), 1.0)
    filled = fraction * _WIDTH
    full = int(filled)
    partial = "" if full == _WIDTH else str(int((filled - full) * 10))
    bar = ("#" * full + partial).ljust(_WIDTH)
    line = f"{label}: {fraction * 100:3.0f}%|{bar}| {_clock(elapsed)}"
    return f"{line} {postfix}" if postfix else line


class ProgressDisplay:
    """Shows a method's progress reports (``report``) or counts finished runs (``advance``).

    ``label`` titles the display; ``total`` is the number of runs to count, or None for one
    method's run, whose bar follows the method's progress towards its stopping rule
    (``values["progress"]``), else the fraction of its budget (``values["fraction"]``).
    """

    def __init__(self, label, total=None):
        self.label = label
        self.total = total
        self.count = 0
        self.fraction = 0.0
        self.started = time.monotonic()
        self.last_line = None
        self.postfix = ""
        self.bar = None
        if _tqdm is not None:
            self.bar = _tqdm(total=total if total is not None else 100, desc=label,
                             unit="run" if total is not None else "%",
                             bar_format=None if total is not None else
                             "{desc}: {percentage:3.0f}%|{bar}| {elapsed} {postfix}")

    def _line(self, text, force=False):
        now = time.monotonic()
        if force or self.last_line is None or now - self.last_line >= _LINE_EVERY_S:
            self.last_line = now
            print(text, file=sys.stderr, flush=True)

    def report(self, step, phi, values):
        """One progress report of a method: its step, φ and named quantities."""
        self.postfix = _describe(step, phi, values)
        fraction = values.get("progress", values.get("fraction"))
        if fraction is not None:
            self.fraction = min(max(fraction, 0.0), 1.0)
        if self.bar is None:
            self._line(text_bar(self.label, self.fraction, time.monotonic() - self.started,
                                self.postfix))
            return
        self.bar.n = round(self.fraction * 100, 1)
        self.bar.set_postfix_str(self.postfix, refresh=False)
        self.bar.refresh()

    def advance(self, text):
        """One finished run, described by ``text``."""
        self.count += 1
        if self.bar is None:
            fraction = self.count / self.total if self.total else 1.0
            self._line(text_bar(self.label, fraction, time.monotonic() - self.started,
                                f"{self.count}/{self.total} runs, last {text}"), force=True)
            return
        self.bar.set_postfix_str(text, refresh=False)
        self.bar.update(1)

    def close(self, done=False):
        """Ends the display; ``done`` (the method met its stopping rule) fills the bar."""
        if done:
            self.fraction = 1.0
        if self.bar is None:
            if self.total is None:
                self._line(text_bar(self.label, self.fraction, time.monotonic() - self.started,
                                    self.postfix), force=True)
            return
        if done and self.total is None:
            self.bar.n = 100
            self.bar.refresh()
        self.bar.close()
