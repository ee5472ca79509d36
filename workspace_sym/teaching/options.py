"""The options of the teaching functions: which fields of :class:`~workspace_sym.interval.driver.StopAt` and
:class:`~workspace_sym.interval.driver.RunOn` apply to each, and the keywords of earlier releases.

:func:`~workspace_sym.teaching.checks.check_reachable`, :func:`~workspace_sym.teaching.grading.grade_answers` and
:func:`~workspace_sym.teaching.exercises.make_exercises` take ``stop=StopAt(...)`` as the rest of the package does:
``max_boxes`` and ``time_limit`` are budgets of the whole call.  The two that run long (a batch of answers, a
sheet) take ``run=RunOn(progress=...)`` for their progress bar; they run in this process and keep no boxes.  A
field that a function cannot honour is refused, never ignored.

The three helpers live in :mod:`workspace_sym.interval.driver`, beside the option objects, so that every
layer refuses and deprecates the same way; this module names them for the teaching package.
"""

from __future__ import annotations

from ..interval.driver import deprecated, refuse_run, refuse_stop

__all__ = ["refuse_stop", "refuse_run", "deprecated"]
