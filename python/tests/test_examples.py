"""The examples run as a user runs them: every code cell of the quick-start notebook in
order, in one namespace (as Jupyter's kernel would)."""

from __future__ import annotations

import json
import pathlib

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"


def test_the_quickstart_notebook_runs(capsys):
    notebook = json.loads((EXAMPLES / "quickstart.ipynb").read_text())
    cells = [c for c in notebook["cells"] if c["cell_type"] == "code"]
    assert len(cells) >= 5
    namespace: dict = {"__name__": "__main__"}
    for i, cell in enumerate(cells):
        exec(compile("".join(cell["source"]), f"quickstart.ipynb[{i}]", "exec"), namespace)
    printed = capsys.readouterr().out
    assert "sq" in printed and "largest difference" in printed and "wrote" in printed
    assert namespace["r"]["sq"] > 0
    assert namespace["heights"].shape == (namespace["scan"].n_vertices,)
