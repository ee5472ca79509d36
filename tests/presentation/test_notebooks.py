"""Every notebook in notebooks/ executes without error (they are stored without outputs), shows its mathematics
in a form an exported page renders without a network, and uses no private name."""

import re

import pytest

from paths import ROOT

NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb"))


def test_there_are_notebooks():
    assert NOTEBOOKS


@pytest.mark.slow                    # a kernel per notebook and their computations: a minute (not in make test-fast)
@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_executes(path):
    import nbformat  # here: only the worker that runs the notebooks imports Jupyter's libraries
    from nbclient import NotebookClient
    from nbconvert import HTMLExporter

    nb = nbformat.read(path, as_version=4)
    assert all(not cell.get("outputs") for cell in nb.cells if cell.cell_type == "code")  # stored clean
    code = "\n".join(c.source for c in nb.cells if c.cell_type == "code")
    assert not re.search(r"(\.|import |from \S+ import .*\b)_[a-z]", code)                 # no private names
    NotebookClient(nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(path.parent)}}).execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    # every typeset result carries MathML (text/html), which nbconvert's HTML prefers to text/latex: the exported
    # page does not need MathJax, hence no network, to show the mathematics
    rich = [o for o in outputs if o.output_type in ("display_data", "execute_result")]
    assert all("text/html" in o.data for o in rich if "text/latex" in o.data)
    # Markdown output (IPython.display.Markdown of a sheet) keeps its $...$ for MathJax: plain text offline
    assert not [o for o in rich if "$" in o.data.get("text/markdown", "") and "text/html" not in o.data]
    page, _ = HTMLExporter().from_notebook_node(nb)
    text = re.sub(r"<script.*?</script>", "", page, flags=re.S)
    assert "\\displaystyle" not in text
    # issue 39: teaching.ipynb showed $\theta_{1}$, $\frac{\pi}{2}$ and $$ ... $$ as text; no TeX is left to MathJax
    assert not re.search(r"\$\$|\$\\[a-zA-Z]", text), re.search(r".{60}(\$\$|\$\\[a-zA-Z]).{60}", text, re.S)
    if "Equations" in code or "typeset" in code or path.name == "teaching.ipynb":
        assert "<math" in page
