"""The catalog: every built-in robot, with its units, source and joint limits in one place.

Each :class:`CatalogEntry` builds its model on demand (``entry.build()``), so
listing the catalog costs nothing.  Other modules register their own models
(planar chains, parallel robots) with :func:`register`.
"""

from __future__ import annotations

import difflib
from collections.abc import Callable
from dataclasses import dataclass, field

import sympy as sp

from .errors import UnknownNameError
from .kinematics import DHJoint, DHRobot

__all__ = ["CatalogEntry", "register", "get", "build", "catalog", "glass_handling_arm", "puma560", "scara",
           "planar_2r", "planar_3r"]

# Entries build on demand; a parallel model imports its module only when built.

deg = sp.pi / 180


@dataclass(frozen=True, slots=True)
class CatalogEntry:
    """One built-in robot.

    ``parameters`` maps parameter names to their default values (in ``units``);
    ``limits`` describes the joint limits as text, the way a table prints them.

    Parameters
    ----------
    name : str
        The catalog name (``"puma560"``).
    kind : str
        The structure, as text (``"serial (DH, 6R)"``).
    source : str
        The publication or data sheet the model comes from.
    units : str
        The unit of lengths.
    summary : str
        One line on the robot.
    factory : callable
        ``factory(**overrides)`` builds the model.
    parameters : dict, optional
        Parameter name -> default value; the only names :meth:`build` accepts.
    limits : str, optional
        The joint limits as text.

    Raises
    ------
    UnknownNameError
        From :meth:`build`, for an override that is not a parameter (the constructor checks nothing).
    """

    name: str
    kind: str
    source: str
    units: str
    summary: str
    factory: Callable[..., object] = field(repr=False)
    parameters: dict = field(default_factory=dict)
    limits: str = ""

    def build(self, **overrides):
        """Build the model; keyword arguments override default parameters (an unknown name is refused, not
        ignored).

        Parameters
        ----------
        **overrides
            Values of parameters named in :attr:`parameters`.

        Returns
        -------
        object
            What ``factory`` builds: a :class:`~workspace_sym.kinematics.DHRobot`, a
            :class:`~workspace_sym.parallel.ConstraintModel` or an :class:`~workspace_sym.orthoglide.Orthoglide`
            for the built-in entries.

        Raises
        ------
        UnknownNameError
            When an override is not one of :attr:`parameters`, naming it and listing them; the factory may
            refuse a value with its own error.
        """
        unknown = sorted(set(overrides) - set(self.parameters))
        if unknown:
            known = ", ".join(self.parameters) or "none"
            raise UnknownNameError(f"robot {self.name!r} has no parameter {unknown[0]!r} (value "
                                   f"{overrides[unknown[0]]!r}); its parameters are: {known}")
        return self.factory(**overrides)


_CATALOG: dict[str, CatalogEntry] = {}


def register(entry: CatalogEntry) -> CatalogEntry:
    """Add an entry to the catalog (name clashes are programming errors).

    Parameters
    ----------
    entry : CatalogEntry
        The entry; its name must be new.

    Returns
    -------
    CatalogEntry
        ``entry`` itself.

    Raises
    ------
    ValueError
        When an entry of that name is already registered.
    """
    if entry.name in _CATALOG:
        raise ValueError(f"catalog entry {entry.name!r} registered twice")
    _CATALOG[entry.name] = entry
    return entry


def catalog() -> list[CatalogEntry]:
    """Every entry, in registration order.

    Returns
    -------
    list of CatalogEntry
        A new list.
    """
    return list(_CATALOG.values())


def get(name: str) -> CatalogEntry:
    """Entry by name; :class:`UnknownNameError` lists the known names otherwise.

    Parameters
    ----------
    name : str
        The catalog name, exactly.

    Returns
    -------
    CatalogEntry
        The entry.

    Raises
    ------
    UnknownNameError
        When no entry has that name.
    """
    try:
        return _CATALOG[name]
    except KeyError:
        known = ", ".join(sorted(_CATALOG))
        hint = "".join(f"did you mean {guess!r}? " for guess in _close_names(name)[:1])
        raise UnknownNameError(f"robot {name!r} is not in the catalog; {hint}known robots: {known}",
                               parameter="robot") from None


