"""The DH file reader, under its earlier module name.

The reader is :mod:`workspace_sym.readers.dh_file`; this module keeps the names its users imported from here.
"""

from .readers.dh_file import read_dh, read_dh_file

__all__ = ["read_dh", "read_dh_file"]
