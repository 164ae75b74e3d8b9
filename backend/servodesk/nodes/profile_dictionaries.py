"""The registry's profile dictionaries: each profile's EDS parsed once, in the dictionary
parser's worker process (od/parser.py), and shared by every node of that profile.

Parsing in threads during a scan (one per node, two or three at once) held the interpreter lock
for hundreds of milliseconds and stalled the event loop. A node's model is the shared one with
its $NODEID entries moved to the node (od/relocate.py, a few objects); its canopen dictionary is
built once per node on a worker thread and kept (going back to the profile's dictionary then
allocates nothing).
"""

from __future__ import annotations

import asyncio
from dataclasses import replace
from pathlib import Path

from canopen.objectdictionary import ObjectDictionary

from servodesk.od import DeviceInfo, ObjectDictionaryModel
from servodesk.od.parser import OdParser
from servodesk.od.relocate import for_node
from servodesk.od.to_canopen import to_canopen
from servodesk.profiles import ProfileMatch

_Key = tuple[Path, tuple[int, int] | None]


class ProfileDictionaries:
    def __init__(self, parser: OdParser) -> None:
        self._parser = parser
        self._parsed: dict[_Key, asyncio.Task[ObjectDictionaryModel]] = {}
        self._models: dict[tuple[_Key, int], ObjectDictionaryModel] = {}
        self._canopen: dict[int, tuple[ObjectDictionaryModel, ObjectDictionary]] = {}

    async def model(self, profile: ProfileMatch, node: int) -> ObjectDictionaryModel:
        """The dictionary of `profile` for node `node` (the file is parsed on first use)."""
        if profile.eds_path is None:
            return _empty(profile.name, node)
        key = (profile.eds_path, profile.index_range)
        cached = self._models.get((key, node))
        if cached is not None:
            return cached
        parsing = self._parsed.get(key)
        if parsing is None or (parsing.done() and parsing.exception() is not None):
            parsing = asyncio.get_running_loop().create_task(self._parse(profile))
            self._parsed[key] = parsing
        model = for_node(await asyncio.shield(parsing), node)
        return self._models.setdefault((key, node), model)

    async def canopen(self, model: ObjectDictionaryModel, node: int) -> ObjectDictionary:
        """`to_canopen(model, node)` for a model of `model()`, built once."""
        cached = self._canopen.get(id(model))
        if cached is not None and cached[0] is model:
            return cached[1]
        built = await asyncio.to_thread(to_canopen, model, node)
        self._canopen[id(model)] = (model, built)
        return built

    @staticmethod
    def filename(profile: ProfileMatch) -> str:
        """How the UI names a profile's dictionary: `cia402/drive.eds`."""
        if profile.eds_path is None:
            return ""
        return f"{profile.eds_path.parent.name}/{profile.eds_path.name}"

    async def _parse(self, profile: ProfileMatch) -> ObjectDictionaryModel:
        path = profile.eds_path
        if path is None:
            raise ValueError("a profile without a file has nothing to parse")
        data = await asyncio.to_thread(path.read_bytes)
        model = await self._parser.parse(data, str(path), node_id=0)
        if profile.index_range is not None:
            low, high = profile.index_range
            objects = {i: obj for i, obj in model.objects.items() if low <= i <= high}
            model = replace(model, objects=objects)
        return model


def _empty(name: str, node: int) -> ObjectDictionaryModel:
    return ObjectDictionaryModel(
        device=DeviceInfo(), objects={}, warnings=(), source=name, format="eds", node_id=node
    )
