"""neurov sets the numerical libraries' thread count where it matters: an
identification fit runs with one BLAS thread whatever the environment says,
and gives back the count it found."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from threadpoolctl import threadpool_info, threadpool_limits

from neurov.threads import one_blas_thread


def _blas_threads() -> set[int]:
    return {lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"}


def test_one_blas_thread_inside_and_the_count_restored_after() -> None:
    if not _blas_threads():
        pytest.skip("no BLAS library loaded by numpy here")
    with threadpool_limits(limits=2, user_api="blas"):
        seen: list[set[int]] = []
        product = one_blas_thread(lambda a: (seen.append(_blas_threads()), a @ a)[1])(np.eye(3))
        assert seen == [{1}] and np.array_equal(product, np.eye(3))
        assert _blas_threads() == {2}


def test_the_identification_fit_runs_on_one_blas_thread(monkeypatch: pytest.MonkeyPatch) -> None:
    from identify_runs import excitation_run

    from neurov.config.vehicle_file import preset_path
    from neurov.identification import fit
    from neurov.identification.neurov_log import log_from_result

    seen: list[set[int]] = []
    original = fit._fit_stages

    def watched(*args: Any, **kwargs: Any) -> Any:
        seen.append(_blas_threads())
        return original(*args, **kwargs)

    monkeypatch.setattr(fit, "_fit_stages", watched)
    with threadpool_limits(limits=2, user_api="blas"):
        fit.identify(log_from_result(excitation_run("nerov", 20.0)), preset_path("nerov"), output_error=False,
                     replicates=20)
    assert seen and all(s <= {1} for s in seen)