def _close_names(name) -> list[str]:
    """Catalog names close to ``name``: case, underscores and spaces ignored, then difflib's closest ones."""
    if not isinstance(name, str):
        return []
    by_key = {key.lower().replace("_", "-"): key for key in _CATALOG}
    typed = name.strip().lower().replace("_", "-").replace(" ", "-")
    if typed in by_key:
        return [by_key[typed]]
    return [by_key[key] for key in difflib.get_close_matches(typed, list(by_key), n=3, cutoff=0.6)]


def build(name: str, **overrides):
    """Build the model of a catalog entry.

    Parameters
    ----------
    name : str
        The catalog name.
    **overrides
        Parameters of the entry overriding their defaults (:meth:`CatalogEntry.build`).

    Returns
    -------
    object
        The model.

    Raises
    ------
    UnknownNameError
        When the name is not in the catalog or an override is not a parameter of the entry.
    """
    return get(name).build(**overrides)


def _revolute_chain(rows, limits_deg):
    """Revolute joints 1..n from DH rows (keyword dicts) and (lower, upper) limits in degrees."""
    return [DHJoint.revolute(k + 1, limits=(lo * deg, hi * deg), **row)
            for k, (row, (lo, hi)) in enumerate(zip(rows, limits_deg))]


# ---------------------------------------------------------------------------- glass-handling arm
GLASS_DEFAULTS = {"d1": 0.30, "a1": 0.05, "a2": 0.25, "a3": 0.20, "d5": 0.10}
"""Default lengths (m) for plots and numbers.

Paper 004 gives no numeric lengths; these are our choice, the proportions of a
desktop teaching arm of the same structure (shoulder offset, two equal-order
links, short wrist).  Every symbolic result keeps ``d1, a1, a2, a3, d5``.
"""

GLASS_LIMITS_DEG = [(-160, 160), (-30, 120), (-130, 130), (-130, 130), (-180, 180), (-180, 180)]
"""Joint ranges of paper 004, section 7 (theta1 to theta4); theta5 and theta6 (roll of
the wrist and gripper) are not limited in the paper and get the full turn."""


def glass_handling_arm(**parameters) -> DHRobot:
    """6R glass-handling arm of Mohammadi & Mirnajafizade (2016), standard DH (docs/methods.md section 1).

    Parameters
    ----------
    **parameters
        Numeric values of the symbolic lengths (d1, a1, a2, a3, d5; defaults :data:`GLASS_DEFAULTS`), in metres,
        overriding the defaults (names are not checked here; :func:`build` refuses unknown ones).

    Returns
    -------
    DHRobot
        The model, with symbolic lengths and ``parameters`` holding their numeric values.

    Examples
    --------
    >>> robot = glass_handling_arm()
    >>> robot.to_str(robot.position[0])
    'c1*(a1 + a2*c2 + a3*c23 + d5*s234)'
    """
    d1, a1, a2, a3, d5 = sp.symbols("d1 a1 a2 a3 d5")
    rows = [dict(d=d1, a=a1, alpha=sp.pi / 2), dict(a=a2), dict(a=a3), dict(alpha=sp.pi / 2), dict(d=d5), dict()]
    return DHRobot(_revolute_chain(rows, GLASS_LIMITS_DEG), name="glass-handling",
                   parameters={**GLASS_DEFAULTS, **parameters}, units="m")


register(CatalogEntry(
    name="glass-handling", kind="serial (DH, 6R)",
    source="B. Mohammadi, S. A. Mirnajafizade, A six degrees of freedom robot for limited movement of objects, 2016",
    units="m", summary="glass-handling arm; symbolic lengths d1, a1, a2, a3, d5 (defaults are ours, not the paper's)",
    factory=glass_handling_arm, parameters=GLASS_DEFAULTS,
    limits="theta1 [-160, 160], theta2 [-30, 120], theta3 [-130, 130], theta4 [-130, 130], theta5, theta6 free (deg)",
))


