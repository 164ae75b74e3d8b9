"""ObjectDictionaryModel -> canopen.ObjectDictionary, so RemoteNode's SDO/PDO helpers can use it."""

from __future__ import annotations

import time
from typing import Any

import canopen
from canopen.objectdictionary import ObjectDictionary, ODArray, ODRecord, ODVariable

from servodesk.od import datatypes as dt
from servodesk.od.model import ObjectDictionaryModel, OdSub, Value

_DUMMY_NAMES = "Dummy{:04d}"  # python-canopen's names for DummyUsage entries
DISPOSE_CHUNK = 256  # objects freed between two releases of the interpreter lock


def to_canopen(
    model: ObjectDictionaryModel, node_id: int | None
) -> canopen.objectdictionary.ObjectDictionary:
    """Node-relative defaults and values ($NODEID+...) are resolved for `node_id`."""
    od = ObjectDictionary()  # type: ignore[no-untyped-call]  # canopen leaves it unannotated
    od.node_id = node_id
    od.bitrate = model.device.baud_rate
    od.comments = model.device.comments
    _device_information(od, model)
    for dummy in sorted(model.device.dummy_usage):
        # dummy entries let a PDO map fill bits (CiA 301), as python-canopen does
        var = ODVariable(_DUMMY_NAMES.format(dummy), dummy, 0)
        var.data_type = dummy
        var.access_type = "const"
        od.add_object(var)
    for obj in model.objects.values():
        if obj.object_type in ("var", "domain"):
            sub = obj.subs.get(0)
            if sub is not None:
                od.add_object(_variable(sub, model.node_id, node_id))
            continue
        container = (
            ODArray(obj.name, obj.index)
            if obj.object_type == "array"
            else ODRecord(obj.name, obj.index)
        )
        for subindex in sorted(obj.subs):
            container.add_member(_variable(obj.subs[subindex], model.node_id, node_id))
        od.add_object(container)
    return od


def _device_information(od: ObjectDictionary, model: ObjectDictionaryModel) -> None:
    # Any: canopen annotates nr_of_RXPDO/nr_of_TXPDO as bool, but stores PDO counts there
    info: Any = od.device_information
    device = model.device
    info.allowed_baudrates = set(device.baud_rates)
    info.vendor_name = device.vendor_name or None
    info.vendor_number = device.vendor_number
    info.product_name = device.product_name or None
    info.product_number = device.product_number
    info.revision_number = device.revision_number
    info.order_code = device.order_code or None
    info.simple_boot_up_master = device.simple_boot_up_master
    info.simple_boot_up_slave = device.simple_boot_up_slave
    info.granularity = device.granularity
    info.dynamic_channels_supported = device.dynamic_channels_supported
    info.group_messaging = device.group_messaging
    info.nr_of_RXPDO = device.nr_rx_pdo
    info.nr_of_TXPDO = device.nr_tx_pdo
    info.LSS_supported = device.lss_supported


def _variable(sub: OdSub, loaded_for: int | None, node_id: int | None) -> ODVariable:
    # Any: canopen annotates min/max/default/value as int, but its own EDS importer stores
    # floats, strings and bytes there, and sets default_raw/value_raw without declaring them
    result = ODVariable(sub.name, sub.index, sub.subindex)
    var: Any = result
    var.data_type = sub.data_type
    var.access_type = sub.access
    var.pdo_mappable = sub.pdo_mappable
    if dt.is_integer(sub.data_type) or dt.is_float(sub.data_type):
        var.min = sub.low
        var.max = sub.high
    var.default = _resolve(sub.default, sub.relative, loaded_for, node_id)
    var.default_raw = sub.default_raw
    var.relative = sub.relative
    var.value = _resolve(sub.value, sub.value_relative, loaded_for, node_id)
    var.value_raw = sub.value_raw
    var.unit = sub.unit
    var.factor = sub.factor
    var.description = sub.description
    return result


def _resolve(
    value: Value | None, relative: bool, loaded_for: int | None, node_id: int | None
) -> Value | None:
    """Move a node-relative value from the node id the model was loaded for to `node_id`."""
    if not relative or not isinstance(value, int):
        return value
    return value - (loaded_for or 0) + (node_id or 0)


def dispose(od: ObjectDictionary, *, pause: bool = False) -> None:
    """Empty a dictionary that is no longer used. canopen links each record member back to its
    record (`parent`), so a dropped dictionary would wait for the cycle collector, whose full
    pass over a large heap stops the server for a noticeable time; without the links its
    entries are freed at once by reference counting. With `pause` (a thread of its own), the
    interpreter lock is given back every DISPOSE_CHUNK objects: freeing a large dictionary
    in one piece holds it for tens of milliseconds."""
    for count, obj in enumerate(list(od.values()), 1):
        if isinstance(obj, ODRecord | ODArray):
            for member in list(obj.values()):
                member.parent = None
            obj.subindices.clear()
            obj.names.clear()
        if pause and count % DISPOSE_CHUNK == 0:
            time.sleep(0)
    od.names.clear()
    while od.indices:
        for _ in range(min(DISPOSE_CHUNK, len(od.indices))):
            od.indices.popitem()
        if pause:
            time.sleep(0)
