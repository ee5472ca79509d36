"""Readers of robot descriptions: DH tables, URDF (and xacro) files and MuJoCo models as exact DH robots.

Every reader returns a :class:`~workspace_sym.kinematics.DHRobot`, reads every string through
:mod:`workspace_sym.expressions` and every float through :class:`workspace_sym.snap.Snapper`, treats every file as
untrusted data and raises a :class:`~workspace_sym.errors.DHTableError` (or its subclass
:class:`~workspace_sym.errors.URDFError`, :class:`~workspace_sym.errors.MJCFError`) naming the API parameter.  The
rooms, from the bottom up:

* :mod:`.dh_file`: DH tables in JSON (:func:`read_dh`, :func:`read_dh_file`);
* :mod:`.chain`: joint axes to DH rows, a chain of URDF-shaped joints as an exact standard-DH robot with base and
  tool transforms (:func:`~.chain.dh_robot`);
* :mod:`.xacro`: xacro files expanded into URDF, only a file named ``*.xacro`` (it is a program);
* :mod:`.urdf`: URDF files (:func:`read_urdf`): the chain between two links, handed to :mod:`.chain`;
* :mod:`.mjcf`: MuJoCo models (:func:`read_mjcf`): bodies and joints as URDF-shaped joints, handed to :mod:`.chain`.

The readers build on :mod:`workspace_sym.kinematics`, which does not import them: importing this package
registers them in :data:`workspace_sym.kinematics.READERS`, where ``DHRobot.from_dict``, ``from_file``,
``from_urdf`` and ``from_mjcf`` look them up (``import workspace_sym`` imports this package).
"""

from ..kinematics import READERS
from .dh_file import read_dh, read_dh_file
from .mjcf import read_mjcf
from .urdf import read_urdf

__all__ = ["read_dh", "read_dh_file", "read_urdf", "read_mjcf"]

READERS.update(dh=read_dh, dh_file=read_dh_file, urdf=read_urdf, mjcf=read_mjcf)