# ---------------------------------------------------------------------------- Puma 560
PUMA_DEFAULTS = {"a2": 0.4318, "a3": 0.0203, "d3": 0.15005, "d4": 0.4318}
PUMA_LIMITS_DEG = [(-160, 160), (-110, 110), (-135, 135), (-266, 266), (-100, 100), (-266, 266)]


def puma560(**parameters) -> DHRobot:
    """Unimation Puma 560, standard DH, lengths of Corke & Armstrong-Helouvry (1994), as in
    the Robotics Toolbox model: a2 = 0.4318, a3 = 0.0203, d3 = 0.15005, d4 = 0.4318 m.

    Parameters
    ----------
    **parameters
        Numeric values of the symbolic lengths (a2, a3, d3, d4), in metres, overriding the defaults (names are
        not checked here; :func:`build` refuses unknown ones).

    Returns
    -------
    DHRobot
        The model, with symbolic lengths and ``parameters`` holding their numeric values.
    """
    a2, a3, d3, d4 = sp.symbols("a2 a3 d3 d4")
    rows = [dict(alpha=sp.pi / 2), dict(a=a2), dict(d=d3, a=a3, alpha=-sp.pi / 2), dict(d=d4, alpha=sp.pi / 2),
            dict(alpha=-sp.pi / 2), dict()]
    return DHRobot(_revolute_chain(rows, PUMA_LIMITS_DEG), name="puma560",
                   parameters={**PUMA_DEFAULTS, **parameters}, units="m")


register(CatalogEntry(
    name="puma560", kind="serial (DH, 6R)",
    source=("P. Corke, B. Armstrong-Helouvry, A search for consensus among model parameters reported for the "
            "PUMA 560 robot, ICRA 1994"),
    units="m", summary="Unimation Puma 560, standard DH", factory=puma560, parameters=PUMA_DEFAULTS,
    limits="[-160, 160], [-110, 110], [-135, 135], [-266, 266], [-100, 100], [-266, 266] (deg)",
))


# ---------------------------------------------------------------------------- SCARA
SCARA_DEFAULTS = {"d1": 0.387, "a1": 0.325, "a2": 0.275}


def scara(**parameters) -> DHRobot:
    """RRPR SCARA with the dimensions of the Adept Cobra 600 (standard DH, alpha2 = pi so
    that the prismatic joint moves down): reach 0.325 + 0.275 m, stroke 0.210 m.

    Parameters
    ----------
    **parameters
        Numeric values of the symbolic lengths (d1 = 0.387, a1 = 0.325, a2 = 0.275 by default), in metres,
        overriding the defaults (names are not checked here; :func:`build` refuses unknown ones).

    Returns
    -------
    DHRobot
        The model, with symbolic lengths and ``parameters`` holding their numeric values.
    """
    d1, a1, a2 = sp.symbols("d1 a1 a2")
    joints = [
        DHJoint.revolute(1, d=d1, a=a1, limits=(-50 * deg, 50 * deg)),
        DHJoint.revolute(2, a=a2, alpha=sp.pi, limits=(-88 * deg, 88 * deg)),
        DHJoint.prismatic(3, limits=(0, sp.Rational(21, 100))),
        DHJoint.revolute(4, limits=(-sp.pi, sp.pi)),
    ]
    return DHRobot(joints, name="scara", parameters={**SCARA_DEFAULTS, **parameters}, units="m")


register(CatalogEntry(
    name="scara", kind="serial (DH, RRPR)", source="Adept Cobra 600 data sheet dimensions",
    units="m", summary="SCARA, prismatic third joint", factory=scara, parameters=SCARA_DEFAULTS,
    limits="theta1 [-50, 50] deg, theta2 [-88, 88] deg, d3 [0, 0.21] m, theta4 [-180, 180] deg",
))


