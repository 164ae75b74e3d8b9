"""BusManager: owns the python-can bus and the canopen.Network, and keeps them connected.

One manager per app. `connect` replaces any current connection; a connection that fails later
(the adapter was unplugged, the driver reports an error) goes to ERROR and an asyncio task opens
it again with backoff, while every other part of the tool keeps running. Nothing on the
notifier thread does I/O: failures are handed to the event loop with `call_soon_threadsafe`.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import time
from collections.abc import Callable
from concurrent.futures import Future
from typing import TYPE_CHECKING

import can
import canopen

from servodesk.bus.config_check import check_bus_config
from servodesk.bus.counters import BusCounters
from servodesk.bus.frame_tap import FrameTap
from servodesk.bus.interfaces import REFUSED
from servodesk.bus.link import Link, close_link, open_link
from servodesk.errors import BusNotConnectedError, BusOpenError, InvalidValueError
from servodesk.models.bus import BusConfig, BusState, BusStatus
from servodesk.settings import Settings

if TYPE_CHECKING:
    # types only: the simulator is started in bus/simulated.py and nowhere else, and that module
    # is imported only when simulated drives are asked for (`_open_and_report`)
    from servodesk.bus.simulated import SimBus, SimulatedDrives

log = logging.getLogger(__name__)

BusFactory = Callable[[BusConfig], can.BusABC]
StatusListener = Callable[[BusStatus], None]


def default_bus_factory(config: BusConfig) -> can.BusABC:
    """`can.Bus(...)` with unset arguments left out, so python-can's config file and
    environment variables still fill them in."""
    kwargs: dict[str, object] = {
        key: value
        for key, value in (
            ("interface", config.interface),
            ("channel", config.channel),
            ("bitrate", config.bitrate),
        )
        if value is not None
    }
    if config.interface == "socketcand":
        # python-can leaves Nagle's algorithm on for socketcand: a stop written while an earlier
        # frame (a SYNC) waits for its ACK is held until it comes, up to the peer's 40 ms
        # delayed ACK. `tcp_tune` sets TCP_NODELAY / TCP_QUICKACK; an explicit option still wins.
        kwargs["tcp_tune"] = True
    kwargs.update(config.options)
    return can.Bus(**kwargs)  # type: ignore[arg-type]  # python-can takes backend kwargs


def config_from_settings(settings: Settings) -> BusConfig:
    """The bus the settings (environment / CLI flags) name."""
    return BusConfig(
        interface=settings.interface,
        channel=settings.channel,
        bitrate=settings.bitrate,
        options=dict(settings.bus_options),
        simulated=settings.simulated,
    )


def _describe(exc: BaseException) -> str:
    text = str(exc).strip()
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


class BusManager:
    def __init__(self, settings: Settings, *, bus_factory: BusFactory | None = None) -> None:
        self._settings = settings
        self._factory: BusFactory = bus_factory or default_bus_factory
        self._config: BusConfig | None = None
        self._state = BusState.DISCONNECTED
        self._error: str | None = None
        self._since: float | None = None
        self._counters = BusCounters()
        self._link: Link | None = None
        self._sim: SimulatedDrives | None = None
        self._listeners: list[StatusListener] = []
        self._frame_listeners: list[can.Listener] = []
        self._sent_listeners: list[can.Listener] = []  # shared with every link's bus
        self._lock = asyncio.Lock()
        self._reconnect_task: asyncio.Task[None] | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self._link_token: object | None = None  # identifies the link whose failures count
        # Links taken out of service and not yet known to be closed; whoever closes them next
        # (the reconnect task, disconnect) waits until they are, even after a cancellation.
        self._closing: list[Link] = []
        # EMCY and SDO aborts picked out once for every service (`frames.on_emcy`, …)
        self.frames = FrameTap()
        self.add_frame_listener(self.frames)

    # ------------------------------------------------------------------ public API

    async def connect(self, config: BusConfig) -> BusStatus:
        """Open `config` (or the simulated drives), replacing any current connection.

        A bus that cannot be opened leaves the manager in ERROR with the reason; it is not
        retried automatically (the configuration is probably wrong), `reconnect()` retries it.
        """
        # An incomplete or unknown configuration is refused before the working bus is touched.
        config = check_bus_config(config)
        async with self._lock:
            self._loop = asyncio.get_running_loop()
            if self._replaces_working_bus(config):
                # The new adapter is opened before the working bus is closed: a mistyped
                # channel must not cost the user the bus the drives are on.
                raw = await self._open_beside(config)
                await self._shutdown()
                self._config = config
                self._counters = BusCounters()
                await self._open_and_report(start_sim=False, reconnecting=False, raw=raw)
                return self.status()
            await self._shutdown()
            # The configuration asked for is the one used: `--sim` only chooses what the app
            # connects at start-up, the user may switch to a real adapter afterwards.
            self._config = config
            self._counters = BusCounters()
            await self._open_and_report(start_sim=config.simulated, reconnecting=False)
            return self.status()

    def _replaces_working_bus(self, config: BusConfig) -> bool:
        """A connected bus is being replaced by another real adapter (not the same device,
        which may not open twice, and not the simulated drives, which start their own bus)."""
        current = self._effective_config()
        return (
            self._state is BusState.CONNECTED
            and self._link is not None
            and current is not None
            and not config.simulated
            and (current.interface, current.channel) != (config.interface, config.channel)
        )

    async def _open_beside(self, config: BusConfig) -> can.BusABC:
        """Open `config`'s bus while the current one stays; refuse in words if it cannot."""
        if config.interface in REFUSED:
            raise InvalidValueError(_refused(config.interface))
        try:
            return await self._build_bus(config)
        except Exception as exc:
            log.warning("could not open the CAN bus", exc_info=True)
            current = self._effective_config()
            kept = f"{current.interface} {current.channel}" if current else "the connected bus"
            raise BusOpenError(
                f"could not open {config.interface} {config.channel} ({_describe(exc)}): "
                f"{kept} stays connected; check the interface and channel"
            ) from exc

    async def disconnect(self) -> BusStatus:
        async with self._lock:
            await self._shutdown()
            return self.status()

    async def reconnect(self) -> BusStatus:
        """Open the same configuration again. Simulated drives keep running: only the tool's
        side of the bus is re-opened, as when an adapter is re-plugged."""
        async with self._lock:
            self._loop = asyncio.get_running_loop()
            if self._config is None:
                raise BusNotConnectedError("no bus was connected yet: connect first")
            await self._cancel_reconnect()
            await self._close_link()
            start_sim = self._config.simulated and self._sim is None
            await self._open_and_report(start_sim=start_sim, reconnecting=True)
            return self.status()

    def status(self) -> BusStatus:
        counts = self._counters.snapshot()
        config = self._effective_config()
        return BusStatus(
            state=self._state,
            interface=config.interface if config else None,
            channel=config.channel if config else None,
            bitrate=config.bitrate if config else None,
            simulated=bool(config and config.simulated),
            error=self._error,
            rx_frames=counts.rx_frames,
            tx_frames=counts.tx_frames,
            error_frames=counts.error_frames,
            bus_errors=counts.bus_errors,
            reconnects=counts.reconnects,
            since=self._since,
        )

    @property
    def network(self) -> canopen.Network:
        """The canopen Network of the current connection (a new one after each reconnect)."""
        if self._link is None or self._state is not BusState.CONNECTED:
            if self._state is BusState.ERROR and self._error:
                raise BusNotConnectedError(f"the CAN bus is not connected ({self._error})")
            raise BusNotConnectedError()
        return self._link.network

    @property
    def config(self) -> BusConfig | None:
        return self._config

    def label(self) -> str | None:
        """The bus in words, as stored with each event: "socketcan can0", "virtual
        servodesk-sim-…" (each simulated bus is its own); None before any was configured."""
        config = self._effective_config()
        if config is None or config.interface is None:
            return None
        return f"{config.interface} {config.channel}" if config.channel else config.interface

    @property
    def sim(self) -> SimBus | None:
        return self._sim.sim if self._sim is not None else None

    def add_listener(self, fn: StatusListener) -> Callable[[], None]:
        """Call `fn(status)` on the event loop at every state change; returns its remover."""
        self._listeners.append(fn)

        def remove() -> None:
            with contextlib.suppress(ValueError):
                self._listeners.remove(fn)

        return remove

    def add_frame_listener(
        self, listener: can.Listener, *, sent: bool = False
    ) -> Callable[[], None]:
        """Feed every received frame to `listener` on the notifier thread, on this and every
        later connection; with `sent`, also every frame the tool sends (on the sending thread).
        Returns its remover. The listener must not block or do I/O."""
        self._frame_listeners.append(listener)
        if sent:
            self._sent_listeners.append(listener)
        if self._link is not None:
            self._link.notifier.add_listener(listener)

        def remove() -> None:
            with contextlib.suppress(ValueError):
                self._frame_listeners.remove(listener)
            with contextlib.suppress(ValueError):
                self._sent_listeners.remove(listener)
            if self._link is not None:
                with contextlib.suppress(ValueError):
                    self._link.notifier.remove_listener(listener)

        return remove

    async def close(self) -> None:
        """App shutdown: disconnect and forget every listener."""
        await self.disconnect()
        self._listeners.clear()
        self._frame_listeners[:] = [self.frames]  # its own tap stays, without subscribers
        self.frames.clear()
        self._sent_listeners.clear()

    # ------------------------------------------------------------------ opening and closing

    def _effective_config(self) -> BusConfig | None:
        """What the tool's side of the bus is: the simulated channel in simulated mode."""
        if self._config is not None and self._config.simulated and self._sim is not None:
            return BusConfig(
                interface=self._sim.interface, channel=self._sim.channel, simulated=True
            )
        return self._config

    async def _open_and_report(
        self, *, start_sim: bool, reconnecting: bool, raw: can.BusABC | None = None
    ) -> None:
        self._set_state(BusState.CONNECTING)
        try:
            if start_sim:
                # Imported here, not with this module: bus/simulated.py brings the whole
                # simulator (servodesk_sim and every drive model), which a bus on a real
                # adapter never needs. Only a simulated configuration loads it.
                from servodesk.bus.simulated import prepare_simulated_drives

                self._sim = await asyncio.to_thread(prepare_simulated_drives)
            self._link = await self._open_link(raw)
            if start_sim and self._sim is not None:
                await asyncio.to_thread(self._sim.start)
        except Exception as exc:
            # Any failure to open (unknown interface, missing driver, busy device, bad bitrate)
            # is shown to the user as the bus state; the traceback goes to the log.
            log.warning("could not open the CAN bus", exc_info=True)
            if raw is not None and self._link is None:
                await asyncio.to_thread(raw.shutdown)  # opened for a link that never was
            if start_sim:
                await self._stop_sim()
            self._set_state(BusState.ERROR, _describe(exc))
            return
        if reconnecting:
            self._counters.reconnected()
        self._set_state(BusState.CONNECTED)

    async def _open_link(self, raw: can.BusABC | None = None) -> Link:
        """A link on `raw` (opened already) or on a bus opened now from the configuration."""
        config = self._effective_config()
        if config is None:
            raise BusNotConnectedError("no bus configuration")
        if config.interface in REFUSED:
            raise InvalidValueError(_refused(config.interface))
        if raw is None:
            raw = await self._build_bus(config)
        token = object()  # failures of this link only; stale reports are ignored
        listeners = list(self._frame_listeners)
        link = open_link(
            raw,
            self._counters,
            listeners,
            lambda message: self._failure(token, message),
            self._sent_listeners,
        )
        self._link_token = token
        return link

    async def _build_bus(self, config: BusConfig) -> can.BusABC:
        """Run the factory off the loop; a bus that arrives after we stopped waiting is closed."""
        loop = asyncio.get_running_loop()
        future: Future[can.BusABC] = Future()

        def build() -> None:
            try:
                future.set_result(self._factory(config))
            except BaseException as exc:
                future.set_exception(exc)

        pending = loop.run_in_executor(None, build)
        try:
            await pending
        except asyncio.CancelledError:
            future.add_done_callback(_shutdown_orphan)
            raise
        return future.result()

    async def _close_link(self) -> None:
        if self._link is not None:
            self._closing.append(self._link)
            self._link = None
            self._link_token = None
        for link in list(self._closing):
            await asyncio.to_thread(close_link, link)
            with contextlib.suppress(ValueError):
                self._closing.remove(link)

    async def _stop_sim(self) -> None:
        sim, self._sim = self._sim, None
        if sim is not None:
            await asyncio.to_thread(sim.stop)

    async def _shutdown(self) -> None:
        await self._cancel_reconnect()
        await self._close_link()
        await self._stop_sim()
        if self._state is not BusState.DISCONNECTED:
            self._set_state(BusState.DISCONNECTED)

    # ------------------------------------------------------------------ failures

    def _failure(self, token: object, message: str) -> None:
        """Called on any thread (notifier, node workers, cyclic send task)."""
        loop = self._loop
        if loop is None or loop.is_closed():
            log.warning("CAN bus failure with no event loop to report it to: %s", message)
            return
        try:
            loop.call_soon_threadsafe(self._on_failure, token, message)
        except RuntimeError:
            # The loop closed between the check and the call (app shutdown).
            log.warning("CAN bus failure during shutdown: %s", message)

    def _on_failure(self, token: object, message: str) -> None:
        if token is not self._link_token or self._link is None:
            return  # an older link, already replaced
        self._closing.append(self._link)
        self._link = None
        self._link_token = None
        log.warning("CAN bus failed: %s; reconnecting", message)
        self._set_state(BusState.ERROR, message)
        self._reconnect_task = asyncio.get_running_loop().create_task(
            self._reconnect_loop(message), name="bus-reconnect"
        )

    async def _reconnect_loop(self, reason: str) -> None:
        await self._close_link()  # the failed link
        delay = self._settings.reconnect_initial_delay
        while True:
            await asyncio.sleep(delay)
            async with self._lock:
                try:
                    self._link = await self._open_link()
                except Exception as exc:
                    # The adapter is still gone: say so and try again later.
                    delay = min(delay * 2, self._settings.reconnect_max_delay)
                    retry = f"reconnecting failed ({_describe(exc)}), next try in {delay:g} s"
                    self._set_state(BusState.ERROR, f"{reason}; {retry}")
                    continue
                self._counters.reconnected()
                log.info("CAN bus reconnected")
                self._set_state(BusState.CONNECTED)
                self._reconnect_task = None
                return

    async def _cancel_reconnect(self) -> None:
        task, self._reconnect_task = self._reconnect_task, None
        if task is not None and task is not asyncio.current_task():
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await task

    # ------------------------------------------------------------------ state

    def _set_state(self, state: BusState, error: str | None = None) -> None:
        self._state = state
        self._error = error
        self._since = time.time()
        self._notify()

    def _notify(self) -> None:
        status = self.status()
        for fn in list(self._listeners):
            try:
                fn(status)
            except Exception:
                # One broken listener must not stop the others from hearing about the bus.
                log.exception("bus status listener failed")


def _refused(interface: str) -> str:
    return (
        f"the {interface} interface sends every frame onto the local network; "
        "use a CAN adapter, socketcand or the simulated drives"
    )


def _shutdown_orphan(future: Future[can.BusABC]) -> None:
    if not future.cancelled() and future.exception() is None:
        future.result().shutdown()
