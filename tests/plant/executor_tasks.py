"""Tasks the executor tests send to worker processes (a module of few imports: each worker imports it)."""

from __future__ import annotations

import os
import time


def echo_after(task):
    """(value, seconds) -> (value, this process): ends after the given sleep, so later tasks can end first."""
    value, seconds = task
    time.sleep(seconds)
    return value, os.getpid()


def logged(task):
    """The task of `fn`, its start written to the log first (fn's name, the task's index, this process): which ran
    where, and how often."""
    log, index, fn, inner = task
    with open(log, "a") as out:
        out.write(f"{fn.__name__} {index} {os.getpid()}\n")
    return fn(inner)
