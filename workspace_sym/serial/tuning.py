"""The tuning of the reach methods: every constant that changes which boxes are proved, in one frozen object.

A plan (:mod:`workspace_sym.serial.plans`) reads its figures from a :class:`Tuning`, the default
:data:`DEFAULT` or one given to :func:`~workspace_sym.serial.api.reach` (``tuning=``).  None of them can make a
box proved wrongly: they say how much work each stage may do (samples, pairs, depths, chunks between two looks
at the budget, shares of a time limit), so they decide how many boxes are proved, and where a stopped run stops.
The whole object is part of the fingerprint of every checkpoint and kept section
(:func:`~workspace_sym.serial.stored.reach_problem`): a run resumed with another tuning is refused.

The constants that guard soundness are not here and cannot be tuned: the widening of float polar angles
(:data:`workspace_sym.serial.angles.ANGLE_PAD`) and the four axis directions of a limited turn
(:data:`workspace_sym.serial.turn.DIRECTIONS`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from ..errors import InvalidParameterError

__all__ = ["Tuning", "DEFAULT"]


@dataclass(frozen=True, slots=True)
class Tuning:
    """How much work each stage of a reach run may do (module docstring).

    Parameters
    ----------
    max_pairs, inner_depth : int
        The pairs method without a tool constraint: a task box stops refining its joint boxes once it would
        hold more than ``max_pairs`` times its share of the root box's measure (``min_pairs`` at least); a box
        about to become a boundary box is also proved inner piece by piece, halved along every edge up to
        ``inner_depth`` times.
    pose_max_pairs, pose_inner_depth : int
        The same with a tool constraint (its pairs carry wrist values too).
    min_pairs : int
        Pairs a task box may always hold, however small its share of the root box.
    section_ratio : float
        Cell width of a section (the plane a turned arm's workspace reduces to) against the width of the task
        boxes.
    section_reserve : float
        Margin on the expected time of a step of a turned section, and on its (x, y, z) boxes.
    section_pairs, section_samples, section_chunk : int
        A section moved by three joints or more (:func:`~workspace_sym.serial.section.section_paving`): the
        (cell block, joint box) pairs of one generation of its blocks at most, the sampled configurations whose
        cells are proved inside first, and the cells proved between two looks at the budget.
    blocks_share, blocks_weight : float
        With a time limit, the share of the section's time left after the first proofs that its blocks may
        take: at most ``blocks_share``, else ``blocks_weight`` times the share of the undecided volume no
        sample reached (tuned on the UR5, where that share is 5 % and blocks decide nothing, and the KR16,
        27 %, where they decide 0.66 m^3 outside in 28 s).
    reach_tolerance : float
        The bound of the squared distance from the shoulder is sought within this many cell widths times the
        greatest distance (in distance, about half this many cell widths: a tenth of a cell).
    section_depth : int
        With a time limit, an undecided cell of a section is refined into pieces halved this often at most
        (the time limit stops it first on the UR5 and the KR16).
    direction_chunk, direction_samples : int
        A first joint limited to part of a turn (:mod:`workspace_sym.serial.turn`): cells proved at a direction
        between two looks at the budget, and the sampled configurations giving the seeds of the proofs.
    flange_directions : float
        An offset flange's sections (:class:`~workspace_sym.serial.plans.FlangePlan`): the share of a
        solution's time its directions take when its conditions hold the most often (less in proportion to
        how often they hold), the blocks the rest until ``blocks_end`` (0.5 since the sectors were read from the
        spin's linear form: 30.6 % against 31.5 % with 0.6 and 32.7 % with 0.4, BENCHMARKS.md, session 31).
    flange_pairs : int
        The ``section_pairs`` of an offset flange's blocks: its joint boxes' enclosures are wider (the unit
        vector of the offset), and four times the default's pairs narrowed the Panda's upper bound from 2.52 to
        2.30 m³ in the same time (BENCHMARKS.md, session 30); eight times gave 27.4 % beside another run and
        32.1 % alone against this default's 30.6 % (session 31): not kept.
    cone_directions : float
        A cone on an offset flange: the share of its own map's time (the tool point's section, whose blocks give
        outer proofs and whose directions inner ones over the whole cone) its directions take.  With the wrist's
        ring proving the outer cells, the directions take most (the Panda's cone of 20 deg in 300 s: 45.2 % at
        0.1, 18.5 % at 0.6, 14.4 % at 0.85; BENCHMARKS.md, session 32).
    flange_section_share : float
        An offset flange's sections take this share of the time left (``pose_section_share`` for the other
        pose plans): the task boxes are read from their cells in a few seconds (the Panda's tool down: 32.0 %
        against 34.1 % with 0.8 in 300 s, BENCHMARKS.md, session 31).
    direction_depth, timed_depth : int
        A cell failing whole is tried in ``4^level`` pieces, level up to ``direction_depth`` (``timed_depth``
        with a time limit: the deepest level takes the time the other stages leave).
    directions_share, blocks_end : float
        With a time limit (or a budget of section boxes), the cells are tried at the four directions until
        ``directions_share`` of the time left after the symbolic preparation, then outside blocks until
        ``blocks_end`` of it.
    budget_cells : int
        With a budget (a time limit or ``section_boxes``), a limited turn's section cells are as wide as the
        greatest distance from the shoulder (half the section's enclosure without a shoulder) over this many,
        whatever ``delta``: the section, and so its volume bracket, no longer depends on the task boxes' size
        (:func:`~workspace_sym.serial.turn.budgeted_width`; 66 gives the LBR iiwa and the Panda the cells of
        ``delta = 0.1``).
    shoulder_pieces : int
        The undecided cells of a limited turn are cut this many times along each axis for the volume's upper
        bound.
    cells_max_joints : int
        A turned section proving no inner box gives way to the 3-D cells of the critical method up to this
        many moving joints (a square map: docs/methods.md section 5 has the measured costs).
    cell_chunk : int
        Marked cells of the 3-D critical method proved between two looks at the budget.
    wrist_cells, wrist_grid : int
        With a tool constraint: wrist boxes examined per arm box at once, and wrist values per joint tried
        first for a witness of the cone.
    pose_timed_cells, pose_timed_seconds : int, float
        With a tool constraint and a time limit of ``pose_timed_seconds`` or more left after the symbolic
        preparation, the constrained section is paved toward cells as wide as the longest side of its enclosure
        over ``pose_timed_cells`` (or those of ``delta``, when finer), whatever ``delta``; with less time, over
        that many times the square root of the share of ``pose_timed_seconds`` left (a grid of fewer cells).
    pose_section_share : float
        ... and until this share of the time left after the symbolic preparation; the task boxes take the rest.

    Raises
    ------
    InvalidParameterError
        A whole-number field that is not an int of at least 1 (at least 0 for the depths), or another field that
        is not a finite positive number.

    Examples
    --------
    >>> Tuning().section_ratio, Tuning(inner_depth=1).inner_depth
    (0.25, 1)
    >>> Tuning(section_ratio=0)
    Traceback (most recent call last):
    ...
    workspace_sym.errors.InvalidParameterError: section_ratio must be a positive number; got 0
    """

    max_pairs: int = 200_000
    inner_depth: int = 2
    pose_max_pairs: int = 400_000
    pose_inner_depth: int = 1
    min_pairs: int = 64
    section_ratio: float = 0.25
    section_reserve: float = 1.5
    section_pairs: int = 60_000
    section_samples: int = 400_000
    section_chunk: int = 2_000
    blocks_share: float = 0.5
    blocks_weight: float = 2.0
    reach_tolerance: float = 0.2
    section_depth: int = 6
    direction_chunk: int = 2_000
    direction_samples: int = 400_000
    flange_directions: float = 0.5
    flange_pairs: int = 240_000
    cone_directions: float = 0.85
    flange_section_share: float = 0.95
    direction_depth: int = 2
    timed_depth: int = 3
    directions_share: float = 0.75
    blocks_end: float = 0.92
    budget_cells: int = 66
    shoulder_pieces: int = 8
    cells_max_joints: int = 3
    cell_chunk: int = 2_000
    wrist_cells: int = 64
    wrist_grid: int = 9
    pose_timed_cells: int = 4096
    pose_timed_seconds: float = 120.0
    pose_section_share: float = 0.8

    def __post_init__(self):
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            whole = f.type == "int"
            least = 0 if f.name in ("inner_depth", "pose_inner_depth", "section_depth", "direction_depth",
                                    "timed_depth") else 1
            if whole and (not isinstance(value, int) or isinstance(value, bool) or value < least):
                raise InvalidParameterError(f"{f.name} must be a whole number, {least} or more; got {value!r}",
                                            parameter=f.name)
            if not whole and (not isinstance(value, (int, float)) or isinstance(value, bool) or not value > 0
                              or value != value or value == float("inf")):
                raise InvalidParameterError(f"{f.name} must be a positive number; got {value!r}", parameter=f.name)

    def replace(self, **changes) -> Tuning:
        """This tuning with ``changes`` (checked as at construction).

        Parameters
        ----------
        **changes
            New values of fields, by name.

        Returns
        -------
        Tuning
            A new tuning; this one is unchanged.

        Raises
        ------
        InvalidParameterError
            A new value refused as at construction.
        TypeError
            A name that is not a field.
        """
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict:
        """The fields by name, for the fingerprint of a run (:func:`~workspace_sym.serial.stored.reach_problem`).

        Returns
        -------
        dict
            Every field and its value.
        """
        return dataclasses.asdict(self)


#: The tuning every run uses unless given another.
DEFAULT = Tuning()
