"""Study files shared by the study tests: two short scenarios (a BlueROV2
heading step and a NEROV depth step, 30 s each) and a small study over them,
so a whole study runs in seconds."""

from __future__ import annotations

from pathlib import Path

import pytest

NOISE = "[noise]\neta = [0.01, 0.01, 0.01, 0.002, 0.002, 0.005]\n"


def step_scenario(name: str, preset: str, start: list[float], target: list[float], *,
                  kp: float, kd: float, duration: float = 30.0, thrusters: bool = False,
                  extra: str = "") -> str:
    """A scenario file: a PD controller holding `start`, then `target` from
    t = 2 s, with `extra` tables after."""
    return f"""
name = "{name}"
duration = {duration}
[vehicle]
preset = "{preset}"
thrusters = {str(thrusters).lower()}
[command]
type = "waypoints"
interpolation = "hold"
times = [0.0, 2.0]
poses = [{start}, {target}]
[controller]
type = "pd"
kp = {kp}
kd = {kd}
{extra}"""


# A short BlueROV2 heading step next to a shipped scenario trimmed to 30 s,
# so the whole file runs in seconds.
SHORT_BLUEROV = step_scenario(
    "short_bluerov", "bluerov2_heavy", [0, 0, 1, 0, 0, 0], [1, 0, 1, 0, 0, 0.5], kp=10.0, kd=10.0,
    extra="[current]\nvelocity = [0.2, 0.0, 0.0]\n" + NOISE)

SHORT_NEROV = step_scenario(
    "short_nerov", "nerov", [0, 0, 0, 0, 0, 0], [0, 0, 2, 0, 0, 0.5], kp=50.0, kd=200.0,
    thrusters=True,
    extra="[[disturbances]]\ndof = \"yaw\"\namplitude = 10.0\nfrequency = 0.05\n")

STUDY = """
name = "small"
description = "2 scenarios x 3 controllers x 4 samples"
seed = 7
samples = 4
after = 5.0
scenarios = ["short_nerov.toml", "short_bluerov.toml"]
head_to_head = [["nn", "linear"]]

[ranking]
metric = "rmse_position_m"

[failure]
rmse_position_m = 0.5

[controllers.pd]
type = "pd"
label = "PD"
[controllers.pd.nerov]
kp = [100, 100, 100, 50, 50, 50]
kd = [200, 200, 200, 50, 50, 50]
[controllers.pd.bluerov2_heavy]
kp = [20, 20, 20, 2, 2, 2]
kd = [25, 25, 40, 1, 1, 1]

[controllers.linear]
type = "linear"
theta0 = "true"
label = "linear adaptive"
[controllers.linear.nerov]
kd = [200, 200, 200, 50, 50, 50]
[controllers.linear.bluerov2_heavy]
kd = [25, 25, 40, 1, 1, 1]
gamma = 0.1

[controllers.nn]
type = "nn"
label = "NN adaptive"
[controllers.nn.centres]
method = "sobol"
n = 16
seed = 1
[controllers.nn.nerov]
kd = [200, 200, 200, 50, 50, 50]
[controllers.nn.bluerov2_heavy]
kd = [25, 25, 40, 1, 1, 1]
gamma = 0.03

[[perturbations]]
parameter = "mass"
relative = 0.3

[[perturbations]]
parameter = "added_mass"
relative = 0.2
distribution = "normal"

[[perturbations]]
parameter = "linear_damping"
relative = 0.3
per_element = false

[[perturbations]]
parameter = "current_speed"
range = [0.0, 0.5]

[[perturbations]]
parameter = "current_direction"
range = [0.0, 360.0]

[[perturbations]]
parameter = "noise_scale"
range = [0.5, 2.0]
"""


def write_study(folder: Path, text: str = STUDY, name: str = "small.toml") -> Path:
    (folder / "short_nerov.toml").write_text(SHORT_NEROV)
    (folder / "short_bluerov.toml").write_text(SHORT_BLUEROV)
    path = folder / name
    path.write_text(text)
    return path


@pytest.fixture
def study_file(tmp_path: Path) -> Path:
    return write_study(tmp_path)


def study_with(change: str) -> str:
    """The small study with one top-level key or table replaced by `change`."""
    base = [
        'name = "small"', "seed = 1", "samples = 2",
        'scenarios = ["short_nerov.toml", "short_bluerov.toml"]',
        "[controllers.pd]", 'type = "pd"', "kp = 1.0", "kd = 1.0",
    ]
    head, _, _ = change.partition("\n")
    key = head.split("=")[0].strip()
    if key.startswith("[controllers"):
        base = base[:4] + [change]
    elif "=" in head and not head.startswith("["):
        base = [line for line in base if not line.startswith(key + " ")]
        base.insert(0, change)
    else:
        base.append(change)
    return "\n".join(base) + "\n"


def pd_study(name: str, seed: int, samples: int, after: float) -> str:
    """The head of the user-controller studies: scenarios a.toml and b.toml
    (beside the study file) and a PD controller; the tests add theirs."""
    return f"""
name = "{name}"
seed = {seed}
samples = {samples}
after = {after}
scenarios = ["a.toml", "b.toml"]

[controllers.pd]
type = "pd"
kp = [200, 200, 200, 50, 50, 50]
kd = [200, 200, 200, 50, 50, 50]
"""


#: The mass perturbation both user-controller studies draw.
MASS_PERTURBATION = """
[[perturbations]]
parameter = "mass"
relative = 0.2
"""
