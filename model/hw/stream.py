"""Stream blocks of the texture unit that compute nothing on their data: Python twins.

`axis_skid` is the twin of rtl/axis_skid.v, the output skid buffer of texture_pipeline:
on the stream of beats it is the identity (every beat accepted leaves once, in order,
unchanged); what it adds (one clock of latency, a registered input ready, data held while
stalled) is timing, which its testbench (tb/axis_skid) checks on the RTL.
"""
from __future__ import annotations


def axis_skid(beats):
    """The beats (tdata, tlast) that leave rtl/axis_skid.v for the beats accepted: the same, in order."""
    return [tuple(b) for b in beats]
