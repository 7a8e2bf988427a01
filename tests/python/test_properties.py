"""Property-based tests (Hypothesis) of the Python API: the bad-input
guarantees of the controllers and the reference model (the kinematic
identities and C(nu) are in test_model_properties.py), and that the closed loop allocates nothing per step,
all under generated inputs. Generated cases are few and small (the whole file
runs in seconds); the exhaustive sweeps are in tests/cpp/test_reliability_*.cpp.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, invariant, rule

import neurov
import reference_model as ref
from property_strategies import ARGS, FEW, SETTINGS, finite, poses, vectors, velocities

# ------------------------------------------------------------ bad-input rules

NETWORK_CENTRES = np.random.default_rng(5).uniform(-1.5, 1.5, size=(10, 24))


def make(kind: str) -> Any:
    lam = np.full(6, 0.8)
    kd = np.array([200.0, 200, 200, 50, 50, 50])
    if kind == "nn":
        net = neurov.RbfNetwork(NETWORK_CENTRES, 2.0)
        net.weights = np.random.default_rng(6).normal(scale=10.0, size=(6, 10))
        return neurov.NNAdaptiveController(net, lam, kd, 2.0, 0.2, modification="sigma", sigma_m=0.1)
    if kind == "linear":
        theta = neurov.regressor_parameters(neurov.Vehicle.nerov())
        return neurov.LinearAdaptiveController(lam, kd, 1.0, 0.2, 0.8 * theta)
    if kind == "pid":
        return neurov.PIDController(np.full(6, 100.0), np.full(6, 10.0), kd, np.full(6, 50.0))
    if kind == "smc":
        return neurov.SlidingModeController(lam, kd, np.full(6, 20.0), np.full(6, 0.1),
                                            neurov.regressor_parameters(neurov.Vehicle.nerov()))
    return neurov.PDController(np.full(6, 100.0), kd)


KINDS = ("nn", "linear", "pd", "pid", "smc")


def state(c: Any) -> list[np.ndarray]:
    """Everything a controller exposes that a step may change."""
    out = [np.asarray(v) for _, v in sorted(c.tracking.items())]
    for name in ("weights", "weight_norm", "network_output", "theta", "model_output", "integral"):
        if hasattr(c, name):
            out.append(np.asarray(getattr(c, name), dtype=float))
    return out


def same(a: list[np.ndarray], b: list[np.ndarray]) -> bool:
    # Bit for bit, NaN included.
    return len(a) == len(b) and all(x.tobytes() == y.tobytes() for x, y in zip(a, b))


@st.composite
def step_args(draw: st.DrawFn) -> dict[str, np.ndarray]:
    eta = draw(poses(pitch=finite(-1.2, 1.2)))
    eta[:3] = np.clip(eta[:3], -5, 5)
    return {
        "eta": eta,
        "nu": draw(vectors(6, -1.0, 1.0)),
        "eta_d": eta + draw(vectors(6, -0.3, 0.3)),
        "eta_d_dot": draw(vectors(6, -0.5, 0.5)),
        "eta_d_ddot": draw(vectors(6, -0.5, 0.5)),
    }


def after_one_step(
    kind: str, args: dict[str, np.ndarray], arg: str, index: int, value: float
) -> tuple[Any, list[np.ndarray], dict[str, np.ndarray]]:
    """A controller after one step on `args`, its state, and a copy of `args`
    with args[arg][index] = value."""
    c = make(kind)
    c.step(**args)
    changed = {k: v.copy() for k, v in args.items()}
    changed[arg][index] = value
    return c, state(c), changed


@SETTINGS
@given(st.sampled_from(KINDS), step_args(), st.sampled_from(ARGS), st.integers(0, 5),
       st.sampled_from([np.nan, np.inf, -np.inf]))
def test_non_finite_input_is_refused_naming_it_and_changes_nothing(
    kind: str, args: dict[str, np.ndarray], arg: str, index: int, bad: float
) -> None:
    c, before, broken = after_one_step(kind, args, arg, index, bad)
    with pytest.raises(ValueError, match=f"'{arg}'.*finite"):
        c.step(**broken)
    assert same(state(c), before)


@SETTINGS
@given(st.sampled_from(KINDS), step_args(), st.sampled_from(ARGS), st.integers(0, 5),
       st.one_of(finite(-1e308, 1e308), st.sampled_from([1e308, -1e308, 1e154, 5e-324])))
def test_extreme_finite_input_gives_finite_tau_or_a_refusal_that_changes_nothing(
    kind: str, args: dict[str, np.ndarray], arg: str, index: int, value: float
) -> None:
    c, before, args = after_one_step(kind, args, arg, index, value)
    try:
        tau = c.step(**args)
    except ValueError as e:
        assert "refused" in str(e) and "unchanged" in str(e), str(e)
        assert same(state(c), before)
    else:
        assert np.all(np.isfinite(tau))
        for x in state(c):
            assert np.all(np.isfinite(x))


@SETTINGS
@given(st.sampled_from(KINDS), step_args(), finite(-1e-9, 1e-9), st.sampled_from([-1.0, 1.0]))
def test_pitch_at_the_singularity_is_refused_and_changes_nothing(
    kind: str, args: dict[str, np.ndarray], offset: float, sign: float
) -> None:
    c = make(kind)
    c.step(**args)
    before = state(c)
    eta = args["eta"].copy()
    eta[4] = sign * np.pi / 2 + offset
    with pytest.raises(ValueError, match="singularity"):
        c.step(**{**args, "eta": eta})
    assert same(state(c), before)


@SETTINGS
@given(st.sampled_from(KINDS), step_args(), finite(1e-7, 0.05), st.sampled_from([-1.0, 1.0]))
def test_pitch_near_the_singularity_gives_a_finite_tau(
    kind: str, args: dict[str, np.ndarray], gap: float, sign: float
) -> None:
    # Outside the band (|cos| >= 1.5e-8) the step is taken: 1/cos up to 1e7
    # makes tau large, never non-finite.
    c = make(kind)
    eta = args["eta"].copy()
    eta[4] = sign * (np.pi / 2 - gap)
    tau = c.step(**{**args, "eta": eta})
    assert np.all(np.isfinite(tau))
    assert all(np.all(np.isfinite(x)) for x in state(c))


@st.composite
def awkward_layouts(draw: st.DrawFn, good: np.ndarray) -> np.ndarray:
    """The same numbers as `good`, in a layout numpy code produces: strided,
    reversed, read-only, big-endian, float32-exact, integer-valued lists."""
    form = draw(st.sampled_from(["strided", "reversed", "readonly", "big-endian", "list", "tuple"]))
    if form == "strided":
        buf = np.zeros(2 * good.size)
        buf[::2] = good
        return buf[::2]
    if form == "reversed":
        return good[::-1].copy()[::-1]
    if form == "readonly":
        out = good.copy()
        out.flags.writeable = False
        return out
    if form == "big-endian":
        return good.astype(">f8")
    return list(good) if form == "list" else tuple(good)  # type: ignore[return-value]


@FEW
@given(st.sampled_from(KINDS), step_args(), st.sampled_from(ARGS), st.data())
def test_any_array_layout_gives_the_same_step(kind: str, args: dict[str, np.ndarray], arg: str,
                                                data: st.DataObject) -> None:
    a, b = make(kind), make(kind)
    other = data.draw(awkward_layouts(args[arg]))
    kept = np.array(other, copy=True)
    np.testing.assert_array_equal(a.step(**args), b.step(**{**args, arg: other}))
    assert same(state(a), state(b))
    np.testing.assert_array_equal(np.asarray(other), kept)  # the input was not written


@FEW
@given(st.sampled_from(ARGS), st.lists(st.integers(0, 7), min_size=0, max_size=3).filter(lambda s: s != [6]),
       st.sampled_from(KINDS))
def test_wrong_shape_names_the_argument_and_the_shape(arg: str, shape: list[int], kind: str) -> None:
    c = make(kind)
    with pytest.raises(ValueError) as err:
        c.step(**{**{k: np.zeros(6) for k in ARGS}, arg: np.zeros(shape)})
    assert f"'{arg}'" in str(err.value) and "(6,)" in str(err.value)


@FEW
@given(st.sampled_from(ARGS), st.sampled_from(["U3", "c16", "O", "?", "M8[s]"]))
def test_wrong_dtype_names_the_argument(arg: str, dtype: str) -> None:
    c = make("pd")
    bad = np.zeros(6, dtype=dtype) if dtype != "U3" else np.full(6, "1.0")
    with pytest.raises(TypeError, match=f"'{arg}'"):
        c.step(**{**{k: np.zeros(6) for k in ARGS}, arg: bad})


@SETTINGS
@given(vectors(6, 0.1, 3.0), vectors(6, 0.05, 1.0), st.integers(0, 5),
       st.sampled_from([np.nan, np.inf, -np.inf, 1e308]), st.sampled_from(["r", "dt"]))
def test_reference_model_refusal_changes_nothing(lambda_d: np.ndarray, omega: np.ndarray, index: int,
                                                 bad: float, what: str) -> None:
    m = neurov.ReferenceModel(lambda_d, omega)
    r = np.array([5.0, -2.0, 1.0, 0.1, 0.1, 1.0])
    for _ in range(3):
        m.step(r, 0.2)
    before = (m.eta_d.copy(), m.nu_d.copy())
    try:
        if what == "r":
            cmd = r.copy()
            cmd[index] = bad
            out = m.step(cmd, 0.2)
        else:
            out = m.step(r, bad)
    except ValueError as e:
        assert f"'{what}'" in str(e) or "refused" in str(e), str(e)
        assert m.eta_d.tobytes() == before[0].tobytes() and m.nu_d.tobytes() == before[1].tobytes()
    else:
        assert all(np.all(np.isfinite(x)) for x in out)


class RefusedCallsLoseNothing(RuleBasedStateMachine):
    """A controller that now and then gets a bad call, against a twin that
    only ever sees the good ones: after any sequence they agree bit for bit."""

    @initialize(kind=st.sampled_from(KINDS))
    def start(self, kind: str) -> None:
        self.ctl, self.twin = make(kind), make(kind)

    @rule(args=step_args())
    def good_step(self, args: dict[str, np.ndarray]) -> None:
        t1, t2 = self.ctl.step(**args), self.twin.step(**args)
        assert t1.tobytes() == t2.tobytes()

    @rule(args=step_args(), arg=st.sampled_from(ARGS), index=st.integers(0, 5),
          bad=st.sampled_from([np.nan, np.inf, -np.inf]))
    def bad_step(self, args: dict[str, np.ndarray], arg: str, index: int, bad: float) -> None:
        args[arg][index] = bad
        with pytest.raises(ValueError):
            self.ctl.step(**args)

    @rule(args=step_args())
    def singular_step(self, args: dict[str, np.ndarray]) -> None:
        args["eta"][4] = np.pi / 2
        with pytest.raises(ValueError):
            self.ctl.step(**args)

    @invariant()
    def same_state(self) -> None:
        if hasattr(self, "ctl"):
            assert same(state(self.ctl), state(self.twin))


TestRefusedCallsLoseNothing = RefusedCallsLoseNothing.TestCase
TestRefusedCallsLoseNothing.settings = settings(
    max_examples=25, stateful_step_count=20, deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.large_base_example])


# ------------------------------------------------- allocation-free closed loop

# A malloc interposer loaded with LD_PRELOAD into a child Python: it counts
# every malloc/calloc/realloc/aligned allocation of the process. The whole
# closed loop runs in C++ inside one run_closed_loop call; two runs that differ
# only in their number of steps must make the same number of allocations (the
# result is sized once, up front), so any allocation per control step shows up
# as a difference proportional to the extra steps.
_COUNTER_C = r"""
#include <stddef.h>
extern void* __libc_malloc(size_t);
extern void* __libc_calloc(size_t, size_t);
extern void* __libc_realloc(void*, size_t);
extern void* __libc_memalign(size_t, size_t);
static long counter;
long neurov_alloc_count(void) { return __atomic_load_n(&counter, __ATOMIC_RELAXED); }
static void bump(void) { __atomic_fetch_add(&counter, 1, __ATOMIC_RELAXED); }
void* malloc(size_t n) { bump(); return __libc_malloc(n); }
void* calloc(size_t a, size_t b) { bump(); return __libc_calloc(a, b); }
void* realloc(void* p, size_t n) { bump(); return __libc_realloc(p, n); }
void* memalign(size_t a, size_t n) { bump(); return __libc_memalign(a, n); }
void* aligned_alloc(size_t a, size_t n) { bump(); return __libc_memalign(a, n); }
int posix_memalign(void** p, size_t a, size_t n) {
  bump();
  *p = __libc_memalign(a, n);
  return *p ? 0 : 12;
}
"""

_CHILD = textwrap.dedent(
    """
    import ctypes, json, sys
    import numpy as np
    import neurov
    from neurov.laws.registry import build_controller
    from neurov.running.plant import build_vehicle, simulation_config

    count = ctypes.CDLL(None).neurov_alloc_count
    count.restype = ctypes.c_long
    out = []
    for case in json.load(sys.stdin):
        s = neurov.load_scenario(case["scenario"])
        s = s.replace(
            noise_eta=np.full(6, case["noise"]), noise_nu=np.full(6, case["noise"]), seed=case["seed"],
            sensor_faults=[neurov.SensorFault(**{**f, "kind": neurov.SensorFaultKind.__members__[f["kind"]]})
                           for f in case["faults"]],
            refused_step_policy=case["policy"])
        s.controller = s.controller.replace(type=case["controller"])
        if hasattr(s.controller.config, "kp"):
            s.controller.kp = np.full(6, 100.0)
        vehicle = build_vehicle(s)
        def run(duration):
            c = build_controller(s.controller, s)
            config = simulation_config(s)
            config.duration = duration
            before = count()
            r = neurov.run_closed_loop(vehicle, c, config)
            used = count() - before
            return used, int(np.count_nonzero(r["controller_status"]))
        run(case["short"])  # warm caches (pymalloc arenas, lazily built tables)
        short = min(run(case["short"])[0] for _ in range(3))
        long, refused = min(run(case["long"]) for _ in range(3))
        out.append({"short": short, "long": long, "refused": refused})
    json.dump(out, sys.stdout)
    """
)


@st.composite
def loop_cases(draw: st.DrawFn) -> dict[str, Any]:
    faults = []
    if draw(st.booleans()):
        start = draw(finite(1.0, 20.0))
        faults.append({"kind": draw(st.sampled_from(["freeze", "dropout", "noise_burst"])), "start": start,
                       "end": start + draw(finite(0.5, 10.0)), "eta": True, "nu": draw(st.booleans()),
                       "noise_eta": [0.1] * 6, "noise_nu": [0.1] * 6})
    return {
        "scenario": str(Path(__file__).resolve().parents[2] / "examples" / "scenarios" / "faults"
                        / draw(st.sampled_from(["thruster_failure.toml", "current_step.toml"]))),
        "controller": draw(st.sampled_from(["nn", "linear", "pd", "pid", "smc"])),
        "noise": draw(st.sampled_from([0.0, 0.01])),
        "seed": draw(st.integers(0, 2**31)),
        "faults": faults,
        "policy": draw(st.sampled_from(["zero", "hold"])),
        "short": 30.0,
        "long": 90.0,
    }


@pytest.fixture(scope="module")
def alloc_counter(tmp_path_factory: pytest.TempPathFactory) -> Path:
    cc = shutil.which("cc") or shutil.which("gcc") or shutil.which("clang")
    if cc is None or not sys.platform.startswith("linux"):
        pytest.skip("needs a C compiler and glibc to build the malloc counter")
    d = tmp_path_factory.mktemp("alloc")
    (d / "count.c").write_text(_COUNTER_C)
    subprocess.run([cc, "-shared", "-fPIC", "-O2", "-o", str(d / "libcount.so"), str(d / "count.c")],
                   check=True)
    return d / "libcount.so"


# No shrinking: each example is a child process, and the case list printed on
# failure already names the offending configuration.
@settings(max_examples=2, deadline=None, phases=[Phase.explicit, Phase.reuse, Phase.generate])
@given(st.lists(loop_cases(), min_size=6, max_size=6))
def test_closed_loop_allocates_nothing_per_control_step(alloc_counter: Path, cases: list[dict[str, Any]]) -> None:
    env = {**os.environ, "LD_PRELOAD": str(alloc_counter)}
    done = subprocess.run([sys.executable, "-c", _CHILD], input=json.dumps(cases), env=env,
                          capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    for case, got in zip(cases, json.loads(done.stdout)):
        # 300 more control steps (3000 RK4 substeps); the counter must not notice.
        assert got["long"] - got["short"] <= 2, (case, got)
        assert got["short"] > 0  # the counter counts (the result arrays are allocated)
