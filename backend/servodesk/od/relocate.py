"""One parsed dictionary for every node id: its node-relative entries moved to another node."""

from __future__ import annotations

from dataclasses import replace

from servodesk.od.model import ObjectDictionaryModel, OdObject, OdSub


def for_node(model: ObjectDictionaryModel, node_id: int) -> ObjectDictionaryModel:
    """`model` as if it had been loaded for `node_id`: $NODEID defaults and values moved from
    the node id it was loaded with. Entries without one are shared, not copied."""
    loaded = model.node_id or 0
    if loaded == node_id:
        return model
    shift = node_id - loaded
    objects: dict[int, OdObject] = {}
    for index, obj in model.objects.items():
        subs = obj.subs
        if any(sub.relative or sub.value_relative for sub in subs.values()):
            subs = {subindex: _moved(sub, shift) for subindex, sub in subs.items()}
            obj = replace(obj, subs=subs)
        objects[index] = obj
    return replace(model, objects=objects, node_id=node_id)


def _moved(sub: OdSub, shift: int) -> OdSub:
    default, value = sub.default, sub.value
    if sub.relative and isinstance(default, int):
        default += shift
    if sub.value_relative and isinstance(value, int):
        value += shift
    if default is sub.default and value is sub.value:
        return sub
    return replace(sub, default=default, value=value)
