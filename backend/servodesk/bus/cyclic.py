"""python-can's thread-based cyclic send task, made to keep time (the tool's SYNC rides on it).

`ThreadBasedCyclicSendTask` is what python-can's `send_periodic` gives on every interface without
a scheduler of its own (virtual, socketcand, PCAN, Kvaser …). It sleeps to absolute due times and,
after a stall (its thread not scheduled, or waiting for the interpreter lock), sends every due
time that passed at once, back to back: 6,869 such bursts in 10 s of a 1 ms SYNC on a loaded
host. A drive that gets several SYNCs at once takes each as a cycle. This task differs in two
ways only:

- no bursts: two frames are never closer than half a period. A late frame goes when the thread
  runs; the ones missed meanwhile follow half a period apart until the schedule is met again,
  so a 1 kHz SYNC still counts 1000 per second after a stall of a few periods (the scope's
  samples, an interpolating drive's clock). A stall longer than CATCH_UP_S (or 3 periods) is not
  made up: the schedule moves to the next slot on it;
- its thread asks the kernel for prompt wake-ups, as any unprivileged thread may (Linux): a timer
  slack of 1 ns (`PR_SET_TIMERSLACK`; the default adds up to 50 µs to every wake-up) and a
  0.1 ms scheduler slice (`sched_setattr`, SCHED_OTHER; Linux ≥ 6.12's EEVDF scheduler then
  runs it on waking ahead of CPU-bound tasks with the default slice, 1.4 ms on 2 cores: over
  runs of a 1 ms SYNC on a busy 2-core host, the median p99 period error went from 0.8 to
  0.45 ms). Its share of the CPU stays the same; real-time policies need root.

It does not spin for the last microseconds: spinning holds the interpreter lock, which the drives'
and the notifier's threads need, doubles the task's CPU (+12 % of a core at 1 kHz), and moved the
median by 10 µs but not the p99. The clock and the sleep are parameters so the tests can script
a stall.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import logging
import os
import platform
import struct
import sys
import threading
import time
from collections.abc import Callable, Sequence

import can

log = logging.getLogger(__name__)

PR_SET_TIMERSLACK = 29  # prctl option (linux/prctl.h)
SLICE_NS = 100_000  # the shortest slice the kernel grants
# sched_setattr's number (asm-generic unistd for the 64-bit ARM and RISC-V)
SCHED_SETATTR = {"x86_64": 314, "aarch64": 274, "riscv64": 274, "armv7l": 380, "i686": 351}
# Up to this late, the next interval is shorter by as much and no frame is lost (both errors stay
# within the SYNC target of 0.5 ms); later, the schedule moves and the lateness is not made up.
# A stall up to this long is made up (half-period spacing): each SYNC made up is a real sample
# of the scope's TPDOs, taken when it arrives; a longer one is not (the drives' SYNC-lost alarms
# have counted it, and making it up would double the SYNC rate for as long again)
CATCH_UP_S = 0.1

Clock = Callable[[], int]  # monotonic ns
Sleep = Callable[[float], None]  # s


def precise_wakeups() -> None:
    """This thread: 1 ns timer slack and a short scheduler slice (Linux); elsewhere, or where the
    kernel refuses, the defaults (the task works the same, with later wake-ups)."""
    if not sys.platform.startswith("linux"):
        return
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c"), use_errno=True)
        if libc.prctl(PR_SET_TIMERSLACK, 1, 0, 0, 0) != 0:
            log.debug("PR_SET_TIMERSLACK refused: errno %d", ctypes.get_errno())
        number = SCHED_SETATTR.get(platform.machine())
        if number is not None and os.sched_getscheduler(0) == os.SCHED_OTHER:
            # struct sched_attr, first version (48 bytes): size, policy, flags, nice, priority,
            # runtime (the slice, for SCHED_OTHER), deadline, period; the nice value is kept
            nice = os.getpriority(os.PRIO_PROCESS, 0)  # this thread's, on Linux
            attr = struct.pack("=IIQiIQQQ", 48, os.SCHED_OTHER, 0, nice, 0, SLICE_NS, 0, 0)
            if libc.syscall(number, 0, ctypes.create_string_buffer(attr, len(attr)), 0) != 0:
                log.debug("sched_setattr refused: errno %d", ctypes.get_errno())
    except (OSError, AttributeError):
        log.debug("no prctl or syscall: the cyclic task keeps the default wake-ups")


class SteadyCyclicSendTask(can.broadcastmanager.ThreadBasedCyclicSendTask):
    """`ThreadBasedCyclicSendTask` with the same arguments and behaviour on errors, modifier
    callbacks, durations and restarts, without catch-up bursts (module docstring)."""

    def __init__(
        self,
        bus: can.BusABC,
        lock: threading.Lock,
        messages: Sequence[can.Message] | can.Message,
        period: float,
        duration: float | None = None,
        on_error: Callable[[Exception], bool] | None = None,
        autostart: bool = True,
        modifier_callback: Callable[[can.Message], None] | None = None,
        *,
        clock: Clock = time.perf_counter_ns,
        sleep: Sleep = time.sleep,
    ) -> None:
        self._clock = clock  # set before the base class starts the thread
        self._sleep = sleep
        super().__init__(
            bus, lock, messages, period, duration, on_error, autostart, modifier_callback
        )

    def _run(self) -> None:
        precise_wakeups()
        period = self.period_ns
        half = period // 2
        catch_up = max(3 * period, round(CATCH_UP_S * 1e9))
        index = 0
        slot = self._clock()  # where the schedule says the next frame goes
        last = slot - period  # when the last frame left
        while not self.stopped:
            self._sleep_until(max(slot, last + half))
            if self.stopped:
                break
            if self.end_time is not None and time.perf_counter() >= self.end_time:
                self.stop()
                break
            if not self._send(self.messages[index]):
                break
            # Judged once the send returned: the thread may also be held inside it (the lock),
            # and the frame may have left only then.
            last = self._clock()
            index = (index + 1) % len(self.messages)
            slot += period
            behind = last + half - slot
            if behind > catch_up:  # too long to make up: the next slot on schedule
                slot += -(-behind // period) * period

    def _sleep_until(self, due: int) -> None:
        """Sleep until `due` (clock ns)."""
        while (left := due - self._clock()) > 0:
            self._sleep(left / 1e9)

    def _send(self, message: can.Message) -> bool:
        """One frame, as the base class sends it; False when the task must end."""
        try:
            if self.modifier_callback is not None:
                self.modifier_callback(message)
            with self.send_lock:  # one sender at a time on the bus
                self.bus.send(message)
        except Exception as exc:
            log.exception(exc)
            if self.on_error is None:
                self.stop()
                raise
            if not self.on_error(exc):
                self.stop()
                return False
        return True
