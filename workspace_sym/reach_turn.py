"""An arm turned by a limited first joint, under its earlier module name: :mod:`workspace_sym.serial.turn`."""

from .serial.turn import (
    DirectionMap,
    LimitedTurn,
    LimitedTurnTest,
    cell_level,
    covering_pairs,
    direction_seeds,
    full_turn_cells,
    limited_turn,
    limited_volume,
    pave_limited,
    pieces_upper,
    prove_directions,
)

__all__ = ["LimitedTurn", "limited_turn", "covering_pairs", "DirectionMap", "direction_seeds", "prove_directions",
           "full_turn_cells", "limited_volume", "pieces_upper", "cell_level", "LimitedTurnTest", "pave_limited"]
