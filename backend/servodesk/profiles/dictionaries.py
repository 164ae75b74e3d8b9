"""The object dictionary model each profile gives a node, parsed once per (file, node id).

A model is loaded for one node id because node-relative defaults ($NODEID+0x180 ...) are resolved
while parsing; the cache belongs to the registry that owns it (no module-level state).
"""

from __future__ import annotations

import threading
from dataclasses import replace
from pathlib import Path

from canopen.objectdictionary import ObjectDictionary

from servodesk.od import DeviceInfo, ObjectDictionaryModel, load_od
from servodesk.od.to_canopen import to_canopen
from servodesk.profiles.match import ProfileMatch


class ProfileDictionaries:
    """Parsed profile dictionaries; safe to use from worker threads."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._models: dict[tuple[Path, int, tuple[int, int] | None], ObjectDictionaryModel] = {}
        self._canopen: dict[int, tuple[ObjectDictionaryModel, ObjectDictionary]] = {}

    def model(self, profile: ProfileMatch, node: int) -> ObjectDictionaryModel:
        """The dictionary of `profile` for node `node` (parses the EDS on first use)."""
        if profile.eds_path is None:
            return _empty(profile.name, node)
        key = (profile.eds_path, node, profile.index_range)
        with self._lock:
            cached = self._models.get(key)
        if cached is not None:
            return cached
        model = load_od(profile.eds_path, node_id=node)
        if profile.index_range is not None:
            low, high = profile.index_range
            objects = {i: obj for i, obj in model.objects.items() if low <= i <= high}
            model = replace(model, objects=objects)
        with self._lock:
            return self._models.setdefault(key, model)

    def canopen(self, model: ObjectDictionaryModel, node: int) -> ObjectDictionary:
        """`to_canopen(model, node)` for a cached profile model, built once: going back to the
        profile's dictionary then allocates nothing (new long-lived objects would settle in
        the holes a large freed upload left, and keep its memory from the system)."""
        with self._lock:
            cached = self._canopen.get(id(model))
        if cached is not None and cached[0] is model:
            return cached[1]
        built = to_canopen(model, node)
        with self._lock:
            self._canopen[id(model)] = (model, built)
        return built

    @staticmethod
    def filename(profile: ProfileMatch) -> str:
        """How the UI names a profile's dictionary: `cia402/drive.eds`."""
        if profile.eds_path is None:
            return ""
        return f"{profile.eds_path.parent.name}/{profile.eds_path.name}"


def _empty(name: str, node: int) -> ObjectDictionaryModel:
    return ObjectDictionaryModel(
        device=DeviceInfo(), objects={}, warnings=(), source=name, format="eds", node_id=node
    )
