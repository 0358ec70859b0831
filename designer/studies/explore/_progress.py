"""Live progress of a study: the incremental front of the feasible trials and its hypervolume
(:class:`_FrontTracker`), and the progress bar on stderr (:class:`_Progress`, rich).
"""

from __future__ import annotations

import time

import numpy as np

from designer.studies.front import hypervolume_2d


class _FrontTracker:
    """Incremental non-dominated set of feasible (F_turn, P) points and its hypervolume."""

    def __init__(self, reference):
        self.reference = np.asarray(reference, float)
        self.points = np.empty((0, 2))

    def add(self, values) -> None:
        p = np.asarray(values, float)
        if len(self.points) and np.any(np.all(self.points <= p, axis=1)):
            return
        keep = ~np.all(p <= self.points, axis=1)
        self.points = np.vstack([self.points[keep], p])

    @property
    def hypervolume(self) -> float:
        return hypervolume_2d(self.points, self.reference)


class _Progress:
    def __init__(self, total: int, enabled: bool, initial: int = 0):
        self.enabled = enabled
        self.total = total
        self.initial = initial
        self._last = 0.0

    def __enter__(self):
        if self.enabled:
            from rich.console import Console

            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                Progress,
                TextColumn,
                TimeElapsedColumn,
                TimeRemainingColumn,
            )

            console = Console(stderr=True)
            if not console.is_terminal:  # a log file or a pipe: no bar (rich would print its last state at the end)
                self.enabled = False
                return self
            self.progress = Progress(
                TextColumn("explore"),
                BarColumn(),
                MofNCompleteColumn(),
                TextColumn("front {task.fields[front]:>3}  HV {task.fields[hv]:.5g} N²"),
                TimeElapsedColumn(),
                TimeRemainingColumn(),
                console=console,
                transient=False,
            )
            self.progress.__enter__()
            self.task = self.progress.add_task("explore", total=self.total, completed=self.initial, front=0, hv=0.0)
        return self

    def update(self, complete: int, tracker: _FrontTracker) -> None:
        if not self.enabled:
            return
        now = time.perf_counter()
        if now - self._last < 0.1 and complete < self.total:
            return
        self._last = now
        self.progress.update(self.task, completed=complete, front=len(tracker.points), hv=tracker.hypervolume)

    def __exit__(self, *exc):
        if self.enabled:
            if isinstance(exc[1], KeyboardInterrupt):  # interrupted: the bar goes, "interrupted" is the one line
                self.progress.live.transient = True
            self.progress.__exit__(*exc)
        return False
