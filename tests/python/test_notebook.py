"""The quickstart notebook runs from top to bottom (what a reader will do first)."""
import os
import sys

import nbformat
from nbclient import NotebookClient

from conftest import ROOT


def test_quickstart_notebook_runs():
    nb = nbformat.read(ROOT / "examples" / "quickstart.ipynb", as_version=4)
    os.environ["PYTHONPATH"] = os.pathsep.join(sys.path)  # the kernel imports the module under test
    NotebookClient(nb, timeout=120, kernel_name="python3", resources={"metadata": {"path": str(ROOT)}}).execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    assert any("image/png" in o.get("data", {}) for o in outputs)  # the plots were drawn
