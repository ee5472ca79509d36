"""The URDF reader, under its earlier module name.

The reader is :mod:`workspace_sym.readers.urdf` (xacro files: :mod:`workspace_sym.readers.xacro`; the DH
extraction: :mod:`workspace_sym.readers.chain`); this module keeps the names its users imported from here.
"""

from .readers.urdf import MOVING, UNSUPPORTED, read_urdf

__all__ = ["read_urdf", "MOVING", "UNSUPPORTED"]
