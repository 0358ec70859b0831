"""Child processes never outlive their parent: one function, :func:`bind_to_parent`, called first in every child.

The tool starts child processes in three places: ``designer explore --workers N`` (a pool of optuna workers),
``designer studio`` (its helper process) and ``designer fleet --scheduler local`` (Dask's worker processes,
started by the nannies of this process).  A parent that ends normally, or by SIGINT/SIGTERM, stops its children itself; a parent that is
killed (``kill -9``, the out-of-memory killer) cannot, and its children used to run on under init (an explore
pool finished all its trials).  So each child binds its life to its parent's as it starts:

- Linux: ``prctl(PR_SET_PDEATHSIG, SIGKILL)`` (through ctypes): the kernel kills the child when the thread
  that started it ends.  A parent that died before the call is caught by comparing :func:`os.getppid` with
  the parent's pid passed to the child (the child was re-parented already): the child ends at once.
- Everywhere (and on Linux as a second line, e.g. when the starting thread ends before the process): a daemon
  thread polls :func:`os.getppid` every 0.2 s and ends the child with ``os._exit`` once the parent is gone.

A child of a child binds to its own parent: the chain ends from the top.  Processes that multiprocessing
starts for itself (its resource tracker) end when their pipe from the parent closes.
"""

from __future__ import annotations

import contextlib
import ctypes
import logging
import os
import signal
import sys
import threading
import time

PR_SET_PDEATHSIG = 1
"""prctl option: the signal the kernel sends this process when its parent thread ends (linux/prctl.h)."""

POLL_SECONDS = 0.2
"""How often the watchdog thread looks at the parent's pid [s]."""

EXIT_ORPHANED = 137
"""Exit status of a child whose parent is gone (as if killed by SIGKILL: 128 + 9)."""


def _watch(parent: int) -> None:
    while os.getppid() == parent:
        time.sleep(POLL_SECONDS)
    os._exit(EXIT_ORPHANED)


def bind_to_parent(parent: int | None = None) -> None:
    """End this process when its parent ends, whatever ends the parent (SIGKILL included).

    Call it first in a child process.  ``parent``: the pid of the process that started this one, as that
    process saw it (``os.getpid()`` there, passed as an argument); default the current parent.  If the parent
    has already gone (this process was re-parented before the call) the process ends at once with exit status
    :data:`EXIT_ORPHANED`.
    """
    expected = os.getppid() if parent is None else parent
    if sys.platform.startswith("linux"):  # the kernel sends SIGKILL to this process when its parent ends
        with contextlib.suppress(OSError, AttributeError):  # no libc symbol (musl without prctl, a sandbox)
            ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    if os.getppid() != expected:  # the parent died before the kernel was told: nobody would kill us
        os._exit(EXIT_ORPHANED)
    with contextlib.suppress(RuntimeError):  # at interpreter shutdown no thread can start: the prctl holds
        threading.Thread(target=_watch, args=(expected,), name="parent-watch", daemon=True).start()


WORKER_LOG_LEVEL = logging.ERROR
"""Least level a Dask worker process of the tool logs at: its warnings (a task cancelled when the command is
interrupted, "Async instruction ... ended with CancelledError") are not the user's business; the command
reports what matters itself, and a task's error reaches the command as its exception."""


class SchedulerGone(logging.Filter):
    """A logging filter for the workers of the command's local cluster: it drops a record that carries an
    :class:`OSError` (Dask's ``CommClosedError`` is one), e.g. "Failed to communicate with scheduler during
    heartbeat" and its traceback.  The scheduler of a local cluster lives in the command's process, so a worker
    that loses its connection to it is one whose command is ending (an interruption closes the scheduler while a
    heartbeat is under way); the command says how it ended in its own one line."""

    def filter(self, record: logging.LogRecord) -> bool:
        info = record.exc_info
        return not (info and isinstance(info[1], OSError))


def dask_setup(worker: object) -> None:
    """Dask's preload hook (``preload=["designer.children"]``): a Dask worker process binds itself to the
    process that started it (:func:`bind_to_parent`), leaves Ctrl-C to it (SIGINT reaches the whole process group
    at a terminal; the command stops its workers itself and prints one line), logs only errors
    (:data:`WORKER_LOG_LEVEL`) and none about the command's scheduler going away (:class:`SchedulerGone`)."""
    bind_to_parent()
    dask_log = logging.getLogger("distributed")
    dask_log.setLevel(WORKER_LOG_LEVEL)
    for handler in dask_log.handlers or logging.getLogger().handlers:  # distributed's own stderr handler
        handler.addFilter(SchedulerGone())
    with contextlib.suppress(ValueError):  # not the main thread of the worker process: the parent ends it anyway
        signal.signal(signal.SIGINT, signal.SIG_IGN)


__all__ = ["EXIT_ORPHANED", "POLL_SECONDS", "WORKER_LOG_LEVEL", "SchedulerGone", "bind_to_parent", "dask_setup"]
