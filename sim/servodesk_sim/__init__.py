"""Simulated CANopen servo drives (MDi-S1-C, Kinco, generic CiA 402) that behave like the manuals.

The simulator never imports the backend (`servodesk`); both read the drive data in
`servodesk_data`, so the tool and the simulated drives never disagree about a drive.
"""
