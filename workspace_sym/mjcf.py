"""The MJCF (MuJoCo) reader, under its earlier module name.

The reader is :mod:`workspace_sym.readers.mjcf`; this module keeps the names its users imported from here.
"""

from .readers.mjcf import read_mjcf

__all__ = ["read_mjcf"]
