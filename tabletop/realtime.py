"""Real-time scheduling for the installation's threads: frames not delayed by other programs.

On a machine shared with other work (a gallery PC's updates, a browser, a second program), the
ordinary scheduler shares the cores fairly, and a frame waits whenever another program has the
core. ``SCHED_FIFO`` threads run ahead of every ordinary one. Measured with bench/loop.py on a
2-core machine busy with other programs (load average 10.6 -> 16.7), in an X window: the
4-reactor configuration at ordinary priority 16.0 ticks/s, capture-to-render 124.8 ms median and
243.8 ms p99; with ``realtime_priority`` 10 for its threads and the X server 60.0 ticks/s,
6.7 ms and 9.1 ms (the shipped config: 37.8 ticks/s, 64.6 / 171.7 ms -> 60.1 ticks/s,
3.8 / 7.1 ms). The X server must be ahead too: the present waits for it. Interleaved at load
12.7 (4 reactors, 2 rounds of 3 s): ordinary 25.0 ticks/s, 78 / 159 ms; real-time threads only
59.7 ticks/s, 8.8 / 26.5 ms (present p99 18.5 ms); threads and X server 60.0 ticks/s,
7.8 / 11.0 ms (present p99 1.7 ms). Give the installation's X server the same priority
(e.g. ``chrt -f -p 10 $(pidof Xorg)`` as root, or its display manager's unit with
``CPUSchedulingPolicy=fifo``).

The frame loop is paced (it sleeps between frames) and so is every camera, so real-time threads
leave the rest of the machine its time; the kernel also keeps 5 % of every second for ordinary
threads. Allowed for root, for a process with CAP_SYS_NICE, or up to systemd's ``LimitRTPRIO``.
Linux only; elsewhere, or when refused, one warning and the ordinary scheduler.
"""

from __future__ import annotations

import logging
import os
from typing import Callable

log = logging.getLogger("tabletop")


def realtime_threads(priority: int) -> Callable[[], None] | None:
    """Give every thread of this process SCHED_FIFO ``priority`` (threads they start later
    inherit it); returns a function that puts them back as they were, or None (with one
    warning) when the system refuses."""
    setter = getattr(os, "sched_setscheduler", None)
    try:
        tids = [int(t) for t in os.listdir("/proc/self/task")]
    except OSError:
        tids = []
    if setter is None or not tids:
        log.warning("real-time priority: not available on this system; ordinary scheduling")
        return None
    before: dict[int, tuple[int, int]] = {}
    try:
        for tid in tids:
            try:
                before[tid] = (os.sched_getscheduler(tid), os.sched_getparam(tid).sched_priority)
                setter(tid, os.SCHED_FIFO, os.sched_param(priority))
            except ProcessLookupError:   # a thread that just ended
                before.pop(tid, None)
    except PermissionError:
        _restore(before)
        log.warning("real-time priority %d refused (needs root, CAP_SYS_NICE or systemd's "
                    "LimitRTPRIO=%d); ordinary scheduling", priority, priority)
        return None
    return lambda: _restore(before)


def _restore(before: dict[int, tuple[int, int]]) -> None:
    for tid, (policy, prio) in before.items():
        try:
            os.sched_setscheduler(tid, policy, os.sched_param(prio))
        except (ProcessLookupError, PermissionError):
            pass
