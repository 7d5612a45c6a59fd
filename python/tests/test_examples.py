"""The notebook-style example runs and draws its figure."""
import os
import runpy
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def test_the_scooter_example_draws_one_panel_per_family(tmp_path, monkeypatch):
    figure = tmp_path / "errors.png"
    monkeypatch.setenv("PENDTILT_EXAMPLE_DURATION", "10")
    monkeypatch.setenv("PENDTILT_EXAMPLE_FIGURE", str(figure))
    monkeypatch.delenv("DISPLAY", raising=False)
    g = runpy.run_path(str(EXAMPLES / "scooter.py"), run_name="__main__")
    assert figure.stat().st_size > 10_000
    assert len(g["fig"].axes) == len(g["families"]) == 5
    assert g["est"].rms["ekf"] < g["est"].rms["accel"]
