"""A second process for the studio: it computes one front while the server's process computes the rest.

A change of the target speed (or the load, the sill, a bound) moves both continuous fronts and the
recommendation.  They are independent, and CasADi's solvers cannot run in two threads of one process, so
:func:`designer.studio.view.compute_fronts` hands the risk-bounded front (the costliest part) to this process
(its own compiled solvers, kept warm like the server's) and computes the recommendation and the nominal front
meanwhile: on two cores the change then takes about the longer of the two instead of their sum.

Started by ``designer studio`` (:func:`start`), stopped with it (:func:`stop`); without it (the API, the tests)
everything is computed in the calling process, with the same results: the helper runs the same
:func:`designer.pareto_front` on the same problem.  A helper that fails or dies is dropped and its work done
in the calling process.
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import time
import warnings
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool

import numpy as np

from designer.children import bind_to_parent

_POOL: ProcessPoolExecutor | None = None

KNEE = False
"""Whether the studio's fronts (here and in the view) search their knee: nothing of the studio reads it (the chart
marks the recommendation; "Write report" computes its own report as ``designer pareto`` does), and the search is
half a front's time."""


def _begin(parent: int) -> None:
    """The helper's start.  Ctrl-C reaches every process of the terminal: the server stops, and stops this one.
    A server that is killed cannot stop it: the helper ends with its parent ``parent``, however the parent ends
    (:func:`designer.children.bind_to_parent`)."""
    bind_to_parent(parent)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    expand_batches()


def expand_batches() -> None:
    """Batches expanded in this process (:attr:`designer.solvers.nlp.CasterNLP.EXPAND`): less CPU a change."""
    from designer.solvers.nlp import CasterNLP  # casadi: loaded with the solver's warm-up

    CasterNLP.EXPAND = True


def front_job(problem):
    """(designer.pareto_front(problem), its CPU seconds) in the helper, warnings off as in the studio's view; its
    knee searched only if :data:`KNEE`."""
    from designer.studies.front import pareto_front  # casadi: loaded in the helper when its first job runs

    c0 = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with np.errstate(all="ignore"):
            front = pareto_front(problem, knee=KNEE)
    return front, time.process_time() - c0


def start(warm=None) -> None:
    """Start the helper process (once); ``warm``: a problem whose front it computes at once (its solvers
    compiled before the first change)."""
    global _POOL
    if _POOL is None:
        context = multiprocessing.get_context("spawn")  # a fresh interpreter: the server has threads
        _POOL = ProcessPoolExecutor(max_workers=1, mp_context=context, initializer=_begin, initargs=(os.getpid(),))
    if warm is not None:
        submit(warm)


def submit(problem) -> Future | None:
    """The helper's future of :func:`front_job` for ``problem``, or None without a working helper."""
    global _POOL
    if _POOL is None:
        return None
    try:
        return _POOL.submit(front_job, problem)
    except Exception:  # noqa: BLE001 - a broken or stopped pool: the caller computes the front itself
        stop()
        return None


def result(future: Future | None):
    """(front, CPU seconds) of a :func:`submit`-ted job, or None when it failed (the caller then computes the
    front itself, and raises its error if the problem has one; a helper that died is dropped)."""
    if future is None:
        return None
    try:
        return future.result()
    except BrokenProcessPool:
        stop()
        return None
    except Exception:  # noqa: BLE001 - the job's own error: the caller computes the front and raises it
        return None


def pid() -> int | None:
    """The helper's process id (asked of the helper: after its queued jobs), None without a helper."""
    return None if _POOL is None else _POOL.submit(os.getpid).result()


def stop() -> None:
    """Stop the helper process (nothing if none)."""
    global _POOL
    pool, _POOL = _POOL, None
    if pool is not None:
        pool.shutdown(wait=True, cancel_futures=True)


__all__ = ["expand_batches", "front_job", "pid", "result", "start", "stop", "submit"]
