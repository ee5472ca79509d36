"""What a stored or resumed artefact names of the problem it belongs to.

A checkpoint, a section kept beside it or a directory of stored boxes holds
proved boxes of one problem: read back for another, they would be returned as
certificates of a set they do not describe.  So every such file carries a
:class:`Fingerprint` of its *whole* problem (for a robot: every DH entry,
joint type, offset and limit, the base and tool transforms, the parameter
values; the constraint or pose; the method, ``delta``, ``size`` and the tuning
that changes boxes), and :func:`check_fingerprint` refuses a file whose
fingerprint differs, naming the fields that differ.

A field's value is reduced to a canonical text (:func:`canonical`: SymPy
objects by ``srepr``, floats by their exact ``repr``, arrays by their bytes)
and kept as its SHA-256, so a file names what it was computed for without
holding it.  :data:`FORMAT` is the version of the files' layout: a file of
another version is refused too.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from typing import Any

import numpy as np
import sympy as sp

from ..errors import InvalidParameterError

__all__ = ["FORMAT", "canonical", "Fingerprint", "check_fingerprint"]

#: Version of the layout of checkpoints, kept sections and box stores (2: every file names its whole problem).
FORMAT = 2


def canonical(value: Any) -> str:
    """A text that is equal for two values exactly when they are the same input.

    SymPy objects are written by ``srepr`` (``Rational(1, 2)`` is not ``Float('0.5')``), floats by their
    shortest exact ``repr``, arrays by dtype, shape and bytes; mappings are sorted by key.

    Parameters
    ----------
    value : object
        A mapping, list, tuple, numpy array, SymPy object or matrix, bool, int, float, str or None, nested
        freely (a tuple and a list of the same entries give the same text).

    Returns
    -------
    str
        The canonical text.  Any other type raises ``TypeError``.

    Examples
    --------
    >>> canonical({"a": 0.1, "b": (1, None)})
    "{'a': 0.1, 'b': [1, None]}"
    >>> canonical(sp.Rational(1, 2)) != canonical(sp.Float(0.5))
    True
    """
    if isinstance(value, Mapping):
        items = sorted(((canonical(k), canonical(v)) for k, v in value.items()))
        return "{" + ", ".join(f"{k}: {v}" for k, v in items) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(canonical(v) for v in value) + "]"
    if isinstance(value, np.ndarray):
        data = np.ascontiguousarray(value)
        return f"array({data.dtype.str}, {data.shape}, {hashlib.sha256(data.tobytes()).hexdigest()})"
    if isinstance(value, sp.Basic) or isinstance(value, sp.MatrixBase):
        return sp.srepr(value)
    if isinstance(value, (bool, np.bool_)):
        return repr(bool(value))
    if isinstance(value, (int, np.integer)):
        return repr(int(value))
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    if value is None or isinstance(value, str):
        return repr(value)
    raise TypeError(f"no canonical text for a {type(value).__name__}")


def _digest(value: Any) -> str:
    return hashlib.sha256(canonical(value).encode()).hexdigest()


class Fingerprint(Mapping):
    """The fields of a problem, each kept as the SHA-256 of its canonical text, and :data:`FORMAT`.

    Parameters
    ----------
    fields : mapping or None
        The fields by name, values of any type :func:`canonical` takes; the field ``format`` (:data:`FORMAT`)
        is added first (a field of that name replaces it).  None: no field but ``format``.
    digests : mapping or None
        The digests by name, as :meth:`to_json` wrote them: taken as they are, and ``fields`` is ignored.

    Examples
    --------
    >>> a = Fingerprint({"delta": 0.1, "limits": [(-1, 1)]})
    >>> b = Fingerprint({"delta": 0.1, "limits": [(-1, 2)]})
    >>> a.differs(b)
    ['limits']
    >>> a == Fingerprint.from_json(a.to_json())
    True
    """

    def __init__(self, fields: Mapping[str, Any] | None = None, *, digests: Mapping[str, str] | None = None):
        if digests is not None:                    # read back from a file: as it was written
            self._digests: dict[str, str] = dict(digests)
            return
        self._digests = {str(k): _digest(v) for k, v in {"format": FORMAT, **dict(fields or {})}.items()}

    def __getitem__(self, key: str) -> str:
        return self._digests[key]

    def __iter__(self):
        return iter(self._digests)

    def __len__(self) -> int:
        return len(self._digests)

    def __eq__(self, other) -> bool:
        return isinstance(other, Fingerprint) and self._digests == other._digests

    __hash__ = None  # type: ignore[assignment]

    def __or__(self, fields: Mapping[str, Any]) -> Fingerprint:
        """This fingerprint with more fields (their values, not digests)."""
        return Fingerprint(digests={**self._digests, **{str(k): _digest(v) for k, v in dict(fields).items()}})

    @property
    def digest(self) -> str:
        """One SHA-256 of every field: equal exactly when every field is."""
        return hashlib.sha256(json.dumps(self._digests, sort_keys=True).encode()).hexdigest()

    def differs(self, other: Mapping[str, str]) -> list[str]:
        """The fields whose digests differ (or that only one of the two has), sorted.

        Parameters
        ----------
        other : mapping
            Another fingerprint, or its digests by name.

        Returns
        -------
        list of str
            The names of the fields.
        """
        theirs = dict(other)
        return sorted(k for k in set(theirs) | set(self._digests) if theirs.get(k) != self._digests.get(k))

    def to_json(self) -> dict[str, str]:
        """The digests by name, for a JSON file.

        Returns
        -------
        dict
            A copy of ``{field: SHA-256 hex digest}``.
        """
        return dict(self._digests)

    @classmethod
    def from_json(cls, data: Any) -> Fingerprint:
        """The fingerprint :meth:`to_json` wrote.

        Parameters
        ----------
        data : object
            What the file holds: a mapping of field names to digests, both text.

        Returns
        -------
        Fingerprint
            The fingerprint.  Anything else raises ``ValueError``.
        """
        if not isinstance(data, Mapping) or not all(isinstance(k, str) and isinstance(v, str)
                                                    for k, v in data.items()):
            raise ValueError("a fingerprint is a mapping of field names to digests")
        return cls(digests=data)

    def __repr__(self) -> str:
        return f"Fingerprint({', '.join(sorted(self._digests))}; {self.digest[:12]})"


def check_fingerprint(stored: Any, expected: Fingerprint, *, what: str, parameter: str = "resume") -> None:
    """Refuse (``InvalidParameterError`` on ``parameter``) an artefact whose stored fingerprint is not ``expected``:
    one of another version of the files, or of another problem, naming the fields that differ.  ``what`` names
    the artefact (``"'run.npz' is the checkpoint"``).

    Parameters
    ----------
    stored : object
        What the artefact holds as its fingerprint (:meth:`Fingerprint.to_json`); anything that is not one
        counts as another version.
    expected : Fingerprint
        The fingerprint of this run.
    what : str
        The start of the error message, naming the artefact.
    parameter : str
        The parameter the error names (default ``"resume"``).

    Raises
    ------
    InvalidParameterError
        When ``stored`` is of another :data:`FORMAT` (or none), or any field differs.

    Examples
    --------
    >>> check_fingerprint({}, Fingerprint({"delta": 0.1}), what="'run.npz' is the checkpoint")
    Traceback (most recent call last):
    ...
    workspace_sym.errors.InvalidParameterError: resume: 'run.npz' is the checkpoint of another version of ...
    >>> check_fingerprint(Fingerprint({"delta": 0.2}).to_json(), Fingerprint({"delta": 0.1}), what="'r.npz' is it")
    Traceback (most recent call last):
    ...
    workspace_sym.errors.InvalidParameterError: resume: 'r.npz' is it of another run (it differs in delta); ...
    """
    try:
        theirs = Fingerprint.from_json(stored)
    except ValueError:
        theirs = Fingerprint(digests={"format": ""})
    if theirs.get("format") != expected["format"]:
        raise InvalidParameterError(f"{parameter}: {what} of another version of workspace_sym (files are now of "
                                    f"format {FORMAT}, which names the whole problem); start the run again",
                                    parameter=parameter)
    differ = expected.differs(theirs)
    if differ:
        raise InvalidParameterError(f"{parameter}: {what} of another run (it differs in {', '.join(differ)}); "
                                    "resume with the same problem, or give another file", parameter=parameter)
