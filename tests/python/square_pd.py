"""The paper's square path flown by NEROV with a PD controller, as scenario
file text: the short runs the run-folder and run-evidence tests write."""

from __future__ import annotations


def square_pd_scenario(name: str, duration: float, *, substeps: int | None = None, gain: str | None = None) -> str:
    """A 2 m square from t = 1 s at 5 Hz; `gain`: K_p = K_d = that number
    on every DOF (the preset's gains without it); `substeps`: plant steps
    per control period."""
    steps = f"substeps = {substeps}\n" if substeps is not None else ""
    gains = f"kp = [{', '.join([gain] * 6)}]\nkd = [{', '.join([gain] * 6)}]\n" if gain is not None else ""
    return f"""
name = "{name}"
duration = {duration}
dt = 0.2
{steps}
[vehicle]
preset = "nerov"

[command]
type = "square"
side = 2.0
start = 1.0

[controller]
type = "pd"
{gains}"""
