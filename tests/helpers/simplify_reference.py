"""``count_ops(sympy.simplify(e))``, the yardstick of the textbook tests, stored in ``tests/data/simplify_counts.json``.

``sympy.simplify`` of a raw DH product entry takes 0.5 to 1 s (6 to 10 s per arm, most of the time of
tests/kinematics/test_symbolic.py), and for the same expression and the same SymPy it always gives the same
result: a pure reference, never the thing under test (that is ``textbook``/``fk``, computed by each test).

Each stored count is keyed by the SHA-256 of ``srepr(e)`` (the exact raw entry) and of the SymPy version that
computed it; an entry whose expression or SymPy version differs is not found and is computed here, with this SymPy,
as the tests did before.  Regenerate (after a SymPy upgrade or a change of the raw product)::

    WORKSPACE_SYM_STORE_SIMPLIFY=1 .venv/bin/python -m pytest tests/kinematics/test_symbolic.py -k simplify

(no ``-n``: the file is written when the process ends, with every count that process computed or used).
"""

import atexit
import functools
import hashlib
import json
import os

import sympy as sp

from paths import DATA

STORE = DATA / "simplify_counts.json"
_used: dict[str, int] = {}


def _key(expr) -> str:
    return hashlib.sha256(f"sympy {sp.__version__}\n{sp.srepr(expr)}".encode()).hexdigest()


@functools.lru_cache(maxsize=1)
def _stored() -> dict[str, int]:
    try:
        return json.loads(STORE.read_text())["counts"]
    except FileNotFoundError:
        return {}


def simplified_count(expr) -> int:
    """``sympy.count_ops(sympy.simplify(expr))``: stored if this expression and this SymPy computed it, else now."""
    key = _key(expr)
    count = _stored().get(key)
    if count is None:
        count = int(sp.count_ops(sp.simplify(expr)))
    _used[key] = count
    return count


def _write():
    STORE.write_text(json.dumps({"what": "count_ops(simplify(e)) keyed by sha256('sympy <version>\\n' + srepr(e))",
                                 "sympy": sp.__version__, "counts": dict(sorted(_used.items()))}, indent=0) + "\n")


if os.environ.get("WORKSPACE_SYM_STORE_SIMPLIFY"):
    atexit.register(_write)