# ---------------------------------------------------------------------------- planar 2R / 3R
def planar_2r(**parameters) -> DHRobot:
    """Planar 2R arm with symbolic lengths l1, l2 (defaults 1 and 1/2), joints free.

    Parameters
    ----------
    **parameters
        Numeric values of the symbolic lengths (l1, l2), in metres, overriding the defaults (names are not
        checked here; :func:`build` refuses unknown ones).

    Returns
    -------
    DHRobot
        The model, with symbolic lengths and ``parameters`` holding their numeric values.
    """
    l1, l2 = sp.symbols("l1 l2")
    joints = [DHJoint.revolute(1, a=l1, limits=(-sp.pi, sp.pi)), DHJoint.revolute(2, a=l2, limits=(-sp.pi, sp.pi))]
    return DHRobot(joints, name="planar-2r", parameters={"l1": 1.0, "l2": 0.5, **parameters}, units="m")


def planar_3r(**parameters) -> DHRobot:
    """Planar 3R arm with symbolic lengths l1, l2, l3 (defaults 1, 1/2, 1/4), joints free.

    Parameters
    ----------
    **parameters
        Numeric values of the symbolic lengths (l1, l2, l3), in metres, overriding the defaults (names are not
        checked here; :func:`build` refuses unknown ones).

    Returns
    -------
    DHRobot
        The model, with symbolic lengths and ``parameters`` holding their numeric values.
    """
    ls = sp.symbols("l1:4")
    joints = [DHJoint.revolute(k + 1, a=l, limits=(-sp.pi, sp.pi)) for k, l in enumerate(ls)]
    return DHRobot(joints, name="planar-3r", parameters={"l1": 1.0, "l2": 0.5, "l3": 0.25, **parameters},
                   units="m")


register(CatalogEntry(
    name="planar-2r", kind="serial (DH, planar 2R)", source="textbook example", units="m",
    summary="planar two-link arm", factory=planar_2r, parameters={"l1": 1.0, "l2": 0.5},
    limits="[-180, 180] deg each",
))
register(CatalogEntry(
    name="planar-3r", kind="serial (DH, planar 3R)", source="textbook example", units="m",
    summary="planar three-link arm", factory=planar_3r, parameters={"l1": 1.0, "l2": 0.5, "l3": 0.25},
    limits="[-180, 180] deg each",
))


# ---------------------------------------------------------------------------- parallel robots
def _rpr2(**parameters):
    from .parallel import rpr2

    return rpr2(**parameters)


register(CatalogEntry(
    name="rpr2", kind="parallel (planar 2-RPR, constraints)",
    source="L. A. Rybak, M. A. Posypkin, A. V. Turkin, Method for approximating the workspace of the parallel robot, "
           "IJPT 2016",
    units="length units of the paper", summary="two prismatic legs from (0, 0) and (l0, 0); box [-12, 17] x [0, 12]",
    factory=_rpr2, parameters={"l0": 5, "lmin": 8, "lmax": 12}, limits="leg lengths in [lmin, lmax]",
))


def _orthoglide(**parameters):
    if parameters:
        raise UnknownNameError(f"orthoglide takes no parameters (leg length is normalised to 1); "
                               f"got {sorted(parameters)}")
    from .orthoglide import Orthoglide

    return Orthoglide()


register(CatalogEntry(
    name="orthoglide", kind="parallel (3-PRPaR, translational)",
    source="D. Chablat, P. Wenger, J.-P. Merlet, Workspace analysis of the Orthoglide using interval analysis, "
           "ARK 2002",
    units="leg lengths (L = 1)", summary="three orthogonal linear joints; dextrous workspace sigma in [1/4, 4]",
    factory=_orthoglide, parameters={"L": 1}, limits="inside the three cylinders x^2 + y^2 <= 1, ...",
))
