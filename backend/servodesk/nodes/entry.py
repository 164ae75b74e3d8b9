"""One registered node: identity, profile, dictionary, and its session on the current Network."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

import canopen
from canopen.objectdictionary import ObjectDictionary

from servodesk.models.nodes import NodeInfo
from servodesk.network.health import Health
from servodesk.nodes.identity import Identity
from servodesk.nodes.tracked import TrackedSession
from servodesk.od import ObjectDictionaryModel
from servodesk.profiles import ProfileMatch

OdSource = Literal["profile", "upload"]
SessionFactory = Callable[[canopen.RemoteNode], TrackedSession]


@dataclass
class NodeEntry:
    node: int
    identity: Identity
    profile: ProfileMatch
    model: ObjectDictionaryModel
    od_source: OdSource
    od_filename: str
    canopen_od: ObjectDictionary  # `model` for canopen, resolved for `node`
    session: TrackedSession | None = None
    network: canopen.Network | None = None  # the Network `session` is bound to

    def bound(self, network: canopen.Network, new_session: SessionFactory) -> TrackedSession:
        """The session on `network`, binding a new RemoteNode and session if needed."""
        if self.session is not None and self.network is network:
            return self.session
        self.unbind()
        remote = canopen.RemoteNode(self.node, self.canopen_od)
        network.add_node(remote)  # replaces (and unsubscribes) an older RemoteNode at this id
        session = new_session(remote)
        self.session = session
        self.network = network
        return session

    def unbind(self) -> None:
        """Close the session (a call in progress on it finishes; queued ones are dropped)."""
        if self.session is not None:
            self.session.close()
        self.session = None
        self.network = None

    def info(self, health: Health, last_seen: float | None) -> NodeInfo:
        identity = self.identity
        return NodeInfo(
            node=self.node,
            name=identity.name,
            vendor_id=identity.vendor_id,
            product_code=identity.product_code,
            revision=identity.revision,
            serial=identity.serial,
            hardware_version=identity.hardware,
            software_version=identity.software,
            device_type=identity.device_type,
            profile=self.profile.name,
            profile_label=self.profile.label,
            nmt_state=health.nmt_state,
            online=health.online,
            heartbeat_age_ms=health.heartbeat_age_ms,
            last_seen=last_seen,
            od_source=self.od_source,
            od_filename=self.od_filename,
            od_warnings=len(self.model.warnings),
        )


def live_row(node: int, health: Health) -> dict[str, Any]:
    """One node in the WebSocket's "nodes" message."""
    return {
        "node": node,
        "nmt_state": health.nmt_state.value,
        "online": health.online,
        "heartbeat_age_ms": health.heartbeat_age_ms,
    }
