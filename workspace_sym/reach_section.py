"""An arm turned by its first joint, under its earlier module name: :mod:`workspace_sym.serial.section`."""

from .serial.section import (
    Pieces,
    RadialMap,
    Turned,
    TurnedTest,
    section_bar,
    section_paving,
    turned,
    turned_volume,
)

__all__ = ["Pieces", "RadialMap", "Turned", "turned", "TurnedTest", "section_bar", "section_paving", "turned_volume"]
