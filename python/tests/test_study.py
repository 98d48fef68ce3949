"""`beltrami.study`: the command line's study, with a Python-registered weight scheme."""

from __future__ import annotations

import csv
import pathlib

import pytest

import beltrami as bt

QUICK = {
    "surfaces": ["sphere"],
    "iterations": [10, 20],
    "seeds": 1,
    "small": True,
    "no_countermeasures": True,
}


def half_cotangent(h):
    return 0.25 * (h["opposite_cotangent"] + h["opposite_cotangent"][h["twin"]])


def test_a_study_writes_its_report_and_says_what_it_wrote(tmp_path):
    out = tmp_path / "study"
    result = bt.study(out, weights=["cotangent", "uniform"], **QUICK)
    assert pathlib.Path(result["out"]) == out
    files = [pathlib.Path(f) for f in result["files"]]
    assert files == sorted(files) and all(f.is_file() for f in files)
    names = {f.relative_to(out).as_posix() for f in files}
    assert {"report.md", "results.csv", "results.json", "renders/sphere.png"} <= names
    assert pathlib.Path(result["report"]) == out / "report.md"
    assert result["surfaces"] == ["sphere"]
    assert result["schemes"] == ["cotangent", "uniform"]
    with open(out / "results.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert result["observations"] == len(rows) > 0
    assert sum(result["verdicts"].values()) == len(result["findings"]) > 0
    ids = [f["id"] for f in result["findings"]]
    assert len(set(ids)) == len(ids)
    for finding in result["findings"]:
        assert finding["verdict"] in result["verdicts"]
        assert finding["claim"] and finding["evidence"] is not None
    # One surface cannot decide the statements about the others.
    assert result["verdicts"]["not evaluated"] > 0


def test_a_registered_python_scheme_runs_in_the_study(tmp_path):
    if "half-cotangent" not in bt.weight_schemes():
        bt.register_weight("half-cotangent", half_cotangent)
    result = bt.study(tmp_path / "s", weights=["half-cotangent", "cotangent"], **QUICK)
    assert result["schemes"] == ["half-cotangent", "cotangent"]
    with open(tmp_path / "s" / "results.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    half = [r for r in rows if r["scheme"] == "half-cotangent"]
    full = [r for r in rows if r["scheme"] == "cotangent"]
    assert len(half) == len(full) > 0
    # Halving every weight (exact in binary) leaves the weight-sum rows as they are:
    # the same deviations, to the last digit.
    for a, b in zip(half, full):
        assert (a["iteration"], a["rms"], a["max"]) == (b["iteration"], b["rms"], b["max"])


def test_a_failing_python_scheme_raises_its_exception(tmp_path):
    def broken(h):
        raise ZeroDivisionError("no weights today")

    if "broken-study" not in bt.weight_schemes():
        bt.register_weight("broken-study", broken)
    with pytest.raises(ZeroDivisionError, match="no weights today"):
        bt.study(tmp_path / "s", weights=["broken-study"], **QUICK)
    assert not (tmp_path / "s").exists()


def test_bad_options_are_value_errors_before_anything_is_written(tmp_path):
    out = tmp_path / "s"
    for options, message in [
        ({"surfaces": ["teapot"]}, "teapot"),
        ({"weights": ["nonesuch"]}, "nonesuch"),
        ({"boundary": "loose"}, "boundary must be one of"),
        ({"update": "never"}, "update must be one of"),
        ({"iterations": [20, 10]}, "ascending"),
        ({"lam": 1.5}, "1.5"),
    ]:
        with pytest.raises(ValueError, match=message):
            bt.study(out, **{**QUICK, **options})
        assert not out.exists()
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "mine.txt").write_text("keep")
    with pytest.raises(ValueError, match="does not write"):
        bt.study(foreign, **QUICK)
    assert (foreign / "mine.txt").read_text() == "keep"


def test_every_signature_shows_its_real_defaults():
    # help() and IDEs read inspect.signature: no default may show as Ellipsis.
    import inspect

    for name in dir(bt):
        obj = getattr(bt, name)
        if name.startswith("_") or not callable(obj) or isinstance(obj, type):
            continue
        try:
            signature = inspect.signature(obj)
        except (TypeError, ValueError):
            continue
        for p in signature.parameters.values():
            assert p.default is not Ellipsis, f"{name}({p.name}=...)"
        # And a documentation of its own (a text signature alone is not help).
        assert obj.__doc__ and len(obj.__doc__.strip()) > 40, name
    study = inspect.signature(bt.study).parameters
    assert study["iterations"].default == (10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 200)
    assert study["seeds"].default == 3
    assert inspect.signature(bt.residual).parameters["smr"].default == ()
