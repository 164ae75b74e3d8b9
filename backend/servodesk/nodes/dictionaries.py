"""DictionarySwap: replacing a node's object dictionary (an upload, or back to the profile's)
and moving a node to a new id, with no request cut off: requests already queued for the node
finish with the old dictionary, the new one takes over on the node's own thread."""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

from canopen.objectdictionary import ObjectDictionary

from servodesk.heap import keep_long_lived
from servodesk.nodes.entry import OdSource
from servodesk.nodes.profile_dictionaries import ProfileDictionaries
from servodesk.nodes.table import NodeTable
from servodesk.od import ObjectDictionaryModel
from servodesk.od.parser import release_memory
from servodesk.od.to_canopen import dispose, to_canopen


def _free(od: ObjectDictionary) -> None:
    dispose(od, pause=True)
    release_memory()


class DictionarySwap:
    def __init__(
        self,
        table: NodeTable,
        dictionaries: ProfileDictionaries,
        replaced: Callable[[int], None],
    ) -> None:
        """`replaced(node)` is called after a node's dictionary was replaced."""
        self._table = table
        self._dictionaries = dictionaries
        self._replaced = replaced

    async def set_od(self, node: int, model: ObjectDictionaryModel, source: OdSource) -> None:
        """Use `model` as the node's dictionary. The old one is released (nothing keeps it)."""
        if source == "profile":
            canopen_od = await self._dictionaries.canopen(model, node)
        else:
            canopen_od = await asyncio.to_thread(to_canopen, model, node)  # large files: seconds
        entry = self._table.entry(node)
        old_od = entry.canopen_od if entry.od_source == "upload" else None  # not shared
        entry.model = model
        entry.od_source = source
        entry.od_filename = (
            Path(model.source).name
            if source == "upload"
            else self._dictionaries.filename(entry.profile)
        )
        entry.canopen_od = canopen_od
        session, network = entry.session, entry.network

        def retire() -> None:
            # on a thread of its own, not the node's: emptying a large dictionary takes tens of
            # milliseconds that a stop queued for the node must not wait for
            if old_od is not None:
                threading.Thread(target=_free, args=(old_od,), name="od-retire").start()

        if source == "upload":
            keep_long_lived()  # a large dictionary is never walked by a full collection
        if session is not None and network is not None:
            # Requests already queued for the node finish with the old dictionary; the new one
            # takes over after them on the node's own thread (no request is cut off).
            session.replace_dictionary(entry.canopen_od, then=retire)
        else:
            self._table.bind_if_connected(entry)
            await asyncio.to_thread(retire)
        self._replaced(node)

    async def reset_od(self, node: int) -> None:
        """Back to the profile's dictionary."""
        entry = self._table.entry(node)
        model = await self._dictionaries.model(entry.profile, node)
        await self.set_od(node, model, "profile")

    async def move(self, old: int, new: int) -> None:
        """The node formerly at `old` answers at `new` now (its node id was changed).

        An uploaded dictionary moves with it (to_canopen resolves its node-relative entries
        for `new`); a node registered at `new` before is replaced."""
        table = self._table
        entry = table.entry(old)
        if new == old:
            return
        if entry.od_source == "profile":
            model = await self._dictionaries.model(entry.profile, new)
            canopen_od = await self._dictionaries.canopen(model, new)
        else:
            model = entry.model
            canopen_od = await asyncio.to_thread(to_canopen, model, new)  # large files: seconds
        for stale in (table.nodes.pop(new, None), table.nodes.pop(old)):
            if stale is not None:
                stale.unbind()
        table.monitor.untrack(new)
        table.monitor.untrack(old)
        moved = replace(
            entry,
            node=new,
            model=model,
            canopen_od=canopen_od,
            session=None,
            network=None,
        )
        table.nodes[new] = moved
        table.monitor.track(new, entry.identity.heartbeat_ms)
        table.bind_if_connected(moved)
