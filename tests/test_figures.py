"""Figures: labels that do not collide, no degenerate panels (issue 12). Matplotlib only,
on hand-made results (the figures read result dicts and never call a solver)."""
from __future__ import annotations

import numpy as np
import pytest

from validation import figures


def _loop(FN):
    t = np.arange(81) / 80
    return {"t": (2 + t).tolist(), "du": (1e-8 * np.sin(2 * np.pi * t)).tolist(),
            "Fx": (0.05 * np.sin(2 * np.pi * t)).tolist(), "FN": list(np.broadcast_to(FN(t), t.shape))}


def _result(FN):
    r = np.linspace(0, 3e-5, 50)
    prof = {"r": r.tolist(), "pressure": (3e8 * np.sqrt(np.clip(1 - (r / 2.7e-5) ** 2, 0, None))).tolist(),
            "traction": (1e7 * np.ones_like(r)).tolist(), "r_pairs": r.tolist()}
    rows = [{"side": side, "runtime_s": t, "error_vs_closed_form": e, "error_vs_fe": None}
            for side, t, e in (("mdr", 0.19, 1e-3), ("mdr", 0.25, 1.5e-4), ("mdr", 0.35, 1.02e-3),
                               ("fem", 1.4, 3.5e-3), ("fem", 2.2, 2.2e-3), ("fem", 3.3, 1.3e-4))]
    return {"scene": {"name": "test"}, "closed_form": None, "speed_error": rows,
            "mdr": {"cells": 1600, "loop": _loop(FN), "profiles": prof},
            "fem": {"h_contact": 1 / 80, "loop": _loop(FN), "profiles": prof}}


@pytest.fixture
def kept(monkeypatch):
    """The figures of a call, kept open (figures.save closes them) and drawn."""
    figs = {}

    def save(fig, path):
        fig.canvas.draw()
        figs[str(path).rsplit("/", 1)[-1]] = fig
        buf = fig.canvas.buffer_rgba()
        assert np.asarray(buf).std() > 2.0  # not blank
        return str(path).rsplit("/", 1)[-1]

    monkeypatch.setattr(figures, "save", save)
    yield figs
    for f in figs.values():
        figures.plt.close(f)


def _overlaps(fig):
    """Pairs of visible tick labels of one axis whose boxes overlap."""
    r = fig.canvas.get_renderer()
    bad = []
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            lab = [t for t in axis.get_ticklabels(which="both") if t.get_visible() and t.get_text()]
            boxes = [t.get_window_extent(r) for t in lab]
            for i in range(len(boxes)):
                for j in range(i + 1, len(boxes)):
                    if boxes[i].overlaps(boxes[j]):
                        bad.append((lab[i].get_text(), lab[j].get_text()))
    return bad


def test_constant_normal_force_shows_fx_over_time_not_a_vertical_line(kept, tmp_path):
    figures.scene_figures(_result(lambda t: 0.5), tmp_path)
    ax = kept["loops.png"].axes[1]
    assert "time" in ax.get_xlabel()
    assert any("F_N constant = 0.5 N" in t.get_text() for t in ax.texts)
    assert not _overlaps(kept["loops.png"])


def test_varying_normal_force_plots_fx_against_fn_without_offset(kept, tmp_path):
    figures.scene_figures(_result(lambda t: 0.5 + 0.1 * np.sin(2 * np.pi * t)), tmp_path)
    ax = kept["loops.png"].axes[1]
    assert ax.get_xlabel() == "F_N (N)"
    assert ax.xaxis.get_offset_text().get_text() == ""


def test_speed_error_tick_labels_do_not_collide(kept, tmp_path):
    figures.scene_figures(_result(lambda t: 0.5), tmp_path)
    fig = kept["speed_error.png"]
    assert not _overlaps(fig)
    labels = [t.get_text() for t in fig.axes[0].xaxis.get_ticklabels() if t.get_visible() and t.get_text()]
    assert len(labels) >= 2  # an axis of less than a decade still has labels


def test_slip_index_plot_has_a_sensible_minimum_span(tmp_path, monkeypatch):
    # quick mode: one scene, MDR and FE 7e-5 apart; the axis must not zoom to that gap
    captured = {}
    orig = figures.save

    def save(fig, path):
        captured["ylim"] = fig.axes[0].get_ylim()
        return orig(fig, path)

    monkeypatch.setattr(figures, "save", save)
    figures.series_figure({"mdr": [(2e-5, 0.019436)], "fem": [(2e-5, 0.019369)]}, "b (m)",
                          tmp_path / "delta_vs_b.png")
    lo, hi = captured["ylim"]
    assert hi - lo >= figures.MIN_DELTA_SPAN and lo <= 0.019369 and hi >= 0.019436
    assert (tmp_path / "delta_vs_b.png").stat().st_size > 0
