"""The rank diagnostic of an NN controller's basis along a run: its
definition on known matrices, and in a study: the NN rows get it, the others
NaN, and recording it changes no number of the runs."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from neurov.study import load_study, run_study
from neurov.study.basis_rank import BASIS_COLUMNS, rank_diagnostic

from study_files import STUDY, write_study


def test_rank_diagnostic_of_known_matrices() -> None:
    one = np.outer(np.linspace(1, 2, 50), np.full(8, 0.9))
    d = rank_diagnostic(one)
    assert d["effective_rank"] == pytest.approx(1.0, abs=1e-6) and d["sigma2_ratio"] < 1e-12
    assert (d["min"], d["max"]) == pytest.approx((0.9, 1.8))
    full = np.vstack([np.eye(8)] * 3)
    assert rank_diagnostic(full)["effective_rank"] == pytest.approx(8.0)
    assert rank_diagnostic(full)["sigma2_ratio"] == pytest.approx(1.0)
    assert np.isnan(rank_diagnostic(np.zeros((0, 0)))["effective_rank"])


def test_a_study_records_the_nn_basis_rank_without_changing_a_number(tmp_path: Path) -> None:
    text = STUDY.replace("samples = 4", "samples = 1")
    plain = run_study(load_study(write_study(tmp_path, text)), tmp_path / "a", workers=1, executor="processes",
                      plots=False, progress=False).table
    ranked = run_study(load_study(write_study(tmp_path, text + "\n[diagnostics]\nbasis_rank = true\n", "b.toml")),
                       tmp_path / "b", workers=1, executor="processes", plots=False, progress=False).table
    nn = ranked["controller"] == "nn"
    for col in BASIS_COLUMNS:
        assert ranked.loc[nn, col].notna().all() and ranked.loc[~nn, col].isna().all()
        assert col not in plain.columns
    for col in plain.columns:
        if plain[col].dtype.kind == "f":
            np.testing.assert_array_equal(plain[col].to_numpy(), ranked[col].to_numpy(), err_msg=col)
    # The paper's width (30) on SI inputs: every basis value near 1, one direction.
    assert (ranked.loc[nn, "nn_basis_min"] > 0.8).all()
    assert (ranked.loc[nn, "nn_basis_sigma2_ratio"] < 0.05).all()


def test_normalised_inputs_map_the_centre_box_onto_the_unit_cube() -> None:
    import neurov
    from neurov.laws.registry import default_centre_box, input_normalisation
    from neurov.laws.registry import build_controller

    sc = neurov.load_scenario(Path(neurov.__file__).parent / "scenarios" / "paper_fig3.toml")
    spec = sc.controller.replace(width=1.0)
    spec.inputs = "normalised"
    c = build_controller(spec, sc)
    low, high = default_centre_box(sc)
    offset, scale = input_normalisation(sc)
    np.testing.assert_allclose(np.asarray(c.input_offset), (low + high) / 2)
    np.testing.assert_allclose((high - np.asarray(c.input_offset)) * np.asarray(c.input_scale), 1.0)
    centres = np.asarray(c.centres)
    assert centres.min() >= -1.0 and centres.max() <= 1.0
    np.testing.assert_allclose(np.asarray(c.input_scale), scale)
    with pytest.raises(neurov.ScenarioError, match=r"controller\.inputs: expected one of \['si', 'normalised'\]"):
        from neurov.config.reading import scenario_from_mapping

        import tomllib

        data = tomllib.loads((Path(neurov.__file__).parent / "scenarios" / "paper_fig3.toml").read_text())
        data["controller"]["inputs"] = "unit"
        scenario_from_mapping(data, "paper_fig3.toml")
