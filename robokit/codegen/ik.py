"""placeholder"""
from __future__ import annotations
from dataclasses import dataclass, field
from typing import Any

@dataclass
class IKCode:
    has_ik: bool
    note: str
    max_solutions: int
    header_lines: list = field(default_factory=list)
    source: str = ""

def emit_ik(robot: Any, prefix: str) -> IKCode:
    return IKCode(False, "not yet", 1)
