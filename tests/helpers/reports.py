"""Reports read back as the package built them: the :class:`~workspace_sym.document.Document` a report function
rendered, so that a test can compare its equations and cells as SymPy objects with an independent reference."""

import pytest


def report_with_document(make, folder):
    """Run ``make(folder)`` (a report function) and return its result with the Document it wrote."""
    import workspace_sym.report as report

    seen = []
    write = report.Document.write

    def keep(self, *args, **kwargs):
        seen.append(self)
        return write(self, *args, **kwargs)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(report.Document, "write", keep)
        path = make(folder)
    return path, seen[0]
