"""Turn a drive's data (servodesk_data: profile.toml quirks and fault table) into the settings of
each simulator core, in one place, so a quirk is read from the data and nowhere hard-coded."""

from __future__ import annotations

from dataclasses import dataclass

from servodesk_data import DriveData, NodeIdSource, ObjectRef
from servodesk_data.model import PdoRemapRule, SdoLengthCheck
from servodesk_protocol.emcy import EmcyFormat
from servodesk_sim.motion import MotionConfig
from servodesk_sim.od_store import LengthCheck
from servodesk_sim.pdo import PdoRules
from servodesk_sim.sync import SyncRules

_LENGTH = {
    SdoLengthCheck.GENERIC: LengthCheck.GENERIC,
    SdoLengthCheck.SPECIFIC: LengthCheck.SPECIFIC,
}


@dataclass(frozen=True)
class DriveConfig:
    length_check: LengthCheck
    sdo_block_transfer: bool
    pdo_rules: PdoRules
    sync_rules: SyncRules
    emcy_format: EmcyFormat
    fault_history: bool
    kinco_fault_bits: bool
    motion: MotionConfig
    node_id_source: NodeIdSource
    node_id_object: ObjectRef | None
    bitrate_objects: tuple[ObjectRef, ...]


def drive_config(data: DriveData) -> DriveConfig:
    quirks = data.quirks
    # Nanotec article: the Nanotec-style controller restarts its event timer only when it expires
    # and
    # takes a new PDO CAN-ID only after a reset; the MDi and Kinco act at once (MDi-S1-C manual
    # §2.5.3).
    nanotec_timing = quirks.pdo_remap_rule is PdoRemapRule.OUTSIDE_OPERATIONAL
    pdo_rules = PdoRules(
        rpdo_count=quirks.rpdo_count,
        tpdo_count=quirks.tpdo_count,
        byte_granular=quirks.pdo_byte_granular,
        remap_rule=quirks.pdo_remap_rule,
        rtr_transmission=quirks.pdo_rtr_transmission,
        fixed_cob_ids=quirks.pdo_fixed_cob_ids,
        event_timer_restarts_on_send=not nanotec_timing,
        cob_id_change_needs_reset=nanotec_timing,
    )
    motion = MotionConfig(
        supported_modes=quirks.supported_modes,
        homing_methods=quirks.homing_methods,
        immediate_setpoint=quirks.pp_immediate_setpoint,
        unsupported_mode_display=quirks.unsupported_mode_display,
        reference_found_bit15=quirks.homing_reference_found_bit15,
        max_speed=(*quirks.max_speed_object, "rpm"),
        limit_switch_reaction=quirks.limit_switch_reaction,
    )
    return DriveConfig(
        length_check=_LENGTH[quirks.sdo_length_check],
        sdo_block_transfer=quirks.sdo_block_transfer,
        pdo_rules=pdo_rules,
        sync_rules=SyncRules(
            min_period_us=quirks.sync_min_period_us,
            require_period_before_enable=quirks.sync_require_period_before_enable,
        ),
        emcy_format=quirks.emcy_format,
        fault_history=quirks.fault_history_1003,
        kinco_fault_bits=quirks.kinco_fault_bits,
        motion=motion,
        node_id_source=quirks.node_id_source,
        node_id_object=quirks.node_id_object,
        bitrate_objects=quirks.bitrate_objects,
    )
